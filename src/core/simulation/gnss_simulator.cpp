#include "ppp_bayes_tree/simulation/gnss_simulator.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/models/troposphere.h"
#include "ppp_bayes_tree/simulation/random_stream.h"
#include "ppp_bayes_tree/simulation/simulation_writers.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

SimulatedBands simulatedIonosphereFreeBands(GnssSystem system) {
  return system == GnssSystem::GPS ? SimulatedBands{'1', '2'} : SimulatedBands{'1', '5'};
}

namespace {

// Sub-stream tags of the seed (RandomStream::derive), one per purpose, so that
// switching one error term on or off leaves the others' numbers unchanged.
enum StreamTag : std::uint64_t {
  kTagConstellation = 1,
  kTagSatelliteClocks,
  kTagTroposphere,
  kTagIonosphere,
  kTagReceiverClock,
  kTagProducts,
  kTagGalileoConstellation,
  kTagGalileoClocks,
  kTagGalileoClockOffset,
  kTagImu,
  kTagPerSatellite = 1000,  // GPS: + 100 * term + satellite index (< 1000)
  kTagPerOtherSatellite = 1000000,  // other systems: + 1000 * satellite index + 100 * term
};

/// The dual-frequency signals simulated for a system: GPS C1C/L1C/C1W/C2W/L2W
/// (the IF code of C1W/C2W), Galileo E1/E5a C1C/L1C/C5Q/L5Q.
struct SystemSignals {
  double f1 = 0.0, f2 = 0.0, lambda1 = 0.0, lambda2 = 0.0, gamma = 0.0;
  IonosphereFreeCoefficients k_if{};
  ObservationCode code1, code2, phase1, phase2;
  std::vector<ObservationCode> obs_types;  // RINEX order; C1C carries the band-1 code
  double phase_sigma1 = 0.0, phase_sigma2 = 0.0;
};

SystemSignals systemSignals(GnssSystem system, const ErrorModelConfig::Thermal& th) {
  SystemSignals g;
  const bool gps = system == GnssSystem::GPS;
  const SimulatedBands bands = simulatedIonosphereFreeBands(system);
  g.f1 = *carrierFrequency_hz(system, bands.band1);
  g.f2 = *carrierFrequency_hz(system, bands.band2);
  g.lambda1 = kSpeedOfLight_mps / g.f1;
  g.lambda2 = kSpeedOfLight_mps / g.f2;
  g.gamma = (g.f1 * g.f1) / (g.f2 * g.f2);
  g.k_if = ionosphereFreeCoefficients(g.f1, g.f2);
  const ObservationCode c1c = *ObservationCode::parse("C1C"), l1c = *ObservationCode::parse("L1C");
  if (gps) {
    g.code1 = *ObservationCode::parse("C1W");
    g.code2 = *ObservationCode::parse("C2W");
    g.phase1 = l1c;
    g.phase2 = *ObservationCode::parse("L2W");
    g.obs_types = {c1c, l1c, g.code1, g.code2, g.phase2};
  } else {
    g.code1 = c1c;
    g.code2 = *ObservationCode::parse("C5Q");
    g.phase1 = l1c;
    g.phase2 = *ObservationCode::parse("L5Q");
    g.obs_types = {c1c, l1c, g.code2, g.phase2};
  }
  g.phase_sigma1 = !th.enabled ? 0.0 : th.phase_mode == PhaseNoiseMode::FixedSigma ? th.phase_sigma_m
                                                                                   : th.phase_sigma_cycles * g.lambda1;
  g.phase_sigma2 = !th.enabled ? 0.0 : th.phase_mode == PhaseNoiseMode::FixedSigma ? th.phase_sigma_m
                                                                                   : th.phase_sigma_cycles * g.lambda2;
  return g;
}
enum SatelliteTerm : std::uint64_t { kSatAmbiguity = 0, kSatMultipath, kSatThermal, kSatPhaseBias };

constexpr double kIonosphereConstant = 40.3e16;  // m^3/s^2 per TECU (first-order term 40.3 TEC / f^2)
constexpr double kEarthRadiusIonosphere_m = 6371.0e3;

double quantize(double v, bool on) { return on ? std::round(v * 1000.0) / 1000.0 : v; }

GnssTime floorTo(const GnssTime& t, double interval_s) {
  const auto step = static_cast<std::int64_t>(std::llround(interval_s));
  if (step <= 0 || std::abs(interval_s - static_cast<double>(step)) > 1e-9) return t;
  std::int64_t w = t.wholeSeconds();
  w -= ((w % step) + step) % step;
  return GnssTime::fromGpsSeconds(w);
}

/// Reads an SP3 / clock text back with our readers (the in-process products
/// are exactly what a file reader sees).
PreciseEphemeris productsFromText(const std::string& sp3_text, const std::string& clk_text, const std::string& name) {
  PreciseEphemeris eph;
  auto sp3_src = memoryLineSource(sp3_text, name + ".sp3");
  const Sp3File sp3 = readSp3(*sp3_src);
  auto clk_src = memoryLineSource(clk_text, name + ".clk");
  const RinexClockFile clk = readRinexClock(*clk_src);
  if (!sp3.report.clean() || !clk.report.clean())
    throw std::logic_error("simulator: written products do not read back cleanly: " + sp3.report.summary() +
                           clk.report.summary());
  eph.addOrbits(sp3);
  eph.addClocks(clk);
  return eph;
}

/// SP3 writes a position component of 0.000000 km only as the "absent" marker
/// (SP3-d, position record): move a component closer than 0.5 mm to zero to
/// +-1 mm (probability ~1e-10 per value; the truth is what is written).
void avoidSp3ZeroMarker(Sp3File& sp3) {
  for (auto& [sat, recs] : sp3.satellites)
    for (auto& r : recs)
      if (r.position_ecef_m)
        for (int i = 0; i < 3; ++i)
          if (std::abs((*r.position_ecef_m)(i)) < 5e-4) (*r.position_ecef_m)(i) = (*r.position_ecef_m)(i) < 0 ? -1e-3 : 1e-3;
}

struct ProductErrorSet {
  Eigen::Vector3d orbit_m = Eigen::Vector3d::Zero();  // Independent: ECEF; AnalysisCentre: radial, along, cross
  double clock_m = 0.0;                               // Independent: all of it; AnalysisCentre: the residual
  double orbit_scale = 0.0, clock_scale = 0.0;        // k of 1 + k (t - t_mid) / T
};

/// Step a of the product errors: one set per satellite, drawn by the model.
ProductErrorSet drawProductErrors(const ErrorModelConfig::Products& cfg, RandomStream r) {
  ProductErrorSet e;
  if (cfg.model == ErrorModelConfig::ProductErrorModel::AnalysisCentre) {
    const double radial_m = r.normal(cfg.radial_sigma_m);
    const double along_m = r.normal(cfg.along_sigma_m);
    const double cross_m = r.normal(cfg.cross_sigma_m);
    e.orbit_m = Eigen::Vector3d(radial_m, along_m, cross_m);
    e.clock_m = r.normal(cfg.clock_residual_sigma_m);
  } else {
    // One draw per statement: the order of a call's arguments is unspecified, so three
    // draws as constructor arguments gave other errors with another compiler. The order
    // z, y, x is the one of the existing simulated data sets.
    const double orbit_z_m = r.normal(cfg.orbit_sigma_m);
    const double orbit_y_m = r.normal(cfg.orbit_sigma_m);
    const double orbit_x_m = r.normal(cfg.orbit_sigma_m);
    e.orbit_m = Eigen::Vector3d(orbit_x_m, orbit_y_m, orbit_z_m);
    e.clock_m = r.normal(cfg.clock_sigma_m);
  }
  e.orbit_scale = r.uniform(-cfg.scale_half_range, cfg.scale_half_range);
  e.clock_scale = r.uniform(-cfg.scale_half_range, cfg.scale_half_range);
  return e;
}

/// The satellite's radial / along-track / cross-track axes (columns) at record i, the
/// velocity from the neighbouring records where the record has none.
std::optional<Eigen::Matrix3d> radialAlongCross(const std::vector<Sp3Record>& recs, std::size_t i) {
  const Eigen::Vector3d& r = *recs[i].position_ecef_m;
  Eigen::Vector3d v;
  if (recs[i].velocity_ecef_mps) {
    v = *recs[i].velocity_ecef_mps;
  } else {
    const std::size_t a = i > 0 ? i - 1 : i, b = i + 1 < recs.size() ? i + 1 : i;
    if (a == b || !recs[a].position_ecef_m || !recs[b].position_ecef_m) return std::nullopt;
    v = (*recs[b].position_ecef_m - *recs[a].position_ecef_m) / (recs[b].time - recs[a].time);
  }
  Eigen::Matrix3d rac;
  rac.col(0) = r.normalized();
  rac.col(2) = r.cross(v).normalized();
  rac.col(1) = rac.col(2).cross(rac.col(0));
  return rac;
}

TruthProducts applyProductErrors(const TruthProducts& truth, const ErrorModelConfig::Products& cfg,
                                 RandomStream rng, const GnssTime& t_mid, double span_s,
                                 DrawnParameters& drawn) {
  TruthProducts out = truth;
  if (!cfg.enabled) return out;
  const bool centre = cfg.model == ErrorModelConfig::ProductErrorModel::AnalysisCentre;
  std::map<SatelliteId, ProductErrorSet> errors;
  std::set<SatelliteId> sats;
  for (const auto& [sat, recs] : truth.orbits.satellites) sats.insert(sat);
  for (const auto& [sat, recs] : truth.clocks.satellite_clocks) sats.insert(sat);
  double sum_orbit = 0.0, sum_clock = 0.0;
  for (const auto& sat : sats) {
    const ProductErrorSet e = drawProductErrors(cfg, rng.derive(static_cast<std::uint64_t>(sat.index())));
    const double clock_m = centre ? e.orbit_m(0) + e.clock_m : e.clock_m;
    sum_orbit += e.orbit_m.squaredNorm() / 3.0;
    sum_clock += clock_m * clock_m;
    errors[sat] = e;
  }
  drawn.orbit_error_rms_m = sats.empty() ? 0.0 : std::sqrt(sum_orbit / static_cast<double>(sats.size()));
  drawn.clock_error_rms_m = sats.empty() ? 0.0 : std::sqrt(sum_clock / static_cast<double>(sats.size()));
  auto scale = [&](double k, const GnssTime& t) { return 1.0 + k * (t - t_mid) / span_s; };
  // The clock error at t: independent, or the radial orbit error (with the orbit's
  // drift, so that it stays absorbed) plus the residual.
  auto clockError_m = [&](const ProductErrorSet& e, const GnssTime& t) {
    if (!centre) return e.clock_m * scale(e.clock_scale, t);
    return e.orbit_m(0) * scale(e.orbit_scale, t) + e.clock_m * scale(e.clock_scale, t);
  };
  for (auto& [sat, recs] : out.orbits.satellites) {
    const ProductErrorSet& e = errors[sat];
    const std::vector<Sp3Record>& truth_recs = truth.orbits.satellites.at(sat);  // the frame from the truth
    for (std::size_t i = 0; i < recs.size(); ++i) {
      Sp3Record& r = recs[i];
      if (r.position_ecef_m) {
        Eigen::Vector3d error_ecef_m = e.orbit_m;
        if (centre) {
          const auto rac = radialAlongCross(truth_recs, i);
          error_ecef_m = rac ? Eigen::Vector3d(*rac * e.orbit_m) : Eigen::Vector3d::Zero();
        }
        *r.position_ecef_m += error_ecef_m * scale(e.orbit_scale, r.time);
      }
      if (r.clock_bias_s) *r.clock_bias_s += clockError_m(e, r.time) / kSpeedOfLight_mps;
    }
  }
  for (auto& [sat, recs] : out.clocks.satellite_clocks) {
    const ProductErrorSet& e = errors[sat];
    for (auto& r : recs) r.clock_bias_s += clockError_m(e, r.time) / kSpeedOfLight_mps;
  }
  return out;
}

/// Receiver clock offsets [s] at the epochs.
std::vector<double> receiverClock(const std::vector<TrajectorySample>& traj, const ErrorModelConfig::ReceiverClock& c,
                                  RandomStream rng, DrawnParameters& drawn) {
  std::vector<double> dt(traj.size(), 0.0);
  if (!c.enabled || traj.empty()) return dt;
  drawn.clock_initial_s = rng.normal(c.initial_sigma_s);
  drawn.clock_drift_s_per_s = rng.normal(c.drift_sigma_s_per_s);
  double walk = 0.0, steps = 0.0;
  for (std::size_t k = 0; k < traj.size(); ++k) {
    const double since_start = traj[k].time - traj.front().time;
    if (k > 0) {
      const double h = traj[k].time - traj[k - 1].time;
      walk += rng.normal(c.random_walk_sigma_s * std::sqrt(h));
      if (rng.bernoulli(c.steps_per_hour * h / 3600.0)) {
        steps += rng.bernoulli(0.5) ? c.step_s : -c.step_s;
        ++drawn.clock_steps;
      }
    }
    dt[k] = drawn.clock_initial_s + drawn.clock_drift_s_per_s * since_start + walk + steps;
  }
  return dt;
}

/// Per-satellite tracking and error-process state.
struct SatelliteState {
  SatelliteState(SatelliteId s, RandomStream a, RandomStream m, RandomStream t)
      : sat(s), ambiguity_rng(a), multipath_rng(m), thermal_rng(t) {}
  SatelliteId sat;
  RandomStream ambiguity_rng, multipath_rng, thermal_rng;
  bool tracked = false;
  ArcId arc = 0;
  std::optional<GnssTime> visible_since;
  // Outage caused by the airframe mask (a phase break when reacquired).
  bool body_outage = false;
  GnssTime last_tracked;
  ArcId last_arc = 0;
  double outage_min_body_elevation = 0.0, outage_max_roll = 0.0;
  // Multipath Gauss-Markov states (zenith scale) and time of the last update.
  double mp1 = 0.0, mp2 = 0.0;
  GnssTime mp_time;
  bool first_epoch_of_arc = false;
};

using SignalTable = std::array<SystemSignals, kNumGnssSystems>;

const SystemSignals& signalsOf(const SignalTable& signals, GnssSystem system) {
  return signals[static_cast<int>(system)];
}

/// Step 1: the setup must be one the simulator can generate (throws std::invalid_argument).
void checkSimulationSetup(const SimulationConfig& config, const SimulationSources& sources) {
  if (!(config.rate_hz > 0.0)) throw std::invalid_argument("simulation: rate must be positive");
  if (sources.sp3.has_value() != sources.clk.has_value())
    throw std::invalid_argument("simulation: give both an SP3 and a clock file, or neither");
  for (GnssSystem sys : config.systems)
    if (sys != GnssSystem::GPS && sys != GnssSystem::Galileo)
      throw std::invalid_argument(std::string("simulation: system ") + std::string(systemName(sys)) +
                                  " is not simulated (GPS and Galileo only)");
  if (!config.simulates(GnssSystem::GPS))
    throw std::invalid_argument("simulation: GPS must be among the simulated systems (the reference clock)");
  if (config.simulates(GnssSystem::Galileo) && sources.sp3)
    throw std::invalid_argument("simulation: Galileo needs the nominal constellation (real SP3 products: GPS part only)");
}

/// Step 2a: the first epoch: the configured one, else 10 min after the start of
/// the given products (whole second), else 2026-05-13 10:00:00 GPST.
GnssTime flightStart(const SimulationConfig& config, const SimulationSources& sources) {
  if (config.start) return *config.start;
  if (sources.sp3) {
    GnssTime first = sources.sp3->epochs.empty() ? GnssTime() : sources.sp3->epochs.front();
    for (const auto& [sat, recs] : sources.clk->satellite_clocks)
      if (!recs.empty() && first < recs.front().time) first = recs.front().time;
    return floorTo(first + 600.0, 1.0);
  }
  return GnssTime::fromCalendar({2026, 5, 13, 10, 0, 0.0}, TimeSystem::GPS);
}

/// Step 2b: the trajectory: the user's, or the configured profile sampled from `start`.
std::vector<TrajectorySample> flightTrajectory(const SimulationConfig& config, const SimulationSources& sources,
                                               const GnssTime& start) {
  if (sources.trajectory) {
    if (sources.trajectory->size() < 2)
      throw std::invalid_argument("simulation: the trajectory has fewer than two samples");
    return *sources.trajectory;
  }
  TrajectoryOptions topt;
  topt.profile = config.profile;
  topt.start = start;
  topt.duration_s = config.durationOrDefault_s();
  topt.rate_hz = config.rate_hz;
  topt.origin = config.origin;
  return generateTrajectory(topt);
}

/// One nominal Walker constellation sampled over `sampling`, its geometry offsets
/// and clocks drawn from the streams of `geometry_tag` and `clock_tag`.
TruthProducts walkerProducts(WalkerConstellationOptions w, const ProductSampling& s, const RandomStream& root,
                             std::uint64_t geometry_tag, std::uint64_t clock_tag) {
  w.reference_time = s.first;
  RandomStream geometry = root.derive(geometry_tag);
  w.raan_offset_rad = geometry.uniform(0.0, 2.0 * kPi);
  w.mean_anomaly_offset_rad = geometry.uniform(0.0, 2.0 * kPi);
  return sampleWalkerProducts(WalkerConstellation(w), s, root.derive(clock_tag).seed());
}

/// Step 3a: the truth products: the given SP3/clock within 2 h of the flight, or
/// the nominal constellations sampled from 1 h before to 1 h after it. Galileo
/// has its own geometry and clock streams: the GPS draws stay as they are.
TruthProducts truthProducts(const SimulationConfig& config, const SimulationSources& sources, const RandomStream& root,
                            const GnssTime& t0, const GnssTime& t1) {
  if (sources.sp3) return restrictProducts(*sources.sp3, *sources.clk, t0 - 7200.0, t1 + 7200.0);
  WalkerConstellationOptions w;
  w.satellites = config.satellites;
  ProductSampling s;
  s.first = floorTo(t0 - 3600.0, config.orbit_interval_s);
  s.last = s.first + config.orbit_interval_s * std::ceil((t1 + 3600.0 - s.first) / config.orbit_interval_s);
  s.orbit_interval_s = config.orbit_interval_s;
  s.clock_interval_s = config.clock_interval_s;
  TruthProducts truth = walkerProducts(w, s, root, kTagConstellation, kTagSatelliteClocks);
  if (config.simulates(GnssSystem::Galileo)) {
    WalkerConstellationOptions e = galileoWalkerOptions();
    e.satellites = config.galileo_satellites;
    mergeProducts(truth, walkerProducts(e, s, root, kTagGalileoConstellation, kTagGalileoClocks));
  }
  return truth;
}

/// Step 3b: truth and erroneous products written as file texts and read back
/// (products = truth + product error); they must cover the flight.
void simulateProducts(const SimulationConfig& config, const SimulationSources& sources, const RandomStream& root,
                      const std::vector<TrajectorySample>& traj, SimulatedFlight& f) {
  const GnssTime t0 = traj.front().time, t1 = traj.back().time;
  const double flight_s = std::max(t1 - t0, 1.0);
  const GnssTime t_mid = t0 + 0.5 * (t1 - t0);
  TruthProducts truth = truthProducts(config, sources, root, t0, t1);
  avoidSp3ZeroMarker(truth.orbits);
  f.truth_sp3_text = sp3Text(truth.orbits);
  f.truth_clk_text = rinexClockText(truth.clocks);
  f.truth_products = productsFromText(f.truth_sp3_text, f.truth_clk_text, "truth");
  TruthProducts with_error =
      applyProductErrors(truth, config.errors.products, root.derive(kTagProducts), t_mid, flight_s, f.drawn);
  avoidSp3ZeroMarker(with_error.orbits);
  f.products_sp3_text = sp3Text(with_error.orbits);
  f.products_clk_text = rinexClockText(with_error.clocks);
  f.products = productsFromText(f.products_sp3_text, f.products_clk_text, "products");
  const auto ospan = f.truth_products.orbitSpan();
  const auto cspan = f.truth_products.clockSpan();
  if (!ospan || !cspan || t0 - 1.0 < ospan->first || t0 - 1.0 < cspan->first || ospan->last < t1 + 1.0 ||
      cspan->last < t1 + 1.0)
    throw std::invalid_argument("simulation: the orbit/clock products do not cover the flight " + t0.toString(TimeSystem::GPS, 0) +
                                " .. " + t1.toString(TimeSystem::GPS, 0));
}

/// Step 4a: the flight's troposphere scales and ionosphere (drawn always, kept
/// only for enabled terms, so that switching a term leaves the others' numbers).
void drawAtmosphere(const ErrorModelConfig& err, const RandomStream& root, DrawnParameters& drawn) {
  RandomStream r = root.derive(kTagTroposphere);
  const double a = r.uniform(err.troposphere.dry_scale_min, err.troposphere.dry_scale_max);
  const double b = r.uniform(err.troposphere.wet_scale_min, err.troposphere.wet_scale_max);
  if (err.troposphere.enabled) drawn.dry_scale = a, drawn.wet_scale = b;
  RandomStream i = root.derive(kTagIonosphere);
  const double v = i.uniform(err.ionosphere.vtec_min_tecu, err.ionosphere.vtec_max_tecu);
  const double rate = i.uniform(-err.ionosphere.vtec_rate_max_tecu_per_h, err.ionosphere.vtec_rate_max_tecu_per_h);
  if (err.ionosphere.enabled) drawn.vtec0_tecu = v, drawn.vtec_rate_tecu_per_h = rate;
}

/// Step 4b: receiver clock offsets [s] at the epochs and the Galileo clock offset.
std::vector<double> drawReceiverClocks(const SimulationConfig& config, const std::vector<TrajectorySample>& traj,
                                       const RandomStream& root, DrawnParameters& drawn) {
  const ErrorModelConfig::ReceiverClock& c = config.errors.receiver_clock;
  std::vector<double> clock_s = receiverClock(traj, c, root.derive(kTagReceiverClock), drawn);
  if (config.simulates(GnssSystem::Galileo) && c.enabled) {
    RandomStream g = root.derive(kTagGalileoClockOffset);
    drawn.galileo_clock_offset_s = g.normal(c.galileo_offset_sigma_s);
  }
  return clock_s;
}

/// Step 4c: the signals of each simulated system; the drawn parameters name GPS's phase noise.
SignalTable simulatedSignals(const SimulationConfig& config, DrawnParameters& drawn) {
  SignalTable signals{};
  for (GnssSystem sys : config.systems) signals[static_cast<int>(sys)] = systemSignals(sys, config.errors.thermal);
  const SystemSignals& gps = signalsOf(signals, GnssSystem::GPS);
  drawn.phase_sigma_l1_m = gps.phase_sigma1;
  drawn.phase_sigma_l2_m = gps.phase_sigma2;
  return signals;
}

/// Step 5: the RINEX 3.04 observation header of the flight.
RinexObsHeader simulatedHeader(const SimulationConfig& config, std::uint64_t seed, const SimulationSources& sources,
                               const std::vector<TrajectorySample>& traj, const SignalTable& signals) {
  const GnssTime t0 = traj.front().time, t1 = traj.back().time;
  RinexObsHeader h;
  h.version_text = "3.04";
  h.version = 3.04;
  h.major_version = 3;
  h.file_system = config.simulates(GnssSystem::Galileo) ? 'M' : 'G';
  h.program = "ppp_simulate";
  h.run_by = "ppp_bayes_tree";
  const CalendarTime c = t0.toCalendar(TimeSystem::GPS);
  h.date = format("%04d%02d%02d %02d%02d%02d GPS", c.year, c.month, c.day, c.hour, c.minute,
                  static_cast<int>(c.second));
  h.marker_name = config.marker_name;
  h.marker_type = "NON_GEODETIC";
  h.observer = "simulation";
  h.agency = "ppp_bayes_tree";
  h.receiver_number = "0";
  h.receiver_type = "SIMULATED";
  h.receiver_version = "1";
  h.antenna_number = "0";
  h.antenna_type = "SIMULATED";
  h.antenna_radome = "NONE";
  h.antenna_delta_hen_m = Eigen::Vector3d::Zero();
  h.approx_position_ecef_m = traj.front().position_ecef_m;
  for (GnssSystem sys : config.systems) {
    h.obs_types[static_cast<int>(sys)] = signalsOf(signals, sys).obs_types;
    h.scale_factors[static_cast<int>(sys)] = std::vector<double>(signalsOf(signals, sys).obs_types.size(), 1.0);
  }
  h.interval_s = traj[1].time - traj[0].time;
  h.time_of_first_obs = RinexHeaderTime{t0.toCalendar(TimeSystem::GPS), TimeSystem::GPS, t0};
  h.time_of_last_obs = RinexHeaderTime{t1.toCalendar(TimeSystem::GPS), TimeSystem::GPS, t1};
  h.epoch_time_system = TimeSystem::GPS;
  h.comments = {"SIMULATED UAV FLIGHT, PROFILE " +
                    std::string(sources.trajectory ? "user trajectory" : flightProfileName(config.profile)),
                "SEED " + std::to_string(seed)};
  return h;
}

/// Step 7d: with outages, the header's first and last observation are those of the epochs written.
void fitHeaderToEpochs(RinexObsHeader& h, const std::vector<ObsEpoch>& epochs) {
  const GnssTime first = epochs.front().time, last = epochs.back().time;
  h.time_of_first_obs = RinexHeaderTime{first.toCalendar(TimeSystem::GPS), TimeSystem::GPS, first};
  h.time_of_last_obs = RinexHeaderTime{last.toCalendar(TimeSystem::GPS), TimeSystem::GPS, last};
}

/// Step 6: the simulated satellites (in the truth products with orbit and clock)
/// with their random streams; with satellite phase biases, each one's UPD.
std::vector<SatelliteState> satelliteStates(const SimulationConfig& config, const RandomStream& root,
                                            const SignalTable& signals, SimulatedFlight& f) {
  std::vector<SatelliteState> sats;
  const auto orbit_sats = f.truth_products.orbitSatellites();
  const auto clock_sats = f.truth_products.clockSatellites();
  for (const auto& s : orbit_sats) {
    if (!config.simulates(s.system) || !clock_sats.count(s)) continue;
    const std::uint64_t base = s.system == GnssSystem::GPS
                                   ? kTagPerSatellite + static_cast<std::uint64_t>(s.index())
                                   : kTagPerOtherSatellite + 1000 * static_cast<std::uint64_t>(s.index());
    sats.emplace_back(s, root.derive(base + 100 * kSatAmbiguity), root.derive(base + 100 * kSatMultipath),
                      root.derive(base + 100 * kSatThermal));
    if (config.errors.ambiguity.satellite_phase_biases) {  // UPD per frequency, published as phase OSB
      RandomStream upd = root.derive(base + 100 * kSatPhaseBias);
      const double u1 = upd.uniform(-0.5, 0.5), u2 = upd.uniform(-0.5, 0.5);
      const SystemSignals& g = signalsOf(signals, s.system);
      f.phase_biases.set(s, u1, u2, g.lambda1, g.lambda2);
    }
  }
  return sats;
}

/// Step 8: the IMU options of the configuration.
SimulatedImuOptions imuOptions(const SimulationConfig::Imu& imu) {
  SimulatedImuOptions o;
  o.rate_hz = imu.rate_hz;
  o.noise = imuNoisePreset(imu.grade);
  o.errors = imu.errors;
  return o;
}

/// Where a satellite is seen from the receiver at one epoch and whether it can be tracked.
struct SatelliteView {
  bool available = false;  // orbit and clock known at the epoch
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  double clock_bias_s = 0.0;
  bool visible_local = false;  // above the local elevation mask
  bool visible = false;        // and above the airframe mask (when phase breaks are on)
  double body_elevation_rad = -kPi / 2;
};

/// The receiver's frames at one epoch.
struct ReceiverFrames {
  Eigen::Matrix3d enu_from_ecef, body_from_ned;
};

/// Step 7: the observations of all epochs, epoch by epoch: tracking, the
/// non-dispersive part through the measurement model, the observables with errors.
class EpochGenerator {
 public:
  EpochGenerator(const SimulationConfig& config, const SignalTable& signals, std::vector<SatelliteState>& sats,
                 SimulatedFlight& f)
      : config_(config),
        err_(config.errors),
        signals_(signals),
        sats_(sats),
        f_(f),
        layout_(config.systems),  // one receiver clock per system
        model_(f.truth_products, {}, ReceiverAntenna{}, nullptr, generationOptions(f.model_options)) {}

