#include "ppp_bayes_tree/models/ssr_from_precise.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/io/rinex_nav_reader.h"
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


struct Rac {
  Eigen::Vector3d rac = Eigen::Vector3d::Zero();
  double clock_m = 0.0;
};

}  // namespace

SsrFromPreciseResult ssrFromPrecise(const std::vector<NavData>& navigation, const EphemerisSource& precise,
                                    const AntennaCalibrationProvider* antennas, const BiasProvider* biases,
                                    const GnssTime& first, const GnssTime& last, const SsrFromPreciseOptions& options) {
  const auto interval_code = ssrUpdateIntervalCode(options.interval_s);
  if (!interval_code) throw std::invalid_argument("SSR interval " + std::to_string(options.interval_s) + " s is not an SSR update interval (DF391)");
  const bool apc = options.reference != EphemerisReference::CentreOfMass;
  if (apc && antennas == nullptr) throw std::invalid_argument("SSR at the antenna phase centre needs satellite antenna offsets (ANTEX)");
  EphemerisSelectionOptions selection;
  selection.galileo = GalileoPreference::INavOnly;
  BroadcastEphemerisStore store(selection);
  // As an analysis centre: at t0 only records already transmitted (RINEX transmission
  // time of message) can be corrected; a record without one serves every instant.
  for (const auto& nav : navigation) {
    for (const auto& e : nav.gps) store.add(e, transmissionTime(e));
    for (const auto& e : nav.galileo) store.add(e, transmissionTime(e));
    for (const auto& e : nav.glonass) store.add(e, std::optional<GnssTime>(transmissionTime(e)));
  }
  std::set<SatelliteId> satellites;
  for (const auto& nav : navigation)
    for (const auto& s : nav.satellites)
      if (std::find(options.systems.begin(), options.systems.end(), s.system) != options.systems.end()) satellites.insert(s);

  SsrFromPreciseResult out;
  std::map<std::string, std::size_t> left_out;  // reason -> count
  const double U = options.interval_s;
  const std::int64_t step = static_cast<std::int64_t>(std::llround(U));
  std::int64_t t_s = first.wholeSeconds() + (first.fraction() > 0 ? 1 : 0);
  t_s = ((t_s + step - 1) / step) * step;

  // The precise point the SSR orbit must reproduce, and the precise clock.
  const auto precisePoint = [&](const SatelliteId& sat, const GnssTime& t) -> std::optional<std::pair<Eigen::Vector3d, double>> {
    const auto o = precise.satelliteOrbit(sat, t);
    const auto c = precise.satelliteClock(sat, t);
    if (!o.ok() || !c.ok()) return std::nullopt;
    Eigen::Vector3d x = o.value->position_ecef_m;
    if (apc && o.value->reference == EphemerisReference::CentreOfMass) {
      const auto cal = antennas->satellite(sat, t);
      const auto [b1, b2] = ssrIonosphereFreeBands(sat.system);
      const auto fr1 = carrierFrequency_hz(sat.system, b1), fr2 = carrierFrequency_hz(sat.system, b2);
      if (!fr1 || !fr2) return std::nullopt;
      const auto offset = satelliteReferenceOffset_m(options.reference, cal.calibration, sat.system, b1, b2,
                                                     ionosphereFreeCoefficients(*fr1, *fr2));
      if (!offset) return std::nullopt;
      const Eigen::Vector3d& pco = *offset;
      const SatelliteBodyAxes axes = nominalSatelliteAxes(x, o.value->velocity_ecef_mps, sunPositionEcef_m(t));
      x += pco.x() * axes.x_ecef + pco.y() * axes.y_ecef + pco.z() * axes.z_ecef;
    }
    return std::make_pair(x, c.value->clock_bias_s);
  };
  const auto racAt = [&](const SatelliteId& sat, const Selected& sel, const GnssTime& t) -> std::optional<Rac> {
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
  };

  for (; t_s <= last.wholeSeconds(); t_s += step) {
    const GnssTime t0 = GnssTime::fromGpsSeconds(t_s);
    std::map<GnssSystem, std::vector<std::pair<SsrOrbitCorrection, SsrClockCorrection>>> per_system;
    std::map<GnssSystem, std::vector<SsrCodeBias>> bias_per_system;
    for (const SatelliteId& sat : satellites) {
      const auto sel = selectRecord(store, sat, t0);
      if (!sel) {
        ++left_out["no valid broadcast record"];
        continue;
      }
      const auto now = racAt(sat, *sel, t0);
      if (!now) {
        ++left_out[apc ? "no precise orbit/clock or no satellite PCO" : "no precise orbit/clock"];
        continue;
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
        ++left_out["correction beyond the SSR field ranges"];
        continue;
      }
      per_system[sat.system].push_back({o, c});
      out.satellite_epochs += 1;
      if (biases != nullptr) {
        SsrCodeBias cb;
        cb.satellite = sat;
        for (int id = 0; id < 32; ++id) {
          const auto code = ssrSignalCode(sat.system, id, false);
          if (!code) continue;
          const BiasAnswer a = biases->codeBias(sat, *code, t0);
          if (a.value_m && std::abs(*a.value_m) < 80.0) cb.biases.push_back({id, code, -*a.value_m});
        }
        if (!cb.biases.empty()) bias_per_system[sat.system].push_back(cb);
      }
    }
    if (per_system.empty()) continue;
    out.epochs += 1;
    const auto makeHeader = [&](GnssSystem sys, SsrMessageKind kind) {
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
      m.header.update_interval_code = *interval_code;
      m.header.update_interval_s = U;
      m.header.iod_ssr = options.iod_ssr;
      m.header.provider_id = options.provider_id;
      m.header.solution_id = options.solution_id;
      if (kind == SsrMessageKind::Orbit || kind == SsrMessageKind::Combined) m.header.datum_regional = false;
      return m;
    };
    const std::size_t per_message = static_cast<std::size_t>(std::clamp(options.satellites_per_message, 1, 63));
    for (const auto& [sys, list] : per_system) {
      for (std::size_t i = 0; i < list.size(); i += per_message) {
        const std::size_t end = std::min(list.size(), i + per_message);
        const bool more = end < list.size();
        if (options.combined) {
          SsrMessage m = makeHeader(sys, SsrMessageKind::Combined);
          m.header.multiple_message = more;
          for (std::size_t k = i; k < end; ++k) { m.orbits.push_back(list[k].first); m.clocks.push_back(list[k].second); }
          out.messages.push_back(std::move(m));
        } else {
          SsrMessage mo = makeHeader(sys, SsrMessageKind::Orbit), mc = makeHeader(sys, SsrMessageKind::Clock);
          mo.header.multiple_message = mc.header.multiple_message = more;
          for (std::size_t k = i; k < end; ++k) { mo.orbits.push_back(list[k].first); mc.clocks.push_back(list[k].second); }
          out.messages.push_back(std::move(mo));
          out.messages.push_back(std::move(mc));
        }
      }
    }
    for (const auto& [sys, list] : bias_per_system) {
      for (std::size_t i = 0; i < list.size(); i += per_message) {
        const std::size_t end = std::min(list.size(), i + per_message);
        SsrMessage m = makeHeader(sys, SsrMessageKind::CodeBias);
        m.header.multiple_message = end < list.size();
        m.code_biases.assign(list.begin() + static_cast<std::ptrdiff_t>(i), list.begin() + static_cast<std::ptrdiff_t>(end));
        out.messages.push_back(std::move(m));
      }
    }
  }
  for (const auto& [why, n] : left_out) out.notes.push_back(std::to_string(n) + " satellite-epoch(s) left out: " + why);
  return out;
}

}  // namespace ppp
