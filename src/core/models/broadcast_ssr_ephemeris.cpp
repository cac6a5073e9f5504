#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <Eigen/Geometry>
#include <cstdio>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

namespace {
bool isINav(const GalileoEphemeris& e) { return e.type == GalileoNavType::INav; }
}  // namespace

int glonassSsrIod(const GlonassEphemeris& eph) {
  const double glo_s = eph.tb.toGpsSecondsDouble() + eph.tb.offsetToSystem_s(TimeSystem::GLONASS);
  const double tod = glo_s - std::floor(glo_s / 86400.0) * 86400.0;
  return static_cast<int>(std::floor(tod / 900.0 + 1e-6)) % 96;
}

std::optional<EphemerisReference> ssrReferenceFromStreamName(const std::string& name) {
  const auto slash = name.find_last_of('/');
  const std::string base = slash == std::string::npos ? name : name.substr(slash + 1);
  if (base.rfind("SSRA", 0) == 0) return EphemerisReference::AntennaPhaseCentreL1;
  if (base.rfind("SSRC", 0) == 0) return EphemerisReference::CentreOfMass;
  return std::nullopt;
}

BroadcastSsrEphemeris::BroadcastSsrEphemeris(std::shared_ptr<const SsrCorrectionStore> ssr,
                                             BroadcastSsrOptions options)
    : ssr_(std::move(ssr)), options_(options) {}

bool BroadcastSsrEphemeris::insert(Record r) {
  auto& list = records_[r.gps ? r.gps->satellite : r.galileo ? r.galileo->satellite : r.glonass->satellite];
  const bool inav = r.galileo && isINav(*r.galileo);
  for (const Record& x : list)
    if (x.reference == r.reference && x.iod == r.iod && (x.galileo && isINav(*x.galileo)) == inav) return false;
  list.push_back(std::move(r));
  return true;
}

bool BroadcastSsrEphemeris::addRecord(const GpsLnavEphemeris& e, std::optional<GnssTime> received_at) {
  if (!options_.allow_unhealthy && !isHealthy(e)) return false;
  if (checkKeplerOrbit(e.orbit)) return false;
  Record r;
  r.gps = e;
  r.reference = e.orbit.toe;
  r.iod = e.iode;
  r.received_at = received_at;
  return insert(std::move(r));
}

bool BroadcastSsrEphemeris::addRecord(const GalileoEphemeris& e, std::optional<GnssTime> received_at) {
  if (!options_.allow_unhealthy && !isHealthy(e)) return false;
  if (checkKeplerOrbit(e.orbit)) return false;
  Record r;
  r.galileo = e;
  r.reference = e.orbit.toe;
  r.iod = e.iod_nav;
  r.received_at = received_at;
  return insert(std::move(r));
}

bool BroadcastSsrEphemeris::addRecord(const GlonassEphemeris& e, std::optional<GnssTime> received_at) {
  if (!options_.allow_unhealthy && !isHealthy(e)) return false;
  if (checkGlonassState(e)) return false;
  Record r;
  r.glonass = e;
  r.reference = e.tb;
  r.iod = glonassSsrIod(e);
  r.received_at = received_at;
  return insert(std::move(r));
}

std::size_t BroadcastSsrEphemeris::dropOlderThan(const GnssTime& t, double keep_s) {
  std::size_t n = 0;
  for (auto& [sat, list] : records_) {
    const auto before = list.size();
    list.erase(std::remove_if(list.begin(), list.end(), [&](const Record& r) { return t - r.reference > keep_s; }),
               list.end());
    n += before - list.size();
  }
  return n;
}

std::size_t BroadcastSsrEphemeris::recordCount() const {
  std::size_t n = 0;
  for (const auto& [sat, list] : records_) n += list.size();
  return n;
}

BroadcastSsrEphemeris::BroadcastSsrEphemeris(const std::vector<NavData>& navigation,
                                             std::shared_ptr<const SsrCorrectionStore> ssr, BroadcastSsrOptions options)
    : ssr_(std::move(ssr)), options_(options) {
  for (const NavData& nav : navigation) {
    for (const auto& e : nav.gps) addRecord(e);
    for (const auto& e : nav.galileo) addRecord(e);
    for (const auto& e : nav.glonass) addRecord(e);
  }
  checkConsistency();
}

