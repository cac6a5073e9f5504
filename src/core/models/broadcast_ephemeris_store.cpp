#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"

namespace ppp {

namespace {

const GnssTime& referenceTime(const GpsLnavEphemeris& e) { return e.orbit.toe; }
const GnssTime& referenceTime(const GalileoEphemeris& e) { return e.orbit.toe; }
const GnssTime& referenceTime(const GlonassEphemeris& e) { return e.tb; }
const GnssTime& referenceTime(const BeidouEphemeris& e) { return e.orbit.toe; }

int issueOfData(const GpsLnavEphemeris& e) { return e.iode; }
int issueOfData(const GalileoEphemeris& e) { return e.iod_nav * 2 + (e.type == GalileoNavType::FNav); }
int issueOfData(const GlonassEphemeris&) { return 0; }
int issueOfData(const BeidouEphemeris& e) { return e.aode; }

std::string hours(double seconds) {
  std::ostringstream os;
  os.precision(2);
  os << std::fixed << seconds / 3600.0 << " h";
  return os.str();
}

template <typename Record>
void insertUnique(std::vector<Record>& list, const Record& eph) {
  for (const Record& r : list) {
    if (referenceTime(r) == referenceTime(eph) && issueOfData(r) == issueOfData(eph)) return;
  }
  list.push_back(eph);
}

// Nearest-toe choice among records for one satellite. `half_window` gives the
// validity half-width of a record; `usable` filters by message type.
template <typename Record, typename HalfWindow, typename Usable>
EphemerisLookup<Record> select(const std::map<SatelliteId, std::vector<Record>>& store,
                               const SatelliteId& sat, const GnssTime& t, bool allow_unhealthy,
                               HalfWindow half_window, Usable usable) {
  EphemerisLookup<Record> out;
  const auto it = store.find(sat);
  if (it == store.end() || it->second.empty()) {
    out.unavailable_reason = "no broadcast record for " + sat.toString();
    return out;
  }
  const Record* best = nullptr;
  double best_distance = 0.0;
  double nearest_any = INFINITY;
  int in_window = 0, unhealthy = 0, wrong_type = 0;
  for (const Record& r : it->second) {
    const double d = std::fabs(t - referenceTime(r));
    nearest_any = std::fmin(nearest_any, d);
    if (d > half_window(r)) continue;
    ++in_window;
    if (!usable(r)) {
      ++wrong_type;
      continue;
    }
    if (!allow_unhealthy && !isHealthy(r)) {
      ++unhealthy;
      continue;
    }
    if (best == nullptr || d < best_distance ||
        (d == best_distance && referenceTime(r) > referenceTime(*best))) {
      best = &r;
      best_distance = d;
    }
  }
  if (best != nullptr) {
    out.record = best;
    return out;
  }
  std::ostringstream why;
  why << sat.toString() << " at " << t.toString() << ": ";
  if (in_window == 0) {
    why << "nearest record is " << hours(nearest_any) << " away, outside its validity interval";
  } else if (unhealthy == in_window) {
    why << "all " << unhealthy << " record(s) in the validity interval are flagged unhealthy";
  } else {
    why << in_window << " record(s) in the validity interval: " << wrong_type
        << " of the wrong message type or not yet received, " << unhealthy << " unhealthy";
  }
  out.unavailable_reason = why.str();
  return out;
}

}  // namespace

void BroadcastEphemerisStore::add(const NavData& nav) {
  for (const auto& e : nav.gps) add(e);
  for (const auto& e : nav.galileo) add(e);
  for (const auto& e : nav.glonass) add(e);
  for (const auto& e : nav.beidou) add(e);
}

template <typename Record>
bool BroadcastEphemerisStore::receivedBy(const Record& r, const GnssTime& t) const {
  if (received_.empty()) return true;
  const auto it = received_.find(ReceivedKey{r.satellite, referenceTime(r), issueOfData(r)});
  return it == received_.end() || it->second < t;
}

template <typename Record>
void BroadcastEphemerisStore::noteReceived(const Record& r, const std::optional<GnssTime>& received_at) {
  if (!received_at) return;
  received_.emplace(ReceivedKey{r.satellite, referenceTime(r), issueOfData(r)}, *received_at);
}

template <typename Record>
std::optional<std::string> BroadcastEphemerisStore::addReceived(std::map<SatelliteId, std::vector<Record>>& store,
                                                                const Record& eph,
                                                                const std::optional<GnssTime>& received_at) {
  const std::size_t before = store[eph.satellite].size();
  auto why = add(eph);
  if (!why && store[eph.satellite].size() > before) noteReceived(eph, received_at);
  return why;
}

std::optional<std::string> BroadcastEphemerisStore::add(const GpsLnavEphemeris& eph,
                                                        std::optional<GnssTime> received_at) {
  return addReceived(gps_, eph, received_at);
}

std::optional<std::string> BroadcastEphemerisStore::add(const GalileoEphemeris& eph,
                                                        std::optional<GnssTime> received_at) {
  return addReceived(galileo_, eph, received_at);
}

std::optional<std::string> BroadcastEphemerisStore::add(const GlonassEphemeris& eph,
                                                        std::optional<GnssTime> received_at) {
  return addReceived(glonass_, eph, received_at);
}

std::optional<std::string> BroadcastEphemerisStore::add(const BeidouEphemeris& eph,
                                                        std::optional<GnssTime> received_at) {
  return addReceived(beidou_, eph, received_at);
}

namespace {
template <typename Record, typename Received>
std::size_t dropOld(std::map<SatelliteId, std::vector<Record>>& store, const GnssTime& t, double keep_s,
                    Received& received) {
  std::size_t n = 0;
  for (auto& [sat, list] : store) {
    for (auto it = list.begin(); it != list.end();) {
      if (t - referenceTime(*it) > keep_s) {
        received.erase({it->satellite, referenceTime(*it), issueOfData(*it)});
        it = list.erase(it);
        ++n;
      } else {
        ++it;
      }
    }
  }
  return n;
}
}  // namespace

std::size_t BroadcastEphemerisStore::dropOlderThan(const GnssTime& t, double keep_s) {
  return dropOld(gps_, t, keep_s, received_) + dropOld(galileo_, t, keep_s, received_) +
         dropOld(glonass_, t, keep_s, received_) + dropOld(beidou_, t, keep_s, received_);
}

std::optional<std::string> BroadcastEphemerisStore::add(const GpsLnavEphemeris& eph) {
  if (auto why = checkKeplerOrbit(eph.orbit)) return why;
  if (eph.satellite.system != GnssSystem::GPS && eph.satellite.system != GnssSystem::QZSS) {
    return std::string("LNAV record for a satellite that is neither GPS nor QZSS");
  }
  insertUnique(gps_[eph.satellite], eph);
  return std::nullopt;
}

std::optional<std::string> BroadcastEphemerisStore::add(const GalileoEphemeris& eph) {
  if (auto why = checkKeplerOrbit(eph.orbit)) return why;
  if (eph.satellite.system != GnssSystem::Galileo) return std::string("not a Galileo satellite");
  insertUnique(galileo_[eph.satellite], eph);
  return std::nullopt;
}

std::optional<std::string> BroadcastEphemerisStore::add(const GlonassEphemeris& eph) {
  if (auto why = checkGlonassState(eph)) return why;
  if (eph.satellite.system != GnssSystem::GLONASS) return std::string("not a GLONASS satellite");
  insertUnique(glonass_[eph.satellite], eph);
  return std::nullopt;
}

std::optional<std::string> BroadcastEphemerisStore::add(const BeidouEphemeris& eph) {
  if (auto why = checkKeplerOrbit(eph.orbit)) return why;
  if (eph.satellite.system != GnssSystem::BeiDou) return std::string("not a BeiDou satellite");
  insertUnique(beidou_[eph.satellite], eph);
  return std::nullopt;
}

EphemerisLookup<GpsLnavEphemeris> BroadcastEphemerisStore::gps(const SatelliteId& sat,
                                                               const GnssTime& t) const {
  return select(
      gps_, sat, t, options_.allow_unhealthy,
      [](const GpsLnavEphemeris& e) { return 0.5 * e.fit_interval_h * 3600.0; },
      [this, &t](const GpsLnavEphemeris& e) { return receivedBy(e, t); });
}

EphemerisLookup<GalileoEphemeris> BroadcastEphemerisStore::galileo(const SatelliteId& sat,
                                                                   const GnssTime& t) const {
  const GalileoPreference pref = options_.galileo;
  const double max_age = options_.galileo_max_age_s;
  return select(
      galileo_, sat, t, options_.allow_unhealthy,
      [max_age](const GalileoEphemeris&) { return max_age; },
      [this, &t, pref](const GalileoEphemeris& e) {
        return (pref == GalileoPreference::Any ||
                (pref == GalileoPreference::INavOnly) == (e.type == GalileoNavType::INav)) &&
               receivedBy(e, t);
      });
}

EphemerisLookup<GlonassEphemeris> BroadcastEphemerisStore::glonass(const SatelliteId& sat,
                                                                   const GnssTime& t) const {
  const double max_age = options_.glonass_max_age_s;
  return select(
      glonass_, sat, t, options_.allow_unhealthy,
      [max_age](const GlonassEphemeris&) { return max_age; },
      [this, &t](const GlonassEphemeris& e) { return receivedBy(e, t); });
}

EphemerisLookup<BeidouEphemeris> BroadcastEphemerisStore::beidou(const SatelliteId& sat,
                                                                 const GnssTime& t) const {
  const double max_age = options_.beidou_max_age_s;
  return select(
      beidou_, sat, t, options_.allow_unhealthy,
      [max_age](const BeidouEphemeris&) { return max_age; },
      [this, &t](const BeidouEphemeris& e) { return receivedBy(e, t); });
}

namespace {

/// Calls f with the store's lookup of `sat` at `t` (one branch on the system:
/// each system's record is its own type and model); nullopt for a system
/// without broadcast orbits here.
template <typename F>
auto visitLookup(const BroadcastEphemerisStore& store, const SatelliteId& sat, const GnssTime& t, F&& f)
    -> std::optional<decltype(f(store.gps(sat, t)))> {
  switch (sat.system) {
    case GnssSystem::GPS:
    case GnssSystem::QZSS: return f(store.gps(sat, t));
    case GnssSystem::Galileo: return f(store.galileo(sat, t));
    case GnssSystem::GLONASS: return f(store.glonass(sat, t));
    case GnssSystem::BeiDou: return f(store.beidou(sat, t));
    default: return std::nullopt;
  }
}

std::string notModelled(const SatelliteId& sat) {
  return sat.toString() + ": broadcast orbits of " + std::string(systemName(sat.system)) + " are not modelled";
}

// What the EphemerisSource answers beside the state, per record type.

/// Orbit sigma: the record's URA (GPS/QZSS, BeiDou) or SISA (Galileo); GLONASS records carry none.
std::optional<double> positionSigma_m(const GpsLnavEphemeris& e) { return e.ura_m; }
std::optional<double> positionSigma_m(const GalileoEphemeris& e) { return e.sisa_m; }
std::optional<double> positionSigma_m(const GlonassEphemeris&) { return std::nullopt; }
std::optional<double> positionSigma_m(const BeidouEphemeris& e) { return e.ura_m; }

/// GPS, QZSS, Galileo and BeiDou broadcast orbits refer to the antenna phase
/// centre (the control segments' convention, also that of RTCM SSR); GLONASS to
/// the centre of mass.
template <typename Record>
EphemerisReference orbitReference(const Record&) { return EphemerisReference::AntennaPhaseCentre; }
EphemerisReference orbitReference(const GlonassEphemeris&) { return EphemerisReference::CentreOfMass; }

/// What the ionosphere-free pair's clock lacks against the record's clock [s]:
/// none where the record's clock is that pair's (GPS L1/L2 P(Y); Galileo I/NAV
/// E1/E5b, the E1/E5a BGD not applied; GLONASS). BeiDou: the clock refers to
/// B3I and B1I sees it minus TGD1 (BDS-SIS-ICD-B1I 3.0, 5.2.4.10), so the
/// B1I/B3I ionosphere-free combination sees it minus f1^2 / (f1^2 - f3^2) TGD1.
template <typename Record>
double ionosphereFreeClockOffset_s(const Record&) { return 0.0; }
double ionosphereFreeClockOffset_s(const BeidouEphemeris& e) {
  const double f1 = *carrierFrequency_hz(GnssSystem::BeiDou, '2'), f3 = *carrierFrequency_hz(GnssSystem::BeiDou, '6');
  return f1 * f1 / (f1 * f1 - f3 * f3) * e.tgd1_s;
}

}  // namespace

BroadcastLookup BroadcastEphemerisStore::state(const SatelliteId& sat, const GnssTime& t) const {
  const auto out = visitLookup(*this, sat, t, [&t](const auto& lookup) {
    BroadcastLookup l;
    if (!lookup) l.unavailable_reason = lookup.unavailable_reason;
    else l.state = satelliteState(*lookup.record, t);
    return l;
  });
  if (out) return *out;
  BroadcastLookup l;
  l.unavailable_reason = notModelled(sat);
  return l;
}

EphemerisAnswer<EphemerisClock> BroadcastEphemerisStore::satelliteClock(const SatelliteId& sat,
                                                                         const GnssTime& t) const {
  using A = EphemerisAnswer<EphemerisClock>;
  const auto out = visitLookup(*this, sat, t, [&t](const auto& lookup) {
    if (!lookup) return A::unavailable(EphemerisUnavailable::NoValidRecord, lookup.unavailable_reason);
    const BroadcastState s = satelliteState(*lookup.record, t);
    // The rate of the relativistic term is left in the drift (a few 1e-12 s/s).
    return A::success({s.clock_bias_s - s.relativistic_s - ionosphereFreeClockOffset_s(*lookup.record),
                       s.clock_drift_sps, std::nullopt});
  });
  return out ? *out : A::unavailable(EphemerisUnavailable::SystemNotModelled, notModelled(sat));
}

EphemerisAnswer<EphemerisOrbit> BroadcastEphemerisStore::satelliteOrbit(const SatelliteId& sat,
                                                                         const GnssTime& t) const {
  using A = EphemerisAnswer<EphemerisOrbit>;
  const auto out = visitLookup(*this, sat, t, [&t](const auto& lookup) {
    if (!lookup) return A::unavailable(EphemerisUnavailable::NoValidRecord, lookup.unavailable_reason);
    const BroadcastState s = satelliteState(*lookup.record, t);
    return A::success(EphemerisOrbit{s.position_ecef_m, s.velocity_ecef_mps, orbitReference(*lookup.record),
                                     positionSigma_m(*lookup.record)});
  });
  return out ? *out : A::unavailable(EphemerisUnavailable::SystemNotModelled, notModelled(sat));
}

std::size_t BroadcastEphemerisStore::size() const {
  std::size_t n = 0;
  for (const auto& [sat, list] : gps_) n += list.size();
  for (const auto& [sat, list] : galileo_) n += list.size();
  for (const auto& [sat, list] : glonass_) n += list.size();
  for (const auto& [sat, list] : beidou_) n += list.size();
  return n;
}

}  // namespace ppp