  /// Epoch k of the trajectory with the receiver clock offset clock_s [s].
  void generate(std::size_t k, const TrajectorySample& ts, const GnssTime& t0, double clock_s) {
    const Geodetic geo = ecefToGeodetic(ts.position_ecef_m);
    const ReceiverFrames frames{rotationEnuFromEcef(geo.latitude_rad, geo.longitude_rad),
                                bodyFromNed(ts.roll_rad, ts.pitch_rad, ts.yaw_rad)};
    TruthEpoch te = truthEpoch(ts, geo, clock_s);
    const SimulationConfig::Outage* in_outage = config_.outageAt(ts.time - t0);
    const bool outage = in_outage != nullptr;
    trackSatellites(k, ts, frames, te, in_outage);
    if (outage) waiting_after_outage_ = true;
    if (outage || (waiting_after_outage_ && obs_.empty())) return;  // nothing tracked: no epoch
    waiting_after_outage_ = false;
    predictCodes(ts, te);
    f_.epochs.push_back(observables(ts.time, t0, te));
    f_.truth.push_back(std::move(te));
  }

 private:
  static MeasurementModelOptions generationOptions(MeasurementModelOptions o) {
    o.elevation_cutoff_rad = -0.5 * kPi;  // the simulator applies its own masks
    return o;
  }

