#include "ppp_bayes_tree/models/ssr_from_precise.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

namespace {

/// The broadcast record a user selects at t0, as a function of time, and its IOD.
struct Selected {
  int iod = 0;
  std::function<BroadcastState(const GnssTime&)> state;
};

std::optional<Selected> selectRecord(const BroadcastEphemerisStore& store, const SatelliteId& sat, const GnssTime& t0) {
  switch (sat.system) {
    case GnssSystem::GPS:
    case GnssSystem::QZSS: {
      const auto r = store.gps(sat, t0);
      if (!r) return std::nullopt;
      const GpsLnavEphemeris e = *r.record;
      return Selected{e.iode, [e](const GnssTime& t) { return satelliteState(e, t); }};
    }
    case GnssSystem::Galileo: {
      const auto r = store.galileo(sat, t0);
      if (!r) return std::nullopt;
      const GalileoEphemeris e = *r.record;
      return Selected{e.iod_nav, [e](const GnssTime& t) { return satelliteState(e, t); }};
    }
    case GnssSystem::GLONASS: {
      const auto r = store.glonass(sat, t0);
      if (!r) return std::nullopt;
      const GlonassEphemeris e = *r.record;
      return Selected{glonassSsrIod(e), [e](const GnssTime& t) { return satelliteState(e, t); }};
    }
    default: return std::nullopt;
  }
}


constexpr double kPhaseBiasStep_m = 1e-4;  // DF482 resolution

/// OSBs b1, b2 [m] of two bands (f1 > f2) on the DF482 grid: of the grid points
/// within 4 steps of each, the one whose wide-lane (Melbourne-Wuebbena phase)
/// combination (f1 b1 - f2 b2)/(f1 - f2) is nearest the unrounded one, among those
/// whose ionosphere-free combination stays within one step of it. Rounding each
/// alone would move the wide lane by up to 5e-4 cycle (GPS); this keeps it below 1e-5.
std::pair<double, double> wideLanePreservingGrid(double b1_m, double b2_m, double f1_hz, double f2_hz) {
  const double n1 = std::round(b1_m / kPhaseBiasStep_m), n2 = std::round(b2_m / kPhaseBiasStep_m);
  const auto wl = [&](double x1, double x2) { return (f1_hz * x1 - f2_hz * x2) / (f1_hz - f2_hz); };
  const auto iono_free = [&](double x1, double x2) {
    return (f1_hz * f1_hz * x1 - f2_hz * f2_hz * x2) / (f1_hz * f1_hz - f2_hz * f2_hz);
  };
  std::pair<double, double> best{n1 * kPhaseBiasStep_m, n2 * kPhaseBiasStep_m};
  double best_error_m = std::abs(wl(best.first, best.second) - wl(b1_m, b2_m));
  for (int d1 = -4; d1 <= 4; ++d1)
    for (int d2 = -4; d2 <= 4; ++d2) {
      const double x1 = (n1 + d1) * kPhaseBiasStep_m, x2 = (n2 + d2) * kPhaseBiasStep_m;
      if (std::abs(iono_free(x1, x2) - iono_free(b1_m, b2_m)) > kPhaseBiasStep_m) continue;
      const double error_m = std::abs(wl(x1, x2) - wl(b1_m, b2_m));
      if (error_m < best_error_m) {
        best_error_m = error_m;
        best = {x1, x2};
      }
    }
  return best;
}

/// The SSR phase biases (-OSB) `provider` answers for `sat` at t0, one per RTCM
/// signal id; with two bands, their values on the grid by wideLanePreservingGrid.
std::optional<SsrPhaseBias> integerPhaseBiases(const BiasProvider& provider, const SatelliteId& sat, const GnssTime& t0) {
  SsrPhaseBias p;
  p.satellite = sat;
  std::map<char, double> osb_by_band_m;  // the first answer of each band
  for (int id = 0; id < 32; ++id) {
    auto code = ssrSignalCode(sat.system, id, false);
    if (!code) continue;
    code->type = ObservableType::CarrierPhase;
    const BiasAnswer a = provider.phaseBias(sat, *code, t0);
    if (!a.value_m || std::abs(*a.value_m) > 50.0) continue;  // DF482: +-52.4287 m
    osb_by_band_m.emplace(code->band, *a.value_m);
    SsrSignalPhaseBias s;
    s.signal_id = id;
    s.code = code;
    s.integer = true;
    s.widelane_integer = 2;
    s.discontinuity_counter = 0;
    s.bias_m = -*a.value_m;
    p.biases.push_back(s);
  }
  if (p.biases.empty()) return std::nullopt;
  if (osb_by_band_m.size() == 2) {
    const auto [band_low, band_high] = std::make_pair(osb_by_band_m.begin()->first, osb_by_band_m.rbegin()->first);
    const auto f_low = carrierFrequency_hz(sat.system, band_low), f_high = carrierFrequency_hz(sat.system, band_high);
    if (f_low && f_high && *f_low != *f_high) {
      const bool low_first = *f_low > *f_high;  // band 1 (L1/E1) is the higher frequency
      const char b1 = low_first ? band_low : band_high, b2 = low_first ? band_high : band_low;
      const auto [g1, g2] = wideLanePreservingGrid(osb_by_band_m[b1], osb_by_band_m[b2],
                                                    std::max(*f_low, *f_high), std::min(*f_low, *f_high));
      for (auto& s : p.biases)
        if (s.code->band == b1 && std::abs(-s.bias_m - osb_by_band_m[b1]) < 1e-12) s.bias_m = -g1;
        else if (s.code->band == b2 && std::abs(-s.bias_m - osb_by_band_m[b2]) < 1e-12) s.bias_m = -g2;
    }
  }
  return p;
}

/// The end of the phase-bias message that starts at list[first]: at most
/// `per_message` satellites and 1023 payload bytes (RTCM 10403.3 1265-1270: a
/// 69-bit header with the satellite count, 28 bits per satellite, 32 per signal).
std::size_t phaseBiasMessageEnd(const std::vector<SsrPhaseBias>& list, std::size_t first, std::size_t per_message) {
  constexpr std::size_t kHeaderBits = 69, kSatelliteBits = 28, kSignalBits = 32, kPayloadBits = 1023 * 8;
  std::size_t bits = kHeaderBits, end = first;
  while (end < list.size() && end - first < per_message) {
    const std::size_t add = kSatelliteBits + kSignalBits * list[end].biases.size();
    if (end > first && bits + add > kPayloadBits) break;
    bits += add;
    ++end;
  }
  return end;
}

struct Rac {
  Eigen::Vector3d rac = Eigen::Vector3d::Zero();
  double clock_m = 0.0;
};

/// The corrections of one SSR epoch, per system.
struct EpochCorrections {
  std::map<GnssSystem, std::vector<std::pair<SsrOrbitCorrection, SsrClockCorrection>>> orbit_clock;
  std::map<GnssSystem, std::vector<SsrCodeBias>> code_biases;
  std::map<GnssSystem, std::vector<SsrPhaseBias>> phase_biases;
};

/// Writes the SSR messages of precise orbits and clocks against the broadcast
/// records an analysis centre holds, epoch after epoch (ssrFromPrecise).
class SsrFromPreciseBuilder {
 public:
  SsrFromPreciseBuilder(const EphemerisSource& precise, const AntennaCalibrationProvider* antennas,
                        const BiasProvider* biases, const BiasProvider* phase_biases,
                        const SsrFromPreciseOptions& options, int interval_code)
      : precise_(precise), antennas_(antennas), biases_(biases), phase_biases_(phase_biases), options_(options),
        interval_code_(interval_code), apc_(options.reference != EphemerisReference::CentreOfMass),
        store_(galileoINavOnly()) {}