bool ssrBroadcastModelled(GnssSystem system) {
  constexpr GnssSystem kModelled[] = {GnssSystem::GPS, GnssSystem::QZSS, GnssSystem::Galileo, GnssSystem::GLONASS};
  return std::find(std::begin(kModelled), std::end(kModelled), system) != std::end(kModelled);
}

void BroadcastSsrEphemeris::checkConsistency() {
  consistency_ = StreamCounters{};
  satellites_without_broadcast_.clear();
  if (!ssr_) return;
  // Every orbit correction of a modelled system must find its broadcast record.
  for (const auto& [sat, series] : ssr_->orbits()) {
    if (!ssrBroadcastModelled(sat.system)) continue;
    if (records_.find(sat) == records_.end()) {
      satellites_without_broadcast_.insert(sat);  // no navigation data at all: not a stream problem
      continue;
    }
    for (const auto& [t0, e] : series) {
      if (findRecord(sat, e.value.iod, t0) != nullptr) continue;
      StreamProblem p;
      p.kind = StreamProblemKind::SsrWithoutBroadcast;
      p.byte_offset = e.byte_offset;
      p.frame_index = e.frame_index;
      p.detail = "SSR orbit correction for " + sat.toString() + " IOD " + std::to_string(e.value.iod) + " at " +
                 t0.toString(TimeSystem::GPS, 0) + " has no broadcast record with that IOD: satellite excluded there";
      consistency_.add(std::move(p));
    }
  }
}

const BroadcastSsrEphemeris::Record* BroadcastSsrEphemeris::findRecord(const SatelliteId& sat, int iod,
                                                                      const GnssTime& t) const {
  const auto it = records_.find(sat);
  if (it == records_.end()) return nullptr;
  const Record* best = nullptr;
  double best_d = 0.0;
  bool best_inav = false;
  for (const Record& r : it->second) {
    const bool same = sat.system == GnssSystem::GLONASS ? (r.iod % 128) == (iod % 128) : r.iod == iod;
    if (!same) continue;
    if (r.received_at && !(*r.received_at < t)) continue;  // not yet received at t
    const double d = std::fabs(t - r.reference);
    if (d > 6.0 * 3600.0) continue;  // the same IOD from another day
    const bool inav = r.galileo && isINav(*r.galileo);
    if (best == nullptr || (inav && !best_inav) || (inav == best_inav && d < best_d)) {
      best = &r;
      best_d = d;
      best_inav = inav;
    }
  }
  return best;
}

BroadcastState BroadcastSsrEphemeris::stateOf(const Record& r, const GnssTime& t) {
  if (r.gps) return satelliteState(*r.gps, t);
  if (r.galileo) return satelliteState(*r.galileo, t);
  return satelliteState(*r.glonass, t);
}

double BroadcastSsrEphemeris::polynomialClock_s(const Record& /*r*/, const BroadcastState& s) {
  return s.clock_bias_s - s.relativistic_s;
}