  TruthEpoch truthEpoch(const TrajectorySample& ts, const Geodetic& geo, double clock_s) const {
    TruthEpoch te;
    te.trajectory = ts;
    te.clock_m = clock_s * kSpeedOfLight_mps;
    if (config_.simulates(GnssSystem::Galileo))
      te.galileo_clock_m = te.clock_m + f_.drawn.galileo_clock_offset_s * kSpeedOfLight_mps;
    const SurfaceMeteo meteo = standardAtmosphere(geo.height_m);
    te.zwd_m = f_.drawn.wet_scale * modifiedHopfieldZenithDelays(meteo, geo.height_m).wet_m;
    return te;
  }

  SatelliteView view(const SatelliteState& s, const TrajectorySample& ts, const ReceiverFrames& frames,
                     PreciseEphemeris::OrbitQueryScratch& scratch) const {
    SatelliteView v;
    const auto o = f_.truth_products.orbit(s.sat, ts.time, scratch);
    const auto c = f_.truth_products.clock(s.sat, ts.time);
    if (!o.ok() || !c.ok()) return v;
    v.available = true;
    v.position_ecef_m = o.value->position_ecef_m;
    v.clock_bias_s = c.value->clock_bias_s;
    const Eigen::Vector3d los = (v.position_ecef_m - ts.position_ecef_m).normalized();
    const Eigen::Vector3d enu = frames.enu_from_ecef * los;
    const double el = std::asin(std::clamp(enu.z(), -1.0, 1.0));
    const Eigen::Vector3d body = frames.body_from_ned * Eigen::Vector3d(enu.y(), enu.x(), -enu.z());
    v.body_elevation_rad = std::asin(std::clamp(-body.z(), -1.0, 1.0));
    v.visible_local = el >= config_.elevation_mask_rad;
    v.visible = v.visible_local &&
                (!err_.phase_breaks.enabled || v.body_elevation_rad >= err_.phase_breaks.body_elevation_mask_rad);
    return v;
  }

