#include "ppp_bayes_tree/io/rtcm/rtcm3_msm_encoder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kRangeMs_m = kSpeedOfLight_mps * 0.001;

}  // namespace

unsigned msmLockIndicatorDf407(std::uint32_t lock_ms) {
  if (lock_ms < 64) return lock_ms;
  unsigned n = 1;
  while (n < 21 && lock_ms >= (32u << (n + 1))) ++n;
  const unsigned i = lock_ms / (1u << n) + 32 * n;
  return std::min(i, 704u);
}

std::vector<std::vector<std::uint8_t>> encodeMsm7(const StreamEpoch& epoch, GnssSystem system,
                                                  const MsmEncodeOptions& options) {
  std::vector<const StreamSatellite*> sats;
  for (const auto& s : epoch.satellites)
    if (s.satellite.system == system && msmSatelliteId(s.satellite) >= 1 && msmSatelliteId(s.satellite) <= 64)
      sats.push_back(&s);
  std::sort(sats.begin(), sats.end(), [](const StreamSatellite* a, const StreamSatellite* b) {
    return msmSatelliteId(a->satellite) < msmSatelliteId(b->satellite);
  });
  std::vector<std::vector<std::uint8_t>> out;
  const int type = msmMessageType(system, 7).value_or(0);
  if (sats.empty() || type == 0) return out;

  // Split the satellites into groups whose cells fit 64.
  std::vector<std::vector<const StreamSatellite*>> groups(1);
  std::set<int> group_sigs;
  for (const auto* s : sats) {
    std::set<int> sigs = group_sigs;
    for (const auto& sig : s->signals)
      if (const auto id = msmSignalId(system, sig.band, sig.attribute)) sigs.insert(*id);
    if (!groups.back().empty() && (groups.back().size() + 1) * sigs.size() > 64) {
      groups.emplace_back();
      sigs.clear();
      for (const auto& sig : s->signals)
        if (const auto id = msmSignalId(system, sig.band, sig.attribute)) sigs.insert(*id);
    }
    groups.back().push_back(s);
    group_sigs = sigs;
  }

  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto& group = groups[g];
    std::set<int> sig_set;
    for (const auto* s : group)
      for (const auto& sig : s->signals)
        if (const auto id = msmSignalId(system, sig.band, sig.attribute)) sig_set.insert(*id);
    const std::vector<int> sigs(sig_set.begin(), sig_set.end());
    const bool multiple = g + 1 < groups.size() || options.more_messages_follow;

    BitWriter w;
    w.putUnsigned(static_cast<std::uint64_t>(type), 12);
    w.putUnsigned(static_cast<std::uint64_t>(options.station_id), 12);
    if (system == GnssSystem::GLONASS) {
      const GnssTime glo = epoch.time + epoch.time.offsetToSystem_s(TimeSystem::GLONASS);
      const std::int64_t ms = static_cast<std::int64_t>(std::llround(glo.toGpsSecondsDouble() * 1000.0));
      const std::int64_t day_ms = 86400000LL;
      const std::int64_t tod = ((ms % day_ms) + day_ms) % day_ms;
      const std::int64_t days = (ms - tod) / day_ms;  // days since 1980-01-06 (a Sunday)
      w.putUnsigned(static_cast<std::uint64_t>(((days % 7) + 7) % 7), 3);
      w.putUnsigned(static_cast<std::uint64_t>(tod), 27);
    } else {
      const double sow = (system == GnssSystem::BeiDou ? toBdtWeek(epoch.time) : epoch.time.gpsWeek()).seconds_of_week;
      w.putUnsigned(static_cast<std::uint64_t>(std::llround(sow * 1000.0)) % 604800000ULL, 30);
    }
    w.putFlag(multiple);
    w.putUnsigned(0, 3 + 7 + 2 + 2 + 1 + 3);
    std::uint64_t sat_mask = 0;
    for (const auto* s : group) sat_mask |= 1ULL << (64 - msmSatelliteId(s->satellite));
    w.putUnsigned(sat_mask, 64);
    std::uint32_t sig_mask = 0;
    for (int id : sigs) sig_mask |= 1u << (32 - id);
    w.putUnsigned(sig_mask, 32);

    // Cells and per-satellite rough values.
    struct Cell {
      const StreamSignal* signal;
      std::optional<double> wavelength_m;
    };
    std::vector<Cell> cells;
    std::vector<std::optional<double>> rough_m(group.size()), rough_rate(group.size());
    std::vector<int> ext(group.size(), 0);
    for (std::size_t i = 0; i < group.size(); ++i) {
      const auto* s = group[i];
      double min_pr = 1e300, max_pr = -1e300;
      std::optional<int> channel;
      if (system == GnssSystem::GLONASS) {
        channel = options.glonass_channels.channel(s->satellite.prn);
        ext[i] = channel && *channel <= 6 ? *channel + 7 : 15;  // DF419: 0..13 = channel -7..+6
      }
      for (int id : sigs) {
        const StreamSignal* found = nullptr;
        for (const auto& sig : s->signals)
          if (msmSignalId(system, sig.band, sig.attribute) == id) found = &sig;
        w.putFlag(found != nullptr);
        if (!found) continue;
        cells.push_back(Cell{found, carrierWavelength_m(system, found->band, channel)});
        if (found->pseudorange_m) {
          min_pr = std::min(min_pr, *found->pseudorange_m);
          max_pr = std::max(max_pr, *found->pseudorange_m);
        }
        if (!rough_rate[i] && found->doppler_hz && cells.back().wavelength_m) {
          const double rate = std::round(-*found->doppler_hz * *cells.back().wavelength_m);
          if (std::fabs(rate) < 8191.0) rough_rate[i] = rate;
        }
      }
      // Rough range: the middle of the satellite's pseudoranges on the 2^-10 ms grid,
      // so that every signal's fine value (+-2^-10 ms) fits.
      if (min_pr <= max_pr) {
        const double units = std::round(0.5 * (min_pr + max_pr) / kRangeMs_m * 1024.0);
        if (units >= 0 && units < 255.0 * 1024.0) rough_m[i] = units / 1024.0 * kRangeMs_m;
      }
    }
    // Satellite data.
    for (std::size_t i = 0; i < group.size(); ++i) {
      const double units = rough_m[i] ? std::round(*rough_m[i] / kRangeMs_m * 1024.0) : 0.0;
      w.putUnsigned(rough_m[i] ? static_cast<std::uint64_t>(units) / 1024 : 255, 8);
    }
    for (std::size_t i = 0; i < group.size(); ++i) w.putUnsigned(static_cast<std::uint64_t>(ext[i]), 4);
    for (std::size_t i = 0; i < group.size(); ++i) {
      const double units = rough_m[i] ? std::round(*rough_m[i] / kRangeMs_m * 1024.0) : 0.0;
      w.putUnsigned(rough_m[i] ? static_cast<std::uint64_t>(units) % 1024 : 0, 10);
    }
    for (std::size_t i = 0; i < group.size(); ++i)
      w.putSigned(rough_rate[i] ? static_cast<std::int64_t>(*rough_rate[i]) : -8192, 14);
    // Signal data, in cell order (satellite-major).
    std::vector<std::size_t> cell_sat;
    {
      std::size_t c = 0;
      for (std::size_t i = 0; i < group.size(); ++i) {
        for (int id : sigs) {
          for (const auto& sig : group[i]->signals)
            if (msmSignalId(system, sig.band, sig.attribute) == id) {
              cell_sat.push_back(i);
              ++c;
              break;
            }
        }
      }
      (void)c;
    }
    auto fine = [&](std::optional<double> value_m, std::size_t i, double unit_ms, int bits) -> std::int64_t {
      const std::int64_t invalid = -(1LL << (bits - 1));
      if (!value_m || !rough_m[i]) return invalid;
      const double v = std::round((*value_m - *rough_m[i]) / kRangeMs_m / unit_ms);
      if (v <= static_cast<double>(invalid) || v >= static_cast<double>(-invalid)) return invalid;
      return static_cast<std::int64_t>(v);
    };
    for (std::size_t c = 0; c < cells.size(); ++c)
      w.putSigned(fine(cells[c].signal->pseudorange_m, cell_sat[c], std::ldexp(1.0, -29), 20), 20);
    for (std::size_t c = 0; c < cells.size(); ++c) {
      std::optional<double> phase_m;
      if (cells[c].signal->carrier_phase_cycles && cells[c].wavelength_m)
        phase_m = *cells[c].signal->carrier_phase_cycles * *cells[c].wavelength_m;
      w.putSigned(fine(phase_m, cell_sat[c], std::ldexp(1.0, -31), 24), 24);
    }
    for (std::size_t c = 0; c < cells.size(); ++c)
      w.putUnsigned(msmLockIndicatorDf407(static_cast<std::uint32_t>(
                        std::min(cells[c].signal->lock_time_s * 1000.0 + 1e-6, 67108864.0))),
                    10);
    for (std::size_t c = 0; c < cells.size(); ++c) w.putFlag((cells[c].signal->lli & 2) != 0);
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const double cnr = cells[c].signal->cnr_dbhz.value_or(0.0);
      w.putUnsigned(static_cast<std::uint64_t>(std::clamp(std::round(cnr * 16.0), 0.0, 1023.0)), 10);
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
      std::int64_t v = -16384;
      const std::size_t i = cell_sat[c];
      if (cells[c].signal->doppler_hz && cells[c].wavelength_m && rough_rate[i]) {
        const double rate = -*cells[c].signal->doppler_hz * *cells[c].wavelength_m;
        const double f = std::round((rate - *rough_rate[i]) / 0.0001);
        if (std::fabs(f) < 16383.0) v = static_cast<std::int64_t>(f);
      }
      w.putSigned(v, 15);
    }
    out.push_back(w.bytes());
  }
  return out;
}

}  // namespace ppp
