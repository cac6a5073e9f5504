#include "ppp_bayes_tree/simulation/gps_constellation.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "ppp_bayes_tree/simulation/random_stream.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

WalkerConstellation::WalkerConstellation(WalkerConstellationOptions o) : options_(o) {
  if (o.satellites < 1 || o.satellites > 36 || o.planes < 1 || o.planes > o.satellites)
    throw std::invalid_argument("Walker constellation: 1..36 satellites and 1..satellites planes");
  if (!(o.gm_m3ps2 > 0.0) || !(o.semi_major_axis_m > 0.0))
    throw std::invalid_argument("Walker constellation: GM and semi-major axis must be positive");
  const int T = o.satellites, P = o.planes;
  std::vector<int> in_plane(static_cast<std::size_t>(P), 0);
  for (int k = 0; k < T; ++k) ++in_plane[static_cast<std::size_t>(k % P)];
  std::vector<int> slot(static_cast<std::size_t>(P), 0);
  for (int k = 0; k < T; ++k) {
    const int plane = k % P;
    const int n = in_plane[static_cast<std::size_t>(plane)];
    const int j = slot[static_cast<std::size_t>(plane)]++;
    KeplerianElements e;
    e.satellite = SatelliteId{o.system, k + 1};
    e.semi_major_axis_m = o.semi_major_axis_m;
    e.eccentricity = o.eccentricity;
    e.inclination_rad = o.inclination_rad;
    e.raan_rad = o.raan_offset_rad + 2.0 * kPi * plane / P;
    e.argument_of_perigee_rad = 0.0;
    e.mean_anomaly_rad = o.mean_anomaly_offset_rad + 2.0 * kPi * j / n + 2.0 * kPi * o.phasing * plane / T;
    elements_.push_back(e);
  }
}

WalkerConstellationOptions galileoWalkerOptions() {
  WalkerConstellationOptions o;
  o.system = GnssSystem::Galileo;
  o.gm_m3ps2 = kGmGalileo_m3ps2;
  o.satellites = 24;
  o.planes = 3;
  o.phasing = 1;
  o.semi_major_axis_m = kWgs84SemiMajorAxis_m + kGalileoAltitude_m;
  o.inclination_rad = 56.0 * kDegToRad;
  return o;
}

double WalkerConstellation::period_s() const {
  const double a = options_.semi_major_axis_m;
  return 2.0 * kPi * std::sqrt(a * a * a / options_.gm_m3ps2);
}

void WalkerConstellation::state(std::size_t i, const GnssTime& t, Eigen::Vector3d& position,
                                Eigen::Vector3d& velocity) const {
  const KeplerianElements& e = elements_.at(i);
  const double dt = t - options_.reference_time;
  const double a = e.semi_major_axis_m, ecc = e.eccentricity;
  const double gm = options_.gm_m3ps2;
  const double n = std::sqrt(gm / (a * a * a));
  const double M = std::remainder(e.mean_anomaly_rad + n * dt, 2.0 * kPi);
  double E = M;  // Kepler's equation by Newton iteration
  for (int it = 0; it < 20; ++it) {
    const double d = (E - ecc * std::sin(E) - M) / (1.0 - ecc * std::cos(E));
    E -= d;
    if (std::abs(d) < 1e-15) break;
  }
  const double cosE = std::cos(E), sinE = std::sin(E);
  const double r_pf_x = a * (cosE - ecc), r_pf_y = a * std::sqrt(1.0 - ecc * ecc) * sinE;
  const double rdot_factor = std::sqrt(gm * a) / (a * (1.0 - ecc * cosE));
  const double v_pf_x = -rdot_factor * sinE, v_pf_y = rdot_factor * std::sqrt(1.0 - ecc * ecc) * cosE;
  // Perifocal -> inertial: R3(-RAAN) R1(-i) R3(-omega).
  const double cO = std::cos(e.raan_rad), sO = std::sin(e.raan_rad), ci = std::cos(e.inclination_rad),
               si = std::sin(e.inclination_rad), cw = std::cos(e.argument_of_perigee_rad),
               sw = std::sin(e.argument_of_perigee_rad);
  Eigen::Matrix<double, 3, 2> Q;
  Q << cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci,  //
      sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci,   //
      sw * si, cw * si;
  const Eigen::Vector3d r_i = Q * Eigen::Vector2d(r_pf_x, r_pf_y);
  const Eigen::Vector3d v_i = Q * Eigen::Vector2d(v_pf_x, v_pf_y);
  const double theta = kEarthRotationRate_radps * dt;
  Eigen::Matrix3d R;
  R << std::cos(theta), std::sin(theta), 0, -std::sin(theta), std::cos(theta), 0, 0, 0, 1;
  position = R * r_i;
  velocity = R * v_i - Eigen::Vector3d(0, 0, kEarthRotationRate_radps).cross(position);
}

namespace {

Sp3Header productHeader(const GnssTime& first, double interval, std::size_t epochs,
                        const std::vector<SatelliteId>& sats) {
  Sp3Header h;
  h.version = 'c';
  h.pv_flag = 'P';
  h.first_epoch = first;
  h.first_epoch_calendar = first.toCalendar(TimeSystem::GPS);
  h.epoch_count = static_cast<long long>(epochs);
  h.data_used = "ORBIT";
  h.coordinate_system = "IGS20";
  h.orbit_type = "FIT";
  h.agency = "SIM";
  h.interval_s = interval;
  h.satellites = sats;
  h.position_base = 1.25;  // usual SP3 bases (IGS)
  h.clock_base = 1.025;
  return h;
}

RinexClockHeader clockHeader(const std::vector<SatelliteId>& sats) {
  RinexClockHeader h;
  h.version_text = "3.00";
  h.version = 3.0;
  // One system per call (one constellation, or real products' GPS part);
  // mergeProducts() marks a merged header 'M'.
  h.satellite_system = sats.empty() ? 'G' : systemLetter(sats.front().system);
  h.program = "ppp_simulate";
  h.run_by = "ppp_bayes_tree";
  h.data_types = {"AS"};
  h.analysis_center_id = "SIM";
  h.analysis_center_name = "ppp_bayes_tree simulator";
  h.satellite_count = static_cast<int>(sats.size());
  h.prn_list = sats;
  return h;
}

}  // namespace