  /// Starts a new arc of `s` at t (new ambiguities, multipath from its stationary distribution).
  void startArc(SatelliteState& s, const GnssTime& t, bool after_break) {
    TruthArc a;
    a.id = static_cast<ArcId>(f_.arcs.size() + 1);
    a.satellite = s.sat;
    a.first_time = a.last_time = t;
    if (err_.ambiguity.enabled) {
      a.n1_cycles = s.ambiguity_rng.uniformInt(-err_.ambiguity.max_abs_cycles, err_.ambiguity.max_abs_cycles);
      a.n2_cycles = s.ambiguity_rng.uniformInt(-err_.ambiguity.max_abs_cycles, err_.ambiguity.max_abs_cycles);
    }
    const SystemSignals& g = signalsOf(signals_, s.sat.system);
    a.bias_if_m = ionosphereFree(g.lambda1 * static_cast<double>(a.n1_cycles),
                                 g.lambda2 * static_cast<double>(a.n2_cycles), g.k_if);
    a.after_phase_break = after_break;
    f_.arcs.push_back(a);
    s.arc = a.id;
    s.tracked = true;
    s.first_epoch_of_arc = true;
    s.mp1 = err_.multipath.enabled ? s.multipath_rng.normal(err_.multipath.sigma_m) : 0.0;
    s.mp2 = err_.multipath.enabled ? s.multipath_rng.normal(err_.multipath.sigma_m) : 0.0;
    s.mp_time = t;
  }

