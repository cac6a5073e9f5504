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

using MsmSatellites = std::vector<const StreamSatellite*>;

// One cell of an MSM: a satellite's signal and its carrier wavelength.
struct MsmCell {
  const StreamSignal* signal;
  std::optional<double> wavelength_m;
};

// The cells of one MSM (satellite-major) and the per-satellite rough values.
struct MsmGroupCells {
  std::vector<MsmCell> cells;
  std::vector<std::size_t> cell_satellite;                // index in the group of each cell's satellite
  std::vector<std::optional<double>> rough_range_m;       // DF397/DF398 range, absent when not encodable
  std::vector<std::optional<double>> rough_rate_mps;      // DF399 rate, absent when not encodable
  std::vector<int> extended_info;                         // DF419 (GLONASS channel) or 0
};

// Adds the MSM signal ids of a satellite's signals to `ids`.
void insertMsmSignalIds(GnssSystem system, const StreamSatellite& satellite, std::set<int>& ids) {
  for (const auto& sig : satellite.signals)
    if (const auto id = msmSignalId(system, sig.band, sig.attribute)) ids.insert(*id);
}

// The epoch's satellites of `system` with an MSM satellite id 1..64, by id.
MsmSatellites selectMsmSatellites(const StreamEpoch& epoch, GnssSystem system) {
  MsmSatellites sats;
  for (const auto& s : epoch.satellites)
    if (s.satellite.system == system && msmSatelliteId(s.satellite) >= 1 && msmSatelliteId(s.satellite) <= 64)
      sats.push_back(&s);
  std::sort(sats.begin(), sats.end(), [](const StreamSatellite* a, const StreamSatellite* b) {
    return msmSatelliteId(a->satellite) < msmSatelliteId(b->satellite);
  });
  return sats;
}

// The satellites split into groups whose cells (satellites x signals) fit 64.
std::vector<MsmSatellites> groupSatellitesIn64Cells(const MsmSatellites& sats, GnssSystem system) {
  std::vector<MsmSatellites> groups(1);
  std::set<int> group_sigs;
  for (const auto* s : sats) {
    std::set<int> sigs = group_sigs;
    insertMsmSignalIds(system, *s, sigs);
    if (!groups.back().empty() && (groups.back().size() + 1) * sigs.size() > 64) {
      groups.emplace_back();
      sigs.clear();
      insertMsmSignalIds(system, *s, sigs);
    }
    groups.back().push_back(s);
    group_sigs = sigs;
  }
  return groups;
}

// The MSM signal ids of a group's satellites, ascending.
std::vector<int> groupSignalIds(const MsmSatellites& group, GnssSystem system) {
  std::set<int> sig_set;
  for (const auto* s : group) insertMsmSignalIds(system, *s, sig_set);
  return std::vector<int>(sig_set.begin(), sig_set.end());
}

// The epoch time field: GLONASS day of week and time of day [ms], else time of week [ms].
void putMsmEpochTime_ms(BitWriter& w, GnssSystem system, const GnssTime& time) {
  if (system == GnssSystem::GLONASS) {
    const GnssTime glo = time + time.offsetToSystem_s(TimeSystem::GLONASS);
    const std::int64_t ms = static_cast<std::int64_t>(std::llround(glo.toGpsSecondsDouble() * 1000.0));
    const std::int64_t day_ms = 86400000LL;
    const std::int64_t tod = ((ms % day_ms) + day_ms) % day_ms;
    const std::int64_t days = (ms - tod) / day_ms;  // days since 1980-01-06 (a Sunday)
    w.putUnsigned(static_cast<std::uint64_t>(((days % 7) + 7) % 7), 3);
    w.putUnsigned(static_cast<std::uint64_t>(tod), 27);
  } else {
    const double sow = (system == GnssSystem::BeiDou ? toBdtWeek(time) : time.gpsWeek()).seconds_of_week;
    w.putUnsigned(static_cast<std::uint64_t>(std::llround(sow * 1000.0)) % 604800000ULL, 30);
  }
}