  void addNavigation(const std::vector<NavData>& navigation);
  /// One SSR epoch at t0: the corrections of every satellite, then their messages.
  void epoch(const GnssTime& t0);
  SsrFromPreciseResult finish();

 private:
  static EphemerisSelectionOptions galileoINavOnly() {
    EphemerisSelectionOptions selection;
    selection.galileo = GalileoPreference::INavOnly;
    return selection;
  }
  std::optional<std::pair<Eigen::Vector3d, double>> precisePoint(const SatelliteId& sat, const GnssTime& t) const;
  std::optional<Rac> racAt(const SatelliteId& sat, const Selected& sel, const GnssTime& t) const;
  void satellite(const SatelliteId& sat, const GnssTime& t0, EpochCorrections& corrections);
  std::optional<SsrCodeBias> codeBiases(const SatelliteId& sat, const GnssTime& t0) const;
  SsrMessage header(GnssSystem sys, SsrMessageKind kind, const GnssTime& t0) const;
  void orbitClockMessages(const EpochCorrections& corrections, const GnssTime& t0);
  void biasMessages(const EpochCorrections& corrections, const GnssTime& t0);

  const EphemerisSource& precise_;
  const AntennaCalibrationProvider* antennas_;
  const BiasProvider* biases_;
  const BiasProvider* phase_biases_;
  const SsrFromPreciseOptions& options_;
  const int interval_code_;
  const bool apc_;  // at the antenna phase centre
  BroadcastEphemerisStore store_;
  std::set<SatelliteId> satellites_;
  std::map<std::string, std::size_t> left_out_;  // reason -> count
  SsrFromPreciseResult out_;
};

void SsrFromPreciseBuilder::addNavigation(const std::vector<NavData>& navigation) {
  // As an analysis centre: at t0 only records already transmitted (RINEX transmission
  // time of message) can be corrected; a record without one serves every instant.
  for (const auto& nav : navigation) {
    for (const auto& e : nav.gps) store_.add(e, transmissionTime(e));
    for (const auto& e : nav.galileo) store_.add(e, transmissionTime(e));
    for (const auto& e : nav.glonass) store_.add(e, std::optional<GnssTime>(transmissionTime(e)));
  }
  const auto& systems = options_.systems;
  for (const auto& nav : navigation)
    for (const auto& s : nav.satellites)
      if (std::find(systems.begin(), systems.end(), s.system) != systems.end()) satellites_.insert(s);
}

/// The precise point the SSR orbit must reproduce, and the precise clock [s].
std::optional<std::pair<Eigen::Vector3d, double>> SsrFromPreciseBuilder::precisePoint(const SatelliteId& sat,
                                                                                     const GnssTime& t) const {
  const auto o = precise_.satelliteOrbit(sat, t);
  const auto c = precise_.satelliteClock(sat, t);
  if (!o.ok() || !c.ok()) return std::nullopt;
  Eigen::Vector3d x = o.value->position_ecef_m;
  if (apc_ && o.value->reference == EphemerisReference::CentreOfMass) {
    const auto cal = antennas_->satellite(sat, t);
    const auto [b1, b2] = ssrIonosphereFreeBands(sat.system);
    const auto fr1 = carrierFrequency_hz(sat.system, b1), fr2 = carrierFrequency_hz(sat.system, b2);
    if (!fr1 || !fr2) return std::nullopt;
    const auto offset = satelliteReferenceOffset_m(options_.reference, cal.calibration, sat.system, b1, b2,
                                                   ionosphereFreeCoefficients(*fr1, *fr2));
    if (!offset) return std::nullopt;
    const Eigen::Vector3d& pco = *offset;
    const SatelliteBodyAxes axes = nominalSatelliteAxes(x, o.value->velocity_ecef_mps, sunPositionEcef_m(t));
    x += pco.x() * axes.x_ecef + pco.y() * axes.y_ecef + pco.z() * axes.z_ecef;
  }
  return std::make_pair(x, c.value->clock_bias_s);
}

/// Broadcast minus precise orbit in radial, along, cross [m], and the clock correction [m].
std::optional<Rac> SsrFromPreciseBuilder::racAt(const SatelliteId& sat, const Selected& sel, const GnssTime& t) const {
  const auto p = precisePoint(sat, t);
  if (!p) return std::nullopt;
  const BroadcastState b = sel.state(t);
  const Eigen::Vector3d e_a = b.velocity_ecef_mps.normalized();
  const Eigen::Vector3d e_c = b.position_ecef_m.cross(b.velocity_ecef_mps).normalized();
  const Eigen::Vector3d e_r = e_a.cross(e_c);
  const Eigen::Vector3d d = b.position_ecef_m - p->first;
  Rac r;
  r.rac = Eigen::Vector3d(d.dot(e_r), d.dot(e_a), d.dot(e_c));
  r.clock_m = (p->second - (b.clock_bias_s - b.relativistic_s)) * kSpeedOfLight_mps;
  return r;
}

void SsrFromPreciseBuilder::epoch(const GnssTime& t0) {
  EpochCorrections corrections;
  for (const SatelliteId& sat : satellites_) satellite(sat, t0, corrections);
  if (corrections.orbit_clock.empty()) return;
  out_.epochs += 1;
  orbitClockMessages(corrections, t0);
  biasMessages(corrections, t0);
}

void SsrFromPreciseBuilder::satellite(const SatelliteId& sat, const GnssTime& t0, EpochCorrections& corrections) {
  const double U = options_.interval_s;
  const auto sel = selectRecord(store_, sat, t0);
  if (!sel) {
    ++left_out_["no valid broadcast record"];
    return;
  }
  const auto now = racAt(sat, *sel, t0);
  if (!now) {
    ++left_out_[apc_ ? "no precise orbit/clock or no satellite PCO" : "no precise orbit/clock"];
    return;
  }
  Eigen::Vector3d rate = Eigen::Vector3d::Zero();
  double clock_rate = 0.0;
  if (const auto next = racAt(sat, *sel, t0 + U)) {
    rate = (next->rac - now->rac) / U;
    clock_rate = (next->clock_m - now->clock_m) / U;
  }
  SsrOrbitCorrection o;
  o.satellite = sat;
  o.iod = sel->iod;
  o.radial_m = now->rac.x();
  o.along_m = now->rac.y();
  o.cross_m = now->rac.z();
  o.radial_dot_mps = rate.x();
  o.along_dot_mps = rate.y();
  o.cross_dot_mps = rate.z();
  SsrClockCorrection c;
  c.satellite = sat;
  c.c0_m = now->clock_m;
  c.c1_m_per_s = clock_rate;
  // Values beyond the fields (e.g. a broadcast record metres off) are left out.
  if (std::abs(o.radial_m) > 209.0 || std::abs(o.along_m) > 209.0 || std::abs(o.cross_m) > 209.0 ||
      std::abs(c.c0_m) > 209.0 || std::abs(o.radial_dot_mps) > 1.0 || std::abs(o.along_dot_mps) > 1.0 ||
      std::abs(o.cross_dot_mps) > 1.0 || std::abs(c.c1_m_per_s) > 1.0) {
    ++left_out_["correction beyond the SSR field ranges"];
    return;
  }
  corrections.orbit_clock[sat.system].push_back({o, c});
  out_.satellite_epochs += 1;
  if (const auto cb = codeBiases(sat, t0)) corrections.code_biases[sat.system].push_back(*cb);
  if (phase_biases_ != nullptr)
    if (auto pb = integerPhaseBiases(*phase_biases_, sat, t0)) corrections.phase_biases[sat.system].push_back(std::move(*pb));
}

/// The SSR code biases (-OSB) of `sat` at t0, one per RTCM signal id; nullopt without any.
std::optional<SsrCodeBias> SsrFromPreciseBuilder::codeBiases(const SatelliteId& sat, const GnssTime& t0) const {
  if (biases_ == nullptr) return std::nullopt;
  SsrCodeBias cb;
  cb.satellite = sat;
  for (int id = 0; id < 32; ++id) {
    const auto code = ssrSignalCode(sat.system, id, false);
    if (!code) continue;
    const BiasAnswer a = biases_->codeBias(sat, *code, t0);
    if (a.value_m && std::abs(*a.value_m) < 80.0) cb.biases.push_back({id, code, -*a.value_m});
  }
  if (cb.biases.empty()) return std::nullopt;
  return cb;
}

SsrMessage SsrFromPreciseBuilder::header(GnssSystem sys, SsrMessageKind kind, const GnssTime& t0) const {
  SsrMessage m;
  m.header.system = sys;
  m.header.kind = kind;
  m.header.epoch = t0;
  double sow = t0.gpsWeek().seconds_of_week;
  if (sys == GnssSystem::GLONASS) {
    const double glo = t0.toGpsSecondsDouble() + t0.offsetToSystem_s(TimeSystem::GLONASS);
    sow = glo - std::floor(glo / 86400.0) * 86400.0;
  }
  m.header.epoch_time_s = static_cast<std::uint32_t>(std::llround(sow));
  m.header.update_interval_code = interval_code_;
  m.header.update_interval_s = options_.interval_s;
  m.header.iod_ssr = options_.iod_ssr;
  m.header.provider_id = options_.provider_id;
  m.header.solution_id = options_.solution_id;
  if (kind == SsrMessageKind::Orbit || kind == SsrMessageKind::Combined) m.header.datum_regional = false;
  return m;
}

void SsrFromPreciseBuilder::orbitClockMessages(const EpochCorrections& corrections, const GnssTime& t0) {
  const std::size_t per_message = static_cast<std::size_t>(std::clamp(options_.satellites_per_message, 1, 63));
  for (const auto& [sys, list] : corrections.orbit_clock) {
    for (std::size_t i = 0; i < list.size(); i += per_message) {
      const std::size_t end = std::min(list.size(), i + per_message);
      const bool more = end < list.size();
      if (options_.combined) {
        SsrMessage m = header(sys, SsrMessageKind::Combined, t0);
        m.header.multiple_message = more;
        for (std::size_t k = i; k < end; ++k) { m.orbits.push_back(list[k].first); m.clocks.push_back(list[k].second); }
        out_.messages.push_back(std::move(m));
      } else {
        SsrMessage mo = header(sys, SsrMessageKind::Orbit, t0), mc = header(sys, SsrMessageKind::Clock, t0);
        mo.header.multiple_message = mc.header.multiple_message = more;
        for (std::size_t k = i; k < end; ++k) { mo.orbits.push_back(list[k].first); mc.clocks.push_back(list[k].second); }
        out_.messages.push_back(std::move(mo));
        out_.messages.push_back(std::move(mc));
      }
    }
  }
}

void SsrFromPreciseBuilder::biasMessages(const EpochCorrections& corrections, const GnssTime& t0) {
  const std::size_t per_message = static_cast<std::size_t>(std::clamp(options_.satellites_per_message, 1, 63));
  for (const auto& [sys, list] : corrections.code_biases) {
    for (std::size_t i = 0; i < list.size(); i += per_message) {
      const std::size_t end = std::min(list.size(), i + per_message);
      SsrMessage m = header(sys, SsrMessageKind::CodeBias, t0);
      m.header.multiple_message = end < list.size();
      m.code_biases.assign(list.begin() + static_cast<std::ptrdiff_t>(i), list.begin() + static_cast<std::ptrdiff_t>(end));
      out_.messages.push_back(std::move(m));
    }
  }
  for (const auto& [sys, list] : corrections.phase_biases) {
    for (std::size_t i = 0, end = 0; i < list.size(); i = end) {
      end = phaseBiasMessageEnd(list, i, per_message);
      SsrMessage m = header(sys, SsrMessageKind::PhaseBias, t0);
      m.header.multiple_message = end < list.size();
      m.dispersive_consistent = m.mw_consistent = true;
      m.phase_biases.assign(list.begin() + static_cast<std::ptrdiff_t>(i), list.begin() + static_cast<std::ptrdiff_t>(end));
      out_.messages.push_back(std::move(m));
    }
  }
}

SsrFromPreciseResult SsrFromPreciseBuilder::finish() {
  for (const auto& [why, n] : left_out_) out_.notes.push_back(std::to_string(n) + " satellite-epoch(s) left out: " + why);
  return std::move(out_);
}

}  // namespace