  /// Loss of lock, outage bookkeeping and reacquisition of one satellite at epoch k.
  void updateTracking(SatelliteState& s, std::size_t k, const TrajectorySample& ts, const SatelliteView& v) {
    const GnssTime& t = ts.time;
    if (s.tracked && !v.visible) {  // loss of lock
      s.tracked = false;
      s.body_outage = v.visible_local;
      s.last_arc = s.arc;
      s.outage_min_body_elevation = v.body_elevation_rad;
      s.outage_max_roll = std::abs(ts.roll_rad);
      s.visible_since.reset();
      return;
    }
    if (s.tracked) return;
    if (!v.visible_local) s.body_outage = false;  // set meanwhile: the next pass is a new satellite
    if (s.body_outage) {
      s.outage_min_body_elevation = std::min(s.outage_min_body_elevation, v.body_elevation_rad);
      s.outage_max_roll = std::max(s.outage_max_roll, std::abs(ts.roll_rad));
    }
    if (!v.visible) {
      s.visible_since.reset();
      return;
    }
    if (!s.visible_since) s.visible_since = t;
    if (k == 0 || t - *s.visible_since >= err_.phase_breaks.reacquisition_s - 1e-9) {
      const bool is_break = s.body_outage;
      startArc(s, t, is_break);
      if (is_break)
        f_.breaks.push_back({s.sat, s.last_tracked, t, s.last_arc, s.arc, s.outage_min_body_elevation,
                             s.outage_max_roll});
      s.body_outage = false;
    }
  }