EphemerisAnswer<SsrCorrectedState> BroadcastSsrEphemeris::correctedState(const SatelliteId& sat,
                                                                       const GnssTime& t) const {
  using Answer = EphemerisAnswer<SsrCorrectedState>;
  if (!ssrBroadcastModelled(sat.system))
    return Answer::unavailable(EphemerisUnavailable::SystemNotModelled,
                               std::string("no broadcast model for ") + std::string(systemName(sat.system)));
  if (!ssr_) return Answer::unavailable(EphemerisUnavailable::NoProducts, "no SSR corrections loaded");
  const auto orbit = ssr_->orbit(sat, t);
  if (!orbit)
    return Answer::unavailable(orbit.too_old ? EphemerisUnavailable::OutsideSpan : EphemerisUnavailable::SatelliteNotInProducts,
                               orbit.reason);
  const SsrOrbitCorrection& o = orbit.entry->value;
  const Record* rec = findRecord(sat, o.iod, t);
  if (rec == nullptr)
    return Answer::unavailable(EphemerisUnavailable::NoValidRecord,
                               "SSR correction for " + sat.toString() + " refers to IOD " + std::to_string(o.iod) +
                                   ", which no (healthy) broadcast record has");
  const auto clock = ssr_->clock(sat, t);
  if (!clock)
    return Answer::unavailable(clock.too_old ? EphemerisUnavailable::OutsideSpan : EphemerisUnavailable::SatelliteNotInProducts,
                               clock.reason);
  if (clock.entry->iod_ssr != orbit.entry->iod_ssr)
    return Answer::unavailable(EphemerisUnavailable::Gap, "SSR clock (IOD SSR " + std::to_string(clock.entry->iod_ssr) +
                                                              ") and orbit (IOD SSR " + std::to_string(orbit.entry->iod_ssr) +
                                                              ") of " + sat.toString() + " belong to different sets");

  SsrCorrectedState out;
  out.iod = o.iod;
  out.broadcast = stateOf(*rec, t);
  const Eigen::Vector3d& r = out.broadcast.position_ecef_m;
  const Eigen::Vector3d& v = out.broadcast.velocity_ecef_mps;
  const Eigen::Vector3d e_a = v.normalized();
  const Eigen::Vector3d e_c = r.cross(v).normalized();
  const Eigen::Vector3d e_r = e_a.cross(e_c);
  const double dt_o = t - orbit.entry->t0;
  out.orbit_age_s = dt_o;
  out.correction_rac_m = Eigen::Vector3d(o.radial_m + o.radial_dot_mps * dt_o, o.along_m + o.along_dot_mps * dt_o,
                                         o.cross_m + o.cross_dot_mps * dt_o);
  const Eigen::Vector3d rate_rac(o.radial_dot_mps, o.along_dot_mps, o.cross_dot_mps);
  out.position_ecef_m = r - (e_r * out.correction_rac_m.x() + e_a * out.correction_rac_m.y() + e_c * out.correction_rac_m.z());
  out.velocity_ecef_mps = v - (e_r * rate_rac.x() + e_a * rate_rac.y() + e_c * rate_rac.z());

  const SsrClockCorrection& c = clock.entry->value;
  const double dt_c = t - clock.entry->t0;
  out.clock_age_s = dt_c;
  double dc_m = c.c0_m + c.c1_m_per_s * dt_c + c.c2_m_per_s2 * dt_c * dt_c;
  if (options_.use_high_rate_clock) {
    const auto hr = ssr_->highRateClock(sat, t);
    if (hr && hr.entry->iod_ssr == clock.entry->iod_ssr && !(hr.entry->t0 < clock.entry->t0))
      dc_m += hr.entry->value.clock_m;
  }
  out.clock_correction_m = dc_m;
  out.clock_s = polynomialClock_s(*rec, out.broadcast) + dc_m / kSpeedOfLight_mps;
  out.clock_drift_s_per_s = out.broadcast.clock_drift_sps + (c.c1_m_per_s + 2.0 * c.c2_m_per_s2 * dt_c) / kSpeedOfLight_mps;
  return Answer::success(out);
}

EphemerisAnswer<EphemerisClock> BroadcastSsrEphemeris::satelliteClock(const SatelliteId& sat, const GnssTime& t) const {
  const auto s = correctedState(sat, t);
  if (!s.ok()) return EphemerisAnswer<EphemerisClock>::unavailable(s.reason, s.detail);
  EphemerisClock c;
  c.clock_bias_s = s.value->clock_s;
  c.clock_drift_s_per_s = s.value->clock_drift_s_per_s;
  return EphemerisAnswer<EphemerisClock>::success(c);
}

EphemerisAnswer<EphemerisOrbit> BroadcastSsrEphemeris::satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const {
  const auto s = correctedState(sat, t);
  if (!s.ok()) return EphemerisAnswer<EphemerisOrbit>::unavailable(s.reason, s.detail);
  EphemerisOrbit o;
  o.position_ecef_m = s.value->position_ecef_m;
  o.velocity_ecef_mps = s.value->velocity_ecef_mps;
  o.reference = options_.reference;
  return EphemerisAnswer<EphemerisOrbit>::success(o);
}

std::string BroadcastSsrEphemeris::describeSource() const {
  return std::string("broadcast navigation records with SSR corrections (orbits at the ") +
         std::string(ephemerisReferenceName(options_.reference)) + ")";
}

}  // namespace ppp