SsrFromPreciseResult ssrFromPrecise(const std::vector<NavData>& navigation, const EphemerisSource& precise,
                                    const AntennaCalibrationProvider* antennas, const BiasProvider* biases,
                                    const GnssTime& first, const GnssTime& last, const SsrFromPreciseOptions& options,
                                    const BiasProvider* phase_biases) {
  // 1. The options: an SSR update interval; antenna offsets for the phase centre.
  const auto interval_code = ssrUpdateIntervalCode(options.interval_s);
  if (!interval_code) throw std::invalid_argument("SSR interval " + std::to_string(options.interval_s) + " s is not an SSR update interval (DF391)");
  const bool apc = options.reference != EphemerisReference::CentreOfMass;
  if (apc && antennas == nullptr) throw std::invalid_argument("SSR at the antenna phase centre needs satellite antenna offsets (ANTEX)");
  // 2. The broadcast records and the satellites of the chosen systems.
  SsrFromPreciseBuilder builder(precise, antennas, biases, phase_biases, options, *interval_code);
  builder.addNavigation(navigation);
  // 3. Every SSR epoch from the first whole multiple of the interval on.
  const std::int64_t step = static_cast<std::int64_t>(std::llround(options.interval_s));
  std::int64_t t_s = first.wholeSeconds() + (first.fraction() > 0 ? 1 : 0);
  t_s = ((t_s + step - 1) / step) * step;
  for (; t_s <= last.wholeSeconds(); t_s += step) builder.epoch(GnssTime::fromGpsSeconds(t_s));
  // 4. Notes on the satellite-epochs left out.
  return builder.finish();
}

}  // namespace ppp