  /// The observation slot of a tracked satellite, its code set to a first guess.
  void addCandidate(std::size_t i, const TrajectorySample& ts, const SatelliteView& v, const TruthEpoch& te) {
    const SatelliteState& s = sats_[i];
    DualFrequencyObservation d;
    d.satellite = s.sat;
    d.time = ts.time;
    const SystemSignals& g = signalsOf(signals_, s.sat.system);
    d.code1 = g.code1, d.code2 = g.code2, d.phase1 = g.phase1, d.phase2 = g.phase2;
    d.frequency1_hz = g.f1, d.frequency2_hz = g.f2;
    const double rx_clock_m = s.sat.system == GnssSystem::Galileo ? te.galileo_clock_m : te.clock_m;
    const double guess = (v.position_ecef_m - ts.position_ecef_m).norm() + rx_clock_m -
                         kSpeedOfLight_mps * v.clock_bias_s;
    d.code1_m = d.code2_m = std::clamp(guess, 1.5e7, 9.0e7);
    obs_.push_back(d);
    arc_ids_.push_back(s.arc);
    obs_sat_.push_back(i);
    body_el_.push_back(v.body_elevation_rad);
  }

  /// Step 7a: visibility, tracking and arcs of all satellites at epoch k (in an
  /// outage none is visible: each loses lock; in an outage that keeps lock the
  /// satellites are tracked as usual but none is observed).
  void trackSatellites(std::size_t k, const TrajectorySample& ts, const ReceiverFrames& frames, const TruthEpoch& te,
                       const SimulationConfig::Outage* outage) {
    obs_.clear();
    arc_ids_.clear();
    obs_sat_.clear();
    body_el_.clear();
    const bool visible = !outage || outage->keeps_lock;
    PreciseEphemeris::OrbitQueryScratch orbit_scratch;  // the satellites share the window terms at t
    for (std::size_t i = 0; i < sats_.size(); ++i) {
      const SatelliteView v = visible ? view(sats_[i], ts, frames, orbit_scratch) : SatelliteView{};
      updateTracking(sats_[i], k, ts, v);
      if (sats_[i].tracked && !outage) addCandidate(i, ts, v, te);
    }
  }

