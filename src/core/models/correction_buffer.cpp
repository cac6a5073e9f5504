#include "ppp_bayes_tree/models/correction_buffer.h"

#include <algorithm>
#include <cmath>

namespace ppp {

CorrectionBuffer::CorrectionBuffer(CorrectionBufferOptions options)
    : options_(options), ephemeris_(options.interpolation) {}

std::optional<GnssTime> CorrectionBuffer::newest() const {
  return batches_.empty() ? std::nullopt : std::optional<GnssTime>(batches_.back().time);
}

std::optional<GnssTime> CorrectionBuffer::oldest() const {
  return batches_.empty() ? std::nullopt : std::optional<GnssTime>(batches_.front().time);
}

void CorrectionBuffer::clear() {
  batches_.clear();
  rebuild();
}

BatchAddResult CorrectionBuffer::add(CorrectionBatch batch) {
  if (!std::isfinite(batch.time.fraction()) || batch.time.wholeSeconds() <= 0) return BatchAddResult::InvalidTime;
  const auto by_time = [](const CorrectionBatch& a, const GnssTime& t) { return a.time < t; };
  const auto it = std::lower_bound(batches_.begin(), batches_.end(), batch.time, by_time);
  if (it != batches_.end() && it->time == batch.time) return BatchAddResult::Duplicate;
  // An infinite history keeps every batch (no time is "newest minus infinity").
  const bool bounded = std::isfinite(options_.history_s);
  if (bounded && !batches_.empty() && batch.time < batches_.back().time - options_.history_s)
    return BatchAddResult::TooOld;
  batches_.insert(it, std::move(batch));
  if (bounded) {
    const GnssTime limit = batches_.back().time - options_.history_s;
    const auto keep = std::lower_bound(batches_.begin(), batches_.end(), limit, by_time);
    batches_.erase(batches_.begin(), keep);
  }
  rebuild();
  return BatchAddResult::Added;
}

void CorrectionBuffer::rebuild() {
  // The batches as one SP3 file (orbits, velocities) and one clock file, so
  // that PreciseEphemeris applies its rules unchanged.
  Sp3File sp3;
  RinexClockFile clk;
  sp3.header.pv_flag = 'V';
  double min_spacing = 0.0;
  for (std::size_t i = 0; i < batches_.size(); ++i) {
    const CorrectionBatch& b = batches_[i];
    if (i > 0) {
      const double dt = b.time - batches_[i - 1].time;
      if (dt > 0.0 && (min_spacing <= 0.0 || dt < min_spacing)) min_spacing = dt;
    }
    sp3.epochs.push_back(b.time);
    for (const SatelliteCorrection& s : b.satellites) {
      if (s.position_ecef_m) {
        Sp3Record r;
        r.time = b.time;
        r.position_ecef_m = s.position_ecef_m;
        r.velocity_ecef_mps = s.velocity_ecef_mps;
        auto& series = sp3.satellites[s.satellite];
        if (series.empty() || series.back().time < b.time) series.push_back(r);
      }
      if (s.clock_bias_s) {
        ClockRecord c;
        c.time = b.time;
        c.clock_bias_s = *s.clock_bias_s;
        c.clock_rate_s_per_s = s.clock_drift_s_per_s;
        auto& series = clk.satellite_clocks[s.satellite];
        if (series.empty() || series.back().time < b.time) series.push_back(c);
      }
    }
  }
  // One batch alone: its own epoch is usable (exact hits); spacing limit from the options.
  sp3.header.interval_s = min_spacing > 0.0 ? min_spacing : 30.0;
  ephemeris_ = PreciseEphemeris(options_.interpolation);
  ephemeris_.addOrbits(sp3);
  if (!clk.satellite_clocks.empty()) ephemeris_.addClocks(clk);
}

}  // namespace ppp