// The MSM header up to the signal mask (the cell mask follows with the cells).
void putMsmHeader(BitWriter& w, int type, const StreamEpoch& epoch, GnssSystem system,
                  const MsmEncodeOptions& options, bool multiple, const MsmSatellites& group,
                  const std::vector<int>& sigs) {
  w.putUnsigned(static_cast<std::uint64_t>(type), 12);
  w.putUnsigned(static_cast<std::uint64_t>(options.station_id), 12);
  putMsmEpochTime_ms(w, system, epoch.time);
  w.putFlag(multiple);
  w.putUnsigned(0, 3 + 7 + 2 + 2 + 1 + 3);
  std::uint64_t sat_mask = 0;
  for (const auto* s : group) sat_mask |= 1ULL << (64 - msmSatelliteId(s->satellite));
  w.putUnsigned(sat_mask, 64);
  std::uint32_t sig_mask = 0;
  for (int id : sigs) sig_mask |= 1u << (32 - id);
  w.putUnsigned(sig_mask, 32);
}

// Rough range [m]: the middle of the satellite's pseudoranges on the 2^-10 ms grid, so that every
// signal's fine value (+-2^-10 ms) fits; absent without pseudoranges or outside 0..255 ms.
std::optional<double> roughRange_m(double min_pr_m, double max_pr_m) {
  if (min_pr_m > max_pr_m) return std::nullopt;
  const double units = std::round(0.5 * (min_pr_m + max_pr_m) / kRangeMs_m * 1024.0);
  if (units >= 0 && units < 255.0 * 1024.0) return units / 1024.0 * kRangeMs_m;
  return std::nullopt;
}

// The cell mask of one satellite written, its cells appended and its rough values set.
void addSatelliteCells(BitWriter& w, const StreamSatellite& s, std::size_t i, const std::vector<int>& sigs,
                       GnssSystem system, const MsmEncodeOptions& options, MsmGroupCells& out) {
  double min_pr = 1e300, max_pr = -1e300;
  std::optional<int> channel;
  if (system == GnssSystem::GLONASS) {
    channel = options.glonass_channels.channel(s.satellite.prn);
    out.extended_info[i] = channel && *channel <= 6 ? *channel + 7 : 15;  // DF419: 0..13 = channel -7..+6
  }
  for (int id : sigs) {
    const StreamSignal* found = nullptr;
    for (const auto& sig : s.signals)
      if (msmSignalId(system, sig.band, sig.attribute) == id) found = &sig;
    w.putFlag(found != nullptr);
    if (!found) continue;
    out.cells.push_back(MsmCell{found, carrierWavelength_m(system, found->band, channel)});
    out.cell_satellite.push_back(i);
    if (found->pseudorange_m) {
      min_pr = std::min(min_pr, *found->pseudorange_m);
      max_pr = std::max(max_pr, *found->pseudorange_m);
    }
    if (!out.rough_rate_mps[i] && found->doppler_hz && out.cells.back().wavelength_m) {
      const double rate = std::round(-*found->doppler_hz * *out.cells.back().wavelength_m);
      if (std::fabs(rate) < 8191.0) out.rough_rate_mps[i] = rate;
    }
  }
  out.rough_range_m[i] = roughRange_m(min_pr, max_pr);
}

// The cell mask written and the group's cells and rough values, satellite-major.
MsmGroupCells putCellMask(BitWriter& w, const MsmSatellites& group, const std::vector<int>& sigs,
                          GnssSystem system, const MsmEncodeOptions& options) {
  MsmGroupCells out;
  out.rough_range_m.resize(group.size());
  out.rough_rate_mps.resize(group.size());
  out.extended_info.assign(group.size(), 0);
  for (std::size_t i = 0; i < group.size(); ++i) addSatelliteCells(w, *group[i], i, sigs, system, options, out);
  return out;
}