TruthProducts sampleWalkerProducts(const WalkerConstellation& constellation, const ProductSampling& s,
                                   std::uint64_t clock_seed) {
  if (!(s.orbit_interval_s > 0) || !(s.clock_interval_s > 0) || !(s.first < s.last))
    throw std::invalid_argument("product sampling: positive intervals and first < last");
  TruthProducts out;
  RandomStream rng(clock_seed);
  std::vector<SatelliteId> sats;
  std::vector<double> bias, drift;
  for (const auto& e : constellation.satellites()) {
    sats.push_back(e.satellite);
    bias.push_back(rng.uniform(-5e-4, 5e-4));
    drift.push_back(rng.uniform(-1e-11, 1e-11));
  }
  auto clockAt = [&](std::size_t i, const GnssTime& t) { return bias[i] + drift[i] * (t - s.first); };
  const auto n_orbit = static_cast<std::size_t>(std::floor((s.last - s.first) / s.orbit_interval_s + 1e-9)) + 1;
  out.orbits.header = productHeader(s.first, s.orbit_interval_s, n_orbit, sats);
  for (std::size_t k = 0; k < n_orbit; ++k) {
    const GnssTime t = s.first + static_cast<double>(k) * s.orbit_interval_s;
    out.orbits.epochs.push_back(t);
    for (std::size_t i = 0; i < sats.size(); ++i) {
      Sp3Record r;
      r.time = t;
      Eigen::Vector3d p, v;
      constellation.state(i, t, p, v);
      r.position_ecef_m = p;
      r.clock_bias_s = clockAt(i, t);
      out.orbits.satellites[sats[i]].push_back(r);
    }
  }
  out.orbits.complete = true;
  out.clocks.header = clockHeader(sats);
  const auto n_clock = static_cast<std::size_t>(std::floor((s.last - s.first) / s.clock_interval_s + 1e-9)) + 1;
  for (std::size_t k = 0; k < n_clock; ++k) {
    const GnssTime t = s.first + static_cast<double>(k) * s.clock_interval_s;
    for (std::size_t i = 0; i < sats.size(); ++i) {
      ClockRecord c;
      c.time = t;
      c.clock_bias_s = clockAt(i, t);
      out.clocks.satellite_clocks[sats[i]].push_back(c);
    }
  }
  return out;
}

void mergeProducts(TruthProducts& into, const TruthProducts& other) {
  if (into.orbits.epochs != other.orbits.epochs)
    throw std::invalid_argument("mergeProducts: the orbit samples differ in their epochs");
  for (const auto& [sat, recs] : other.orbits.satellites) {
    into.orbits.satellites[sat] = recs;
    into.orbits.header.satellites.push_back(sat);
  }
  for (const auto& [sat, recs] : other.clocks.satellite_clocks) {
    into.clocks.satellite_clocks[sat] = recs;
    into.clocks.header.prn_list.push_back(sat);
  }
  into.clocks.header.satellite_count = static_cast<int>(into.clocks.header.prn_list.size());
  if (other.clocks.header.satellite_system != into.clocks.header.satellite_system)
    into.clocks.header.satellite_system = 'M';
}

TruthProducts restrictProducts(const Sp3File& sp3, const RinexClockFile& clk, const GnssTime& first,
                               const GnssTime& last) {
  TruthProducts out;
  std::vector<SatelliteId> sats;
  for (const auto& [sat, recs] : sp3.satellites) {
    if (sat.system != GnssSystem::GPS) continue;
    std::vector<Sp3Record> kept;
    for (const auto& r : recs)
      if (r.time >= first && r.time <= last && r.position_ecef_m) kept.push_back(r);
    if (kept.empty()) continue;
    sats.push_back(sat);
    out.orbits.satellites[sat] = std::move(kept);
  }
  for (const auto& t : sp3.epochs)
    if (t >= first && t <= last) out.orbits.epochs.push_back(t);
  if (out.orbits.epochs.empty()) throw std::invalid_argument("the SP3 file has no epoch in the flight span");
  out.orbits.header = productHeader(out.orbits.epochs.front(), sp3.header.interval_s, out.orbits.epochs.size(), sats);
  out.orbits.header.coordinate_system = sp3.header.coordinate_system;
  out.orbits.complete = true;
  std::vector<SatelliteId> clock_sats;
  for (const auto& [sat, recs] : clk.satellite_clocks) {
    if (sat.system != GnssSystem::GPS) continue;
    std::vector<ClockRecord> kept;
    for (const auto& r : recs)
      if (r.time >= first && r.time <= last) {
        ClockRecord c;
        c.time = r.time;
        c.clock_bias_s = r.clock_bias_s;
        kept.push_back(c);
      }
    if (kept.empty()) continue;
    clock_sats.push_back(sat);
    out.clocks.satellite_clocks[sat] = std::move(kept);
  }
  out.clocks.header = clockHeader(clock_sats);
  return out;
}

}  // namespace ppp