  /// Step 7b: the non-dispersive part through the measurement model at the true
  /// state (fixed point on the code: the model's signal time depends on it).
  void predictCodes(const TrajectorySample& ts, const TruthEpoch& te) {
    ReceiverState state(layout_);
    state.position_ecef_m = ts.position_ecef_m;
    state.zwd_m = te.zwd_m;
    state.setClock_m(GnssSystem::GPS, te.clock_m);
    state.setClock_m(GnssSystem::Galileo, te.galileo_clock_m);
    for (int it = 0; it < 3 && !obs_.empty(); ++it) {
      model_.evaluate(obs_, arc_ids_, state, &windup_, meas_, it == 2 ? &terms_ : nullptr);
      std::size_t u = 0;
      for (auto& d : obs_) {
        while (u < meas_.used.size() && meas_.used[u].satellite != d.satellite) ++u;
        if (u < meas_.used.size()) d.code1_m = d.code2_m = meas_.used[u].predicted_code_m;
      }
    }
  }

  /// The dispersive and random error terms of one observation (advances the
  /// satellite's multipath and thermal streams).
  SignalTruth signalTruth(const SatelliteMeasurement& m, const ModelTerms& tm, SatelliteState& s, double body_el,
                          const GnssTime& t, const GnssTime& t0) {
    const SystemSignals& g = signalsOf(signals_, s.sat.system);
    SignalTruth sig;
    sig.satellite = s.sat;
    sig.arc = s.arc;
    sig.elevation_rad = m.elevation_rad;
    sig.body_elevation_rad = body_el;
    sig.windup_cycles = tm.windup_cycles;
    sig.troposphere_error_m = (f_.drawn.dry_scale - 1.0) * tm.troposphere_dry_m;
    sig.nondispersive_m = m.predicted_code_m + sig.troposphere_error_m;
    const double sin_el = std::max(std::sin(m.elevation_rad), 0.05);
    if (err_.ionosphere.enabled) {
      const double vtec = f_.drawn.vtec0_tecu + f_.drawn.vtec_rate_tecu_per_h * (t - t0) / 3600.0;
      const double sz = kEarthRadiusIonosphere_m * std::cos(m.elevation_rad) /
                        (kEarthRadiusIonosphere_m + err_.ionosphere.shell_height_km * 1e3);
      sig.ionosphere_l1_m = kIonosphereConstant * std::max(vtec, 0.0) / std::sqrt(1.0 - sz * sz) / (g.f1 * g.f1);
    }
    if (err_.multipath.enabled) {
      const double dt = t - s.mp_time;
      if (dt > 0.0) {
        const double phi = std::exp(-dt / err_.multipath.time_constant_s);
        const double q = err_.multipath.sigma_m * std::sqrt(1.0 - phi * phi);
        s.mp1 = phi * s.mp1 + s.multipath_rng.normal(q);
        s.mp2 = phi * s.mp2 + s.multipath_rng.normal(q);
        s.mp_time = t;
      }
      sig.multipath_unit = s.mp1;
      sig.multipath1_m = s.mp1 / sin_el;
      sig.multipath2_m = s.mp2 / sin_el;
    }
    if (err_.thermal.enabled) {
      sig.code_noise1_m = s.thermal_rng.normal(err_.thermal.code_sigma_m);
      sig.code_noise2_m = s.thermal_rng.normal(err_.thermal.code_sigma_m);
      sig.phase_noise1_m = s.thermal_rng.normal(g.phase_sigma1);
      sig.phase_noise2_m = s.thermal_rng.normal(g.phase_sigma2);
    }
    return sig;
  }

  /// The satellite's observables in RINEX order, appended to the epoch; the arc's
  /// bookkeeping (last epoch, count) follows.
  void appendObservables(ObsEpoch& epoch, SatelliteState& s, const SignalTruth& sig, const GnssTime& t) {
    const SystemSignals& g = signalsOf(signals_, s.sat.system);
    const TruthArc& arc = f_.arcs[s.arc - 1];
    const double G = sig.nondispersive_m, I1 = sig.ionosphere_l1_m, I2 = g.gamma * I1;
    const SimulatedPhaseBiases::Upd upd = f_.phase_biases.upd(s.sat);
    const double p1 = G + I1 + sig.multipath1_m + sig.code_noise1_m;
    const double p2 = G + I2 + sig.multipath2_m + sig.code_noise2_m;
    const double l1 = (G - I1 + sig.phase_noise1_m) / g.lambda1 + sig.windup_cycles +
                      static_cast<double>(arc.n1_cycles) + upd.l1_cycles;
    const double l2 = (G - I2 + sig.phase_noise2_m) / g.lambda2 + sig.windup_cycles +
                      static_cast<double>(arc.n2_cycles) + upd.l2_cycles;
    const bool lli = config_.loss_of_lock_flags && s.first_epoch_of_arc && arc.after_phase_break;
    s.first_epoch_of_arc = false;
    s.last_tracked = t;
    TruthArc& arc_mut = f_.arcs[s.arc - 1];
    arc_mut.last_time = t;
    ++arc_mut.epochs;
    SatelliteObservations so;
    so.satellite = s.sat;
    so.first = static_cast<std::uint32_t>(epoch.observations.size());
    so.count = static_cast<std::uint32_t>(g.obs_types.size());
    epoch.satellites.push_back(so);
    const bool qz = config_.quantize;
    const auto flag = lli ? std::optional<std::uint8_t>(1) : std::nullopt;
    for (const ObservationCode& code : g.obs_types) {  // RINEX order
      const bool band1 = code.band == '1', phase = code.type == ObservableType::CarrierPhase;
      const double v = phase ? (band1 ? l1 : l2) : (band1 ? p1 : p2);
      epoch.observations.push_back({code, quantize(v, qz), phase ? flag : std::nullopt, std::nullopt});
    }
  }