// Satellite data: rough range integer ms and modulo 1 ms, extended info, rough rate [m/s].
void putSatelliteData(BitWriter& w, const MsmGroupCells& g) {
  const std::size_t n = g.rough_range_m.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double units = g.rough_range_m[i] ? std::round(*g.rough_range_m[i] / kRangeMs_m * 1024.0) : 0.0;
    w.putUnsigned(g.rough_range_m[i] ? static_cast<std::uint64_t>(units) / 1024 : 255, 8);
  }
  for (std::size_t i = 0; i < n; ++i) w.putUnsigned(static_cast<std::uint64_t>(g.extended_info[i]), 4);
  for (std::size_t i = 0; i < n; ++i) {
    const double units = g.rough_range_m[i] ? std::round(*g.rough_range_m[i] / kRangeMs_m * 1024.0) : 0.0;
    w.putUnsigned(g.rough_range_m[i] ? static_cast<std::uint64_t>(units) % 1024 : 0, 10);
  }
  for (std::size_t i = 0; i < n; ++i)
    w.putSigned(g.rough_rate_mps[i] ? static_cast<std::int64_t>(*g.rough_rate_mps[i]) : -8192, 14);
}

// A fine range (value - rough) in units of `unit_ms`, invalid when absent or outside the `bits` field.
std::int64_t fineRange(std::optional<double> value_m, std::optional<double> rough_m, double unit_ms, int bits) {
  const std::int64_t invalid = -(1LL << (bits - 1));
  if (!value_m || !rough_m) return invalid;
  const double v = std::round((*value_m - *rough_m) / kRangeMs_m / unit_ms);
  if (v <= static_cast<double>(invalid) || v >= static_cast<double>(-invalid)) return invalid;
  return static_cast<std::int64_t>(v);
}

// Fine pseudoranges (2^-29 ms) and fine phase ranges (2^-31 ms) of every cell.
void putFineRanges(BitWriter& w, const MsmGroupCells& g) {
  const auto& cells = g.cells;
  for (std::size_t c = 0; c < cells.size(); ++c)
    w.putSigned(fineRange(cells[c].signal->pseudorange_m, g.rough_range_m[g.cell_satellite[c]],
                          std::ldexp(1.0, -29), 20),
                20);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    std::optional<double> phase_m;
    if (cells[c].signal->carrier_phase_cycles && cells[c].wavelength_m)
      phase_m = *cells[c].signal->carrier_phase_cycles * *cells[c].wavelength_m;
    w.putSigned(fineRange(phase_m, g.rough_range_m[g.cell_satellite[c]], std::ldexp(1.0, -31), 24), 24);
  }
}

// Lock time indicators, half-cycle flags, CNR [1/16 dB-Hz] and fine rates [0.0001 m/s] of every cell.
void putCellStatusAndRates(BitWriter& w, const MsmGroupCells& g) {
  const auto& cells = g.cells;
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
    const auto& rough_rate_mps = g.rough_rate_mps[g.cell_satellite[c]];
    if (cells[c].signal->doppler_hz && cells[c].wavelength_m && rough_rate_mps) {
      const double rate = -*cells[c].signal->doppler_hz * *cells[c].wavelength_m;
      const double f = std::round((rate - *rough_rate_mps) / 0.0001);
      if (std::fabs(f) < 16383.0) v = static_cast<std::int64_t>(f);
    }
    w.putSigned(v, 15);
  }
}

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
  std::vector<std::vector<std::uint8_t>> out;
  const MsmSatellites sats = selectMsmSatellites(epoch, system);              // 1. satellites by id
  const int type = msmMessageType(system, 7).value_or(0);
  if (sats.empty() || type == 0) return out;
  const std::vector<MsmSatellites> groups = groupSatellitesIn64Cells(sats, system);  // 2. 64-cell groups
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<int> sigs = groupSignalIds(groups[g], system);
    const bool multiple = g + 1 < groups.size() || options.more_messages_follow;
    BitWriter w;
    putMsmHeader(w, type, epoch, system, options, multiple, groups[g], sigs);        // 3. header
    const MsmGroupCells cells = putCellMask(w, groups[g], sigs, system, options);  // 4. cell mask, rough values
    putSatelliteData(w, cells);                                                  // 5. satellite data
    putFineRanges(w, cells);                                                     // 6. signal data
    putCellStatusAndRates(w, cells);
    out.push_back(w.bytes());
  }
  return out;
}

}  // namespace ppp