  /// Step 7c: the observables with errors of the epoch's tracked satellites.
  ObsEpoch observables(const GnssTime& t, const GnssTime& t0, TruthEpoch& te) {
    ObsEpoch epoch;
    epoch.time = t;
    std::size_t u = 0;
    for (std::size_t j = 0; j < obs_.size(); ++j) {
      while (u < meas_.used.size() && meas_.used[u].satellite != obs_[j].satellite) ++u;
      if (u >= meas_.used.size()) {  // rejected by the model (should not happen): no observation
        u = 0;
        continue;
      }
      SatelliteState& s = sats_[obs_sat_[j]];
      const SignalTruth sig = signalTruth(meas_.used[u], terms_[u], s, body_el_[j], t, t0);
      appendObservables(epoch, s, sig, t);
      te.signals.push_back(sig);
    }
    return epoch;
  }

  const SimulationConfig& config_;
  const ErrorModelConfig& err_;
  const SignalTable& signals_;
  std::vector<SatelliteState>& sats_;
  SimulatedFlight& f_;
  const ReceiverStateLayout layout_;
  const PppMeasurementModel model_;
  WindupTracker windup_;
  bool waiting_after_outage_ = false;  // an outage ended and no satellite is tracked yet
  // Per-epoch scratch: the tracked satellites' observations, arcs, indices into
  // sats_ and body elevations; the model's output.
  std::vector<DualFrequencyObservation> obs_;
  std::vector<ArcId> arc_ids_;
  std::vector<std::size_t> obs_sat_;
  std::vector<double> body_el_;
  EpochMeasurements meas_;
  std::vector<ModelTerms> terms_;
};

}  // namespace

std::vector<std::string> DrawnParameters::describe() const {
  std::vector<std::string> out{
      format("troposphere dry scale %.4f", dry_scale) + format(", wet scale %.4f", wet_scale),
      format("ionosphere VTEC %.2f TECU", vtec0_tecu) + format(" + %.2f TECU/h", vtec_rate_tecu_per_h),
      format("receiver clock offset %.3f ns", clock_initial_s * 1e9) +
          format(", drift %.4f ns/s", clock_drift_s_per_s * 1e9) + ", steps " + std::to_string(clock_steps),
      format("phase noise L1 %.4f m", phase_sigma_l1_m) + format(", L2 %.4f m", phase_sigma_l2_m),
      format("product orbit error RMS %.4f m per component", orbit_error_rms_m) +
          format(", clock error RMS %.4f m", clock_error_rms_m),
  };
  if (galileo_clock_offset_s != 0.0)
    out.push_back(format("Galileo receiver clock - GPS receiver clock %.3f ns", galileo_clock_offset_s * 1e9));
  return out;
}

MeasurementModelOptions simulationModelOptions() {
  MeasurementModelOptions o;
  o.elevation_cutoff_rad = 7.0 * kDegToRad;
  o.solid_earth_tide = false;  // a UAV does not move with the crust
  o.ocean_loading = false;
  o.satellite_antenna = false;  // no ANTEX in the simulation
  o.receiver_antenna = ReceiverAntennaPolicy::Off;
  o.exclude_eclipse = false;
  o.yaw_manoeuvre = YawManoeuvreHandling::Nominal;  // the simulated attitude is the nominal one
  o.phase_windup = true;
  o.shapiro = true;
  o.dry_troposphere = DryTroposphereModel::ModifiedHopfield;
  o.mapping = TroposphereMapping::ModifiedHopfield;
  return o;
}

SimulatedFlight simulateFlight(const SimulationConfig& config, std::uint64_t seed, const SimulationSources& sources) {
  // 1. The setup.
  checkSimulationSetup(config, sources);
  const RandomStream root(seed);
  SimulatedFlight f;
  f.config = config;
  f.seed = seed;
  f.model_options = simulationModelOptions();
  // 2. Start time and trajectory.
  const std::vector<TrajectorySample> traj = flightTrajectory(config, sources, flightStart(config, sources));
  // 3. Truth products, written and read back; products = truth + error.
  simulateProducts(config, sources, root, traj, f);
  // 4. Per-flight parameters: atmosphere, receiver clock, signals and their noise.
  drawAtmosphere(config.errors, root, f.drawn);
  const std::vector<double> clock_s = drawReceiverClocks(config, traj, root, f.drawn);
  const SignalTable signals = simulatedSignals(config, f.drawn);
  // 5. RINEX header.
  f.header = simulatedHeader(config, seed, sources, traj, signals);
  // 6. Satellites and their random streams.
  std::vector<SatelliteState> sats = satelliteStates(config, root, signals, f);
  // 7. The epochs.
  EpochGenerator generator(config, signals, sats, f);
  f.epochs.reserve(traj.size());
  f.truth.reserve(traj.size());
  for (std::size_t k = 0; k < traj.size(); ++k) generator.generate(k, traj[k], traj.front().time, clock_s[k]);
  if (f.epochs.empty()) throw std::invalid_argument("simulation: the GNSS outages leave no epoch with observations");
  if (!config.outages.empty()) fitHeaderToEpochs(f.header, f.epochs);
  // 8. The IMU readings.
  if (config.imu.enabled) f.imu = simulateImu(traj, imuOptions(config.imu), root.derive(kTagImu).seed());
  return f;
}

}  // namespace ppp
