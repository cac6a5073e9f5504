#include "ppp_bayes_tree/evaluation/monte_carlo.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <thread>
#include <tuple>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/model/ppp_factors.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/random_stream.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"

namespace ppp {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Median (mean of the two middle values for an even count; +inf counts as a
/// value); NaN when empty.
double medianOf(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 == 1 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

/// Tag of the Monte Carlo's own sub-stream of a flight seed (the simulator
/// derives its streams from small tags of the same seed).
constexpr std::uint64_t kSetupStreamTag = 0x4d6f6e7465436172ULL;  // "MonteCar"

/// The IF wind-up wavelength of a system's simulated pair is its narrow-lane
/// wavelength c / (f1 + f2) (ppp_measurement_model.cpp): GPS L1/L2 10.7 cm,
/// Galileo E1/E5a 10.9 cm.
double simulatedNarrowLaneWavelength_m(GnssSystem system) {
  const SimulatedBands bands = simulatedIonosphereFreeBands(system);
  return narrowLaneWavelength_m(*carrierFrequency_hz(system, bands.band1), *carrierFrequency_hz(system, bands.band2));
}

/// Bias bookkeeping of one estimator arc.
struct ArcRecord {
  SatelliteId satellite;
  GnssTime first_time;
  ArcId simulated_arc = 0;
  double truth_m = 0.0;
  long windup_cycles = 0;  // the wind-up integer between the simulator's and the estimator's convention
  double last_windup_cycles = 0.0;  // the simulator's wind-up at the arc's last epoch
  bool valid = true;       // still inside its simulated arc
  bool missed_slip = false;
  /// The truth of the arc's phase as the estimator sees it: the simulated arc's
  /// integers minus the slips the arc tracker repaired (PppEpochRecord::slip_repairs).
  long wide_lane_cycles = 0;
  long correction1_cycles = 0, correction2_cycles = 0;
  int generation = 0;  // truth changes (repairs followed)
  long last_bin = -1;
  std::vector<float> ages;  // sampled ages (for the smoothed values)
};

/// Samples the bias errors of one estimator's run from the epoch records.
class BiasSampler {
 public:
  BiasSampler(const SimulatedFlight& f, double bin_s) : f_(f), bin_s_(bin_s) {}

  /// `estimate(arc)`: the estimator's current bias estimate.
  template <class Estimate>
  void epoch(std::size_t k, const PppEpochRecord& rec, Estimate estimate, std::vector<BiasErrorSample>& out) {
    const std::set<ArcId> repaired = applyRepairs(rec);
    if (rec.status != EpochStatus::Ok) return;
    for (const auto& r : rec.residuals) {
      const SignalTruth* s = f_.signal(k, r.satellite);
      auto it = arcs_.find(r.arc);
      if (it == arcs_.end()) {
        ArcRecord a;
        a.satellite = r.satellite;
        a.first_time = rec.solution.time;
        if (s == nullptr || s->arc == 0 || repaired.count(r.arc) != 0) {
          a.valid = false;
        } else {
          a.windup_cycles = std::lround(s->windup_cycles);
          a.last_windup_cycles = s->windup_cycles;
          followTruth(a, s->arc);
        }
        it = arcs_.emplace(r.arc, std::move(a)).first;
      }
      ArcRecord& a = it->second;
      if (!a.valid) continue;
      // A repaired arc's phase: the simulated arc's integers minus the repairs. A new
      // simulated arc starts its wind-up at the principal value while the estimator's
      // arc goes on from its own: the whole cycles between them follow (they are in
      // the phase the repair measured, not in the integers).
      if (s != nullptr && s->arc != 0 && repaired.count(r.arc) != 0) {
        if (s->arc != a.simulated_arc) a.windup_cycles += std::lround(s->windup_cycles - a.last_windup_cycles);
        followTruth(a, s->arc);
      }
      if (s == nullptr || s->arc != a.simulated_arc) {
        a.valid = false;
        a.missed_slip = true;
        continue;
      }
      a.last_windup_cycles = s->windup_cycles;
      const double age = rec.solution.time - a.first_time;
      const long bin = static_cast<long>(std::floor(age / bin_s_ + 1e-9));
      if (bin <= a.last_bin) continue;
      const std::optional<double> b = estimate(r.arc);
      if (!b) continue;
      a.last_bin = bin;
      a.ages.push_back(static_cast<float>(age));
      out.push_back({static_cast<float>(age), static_cast<float>(*b - a.truth_m)});
    }
  }
  const std::map<ArcId, ArcRecord>& arcs() const { return arcs_; }

 private:
  /// Adds this epoch's repaired slips to their arcs' corrections; the arcs repaired.
  std::set<ArcId> applyRepairs(const PppEpochRecord& rec) {
    std::set<ArcId> repaired;
    for (const ArcSlipRepair& r : rec.slip_repairs) {
      if (r.repair.dn1_cycles == 0 && r.repair.dn2_cycles == 0) continue;
      repaired.insert(r.arc);
      auto it = arcs_.find(r.arc);
      if (it == arcs_.end()) continue;
      it->second.correction1_cycles += r.repair.dn1_cycles;
      it->second.correction2_cycles += r.repair.dn2_cycles;
    }
    return repaired;
  }

  /// The record's truth from simulated arc `sim` with its corrections.
  void followTruth(ArcRecord& a, ArcId sim) const {
    const TruthArc& t = f_.arcs[sim - 1];
    const SimulatedBands bands = simulatedIonosphereFreeBands(a.satellite.system);
    const double f1 = *carrierFrequency_hz(a.satellite.system, bands.band1);
    const double f2 = *carrierFrequency_hz(a.satellite.system, bands.band2);
    const double c1 = static_cast<double>(a.correction1_cycles), c2 = static_cast<double>(a.correction2_cycles);
    a.simulated_arc = sim;
    a.wide_lane_cycles = (t.n1_cycles - a.correction1_cycles) - (t.n2_cycles - a.correction2_cycles);
    a.truth_m = t.bias_if_m - ionosphereFreeAmbiguity_m(f1, f2, c1, c1 - c2) +
                simulatedNarrowLaneWavelength_m(a.satellite.system) * static_cast<double>(a.windup_cycles);
    ++a.generation;
  }

  const SimulatedFlight& f_;
  double bin_s_;
  std::map<ArcId, ArcRecord> arcs_;
};

/// Compares one estimator's held integers with the simulator's (HeldIntegerCheck
/// in monte_carlo.h), epoch by epoch.
class HeldIntegerChecker {
 public:
  explicit HeldIntegerChecker(const SimulatedFlight& f) : f_(f) {}

  /// `arcs`: the estimator arcs' truth bookkeeping (BiasSampler::arcs(), updated
  /// for this epoch first).
  void epoch(double time_s, const std::optional<AmbiguityFixSummary>& fix, bool fixed,
             const std::map<ArcId, ArcRecord>& arcs, HeldIntegerCheck& out) {
    if (fixed) ++out.fixed_epochs;
    if (!fix) return;
    bool wrong_now = false;
    for (const NarrowLaneFloat& n : fix->narrow_lanes) {
      if (!n.held_cycles) continue;
      const Key key{n.arc, n.reference_arc, n.wide_lane_cycles, *n.held_cycles, generation(arcs, n.arc),
                    generation(arcs, n.reference_arc)};
      auto it = verdicts_.find(key);
      if (it == verdicts_.end()) {
        const Judgement j = judge(n, arcs, out);
        if (j.verdict == Verdict::Wrong) recordWrongHold(time_s, *fix, n, j, out);
        it = verdicts_.emplace(key, j.verdict).first;
      }
      wrong_now = wrong_now || it->second == Verdict::Wrong;
    }
    if (fixed && wrong_now) ++out.fixed_epochs_with_wrong_hold;
  }

 private:
  /// Arcs, wide lane, held integer and the arcs' truth generations (a repair is judged again).
  using Key = std::tuple<ArcId, ArcId, long, long, int, int>;

  static int generation(const std::map<ArcId, ArcRecord>& arcs, ArcId arc) {
    const auto it = arcs.find(arc);
    return it == arcs.end() ? 0 : it->second.generation;
  }
  enum class Verdict { Right, Wrong, NotCompared };
  /// A hold judged against the truth, with the truth it was judged on.
  struct Judgement {
    Verdict verdict = Verdict::NotCompared;
    long true_wide_lane_cycles = 0;
    double true_cycles = 0.0;  // the true dN1 with the held wide lane
  };

  /// The hold `n` against the truth, counted in `out` (held, cross-system, wrong, not compared).
  Judgement judge(const NarrowLaneFloat& n, const std::map<ArcId, ArcRecord>& arcs, HeldIntegerCheck& out) const {
    const auto a = arcs.find(n.arc), r = arcs.find(n.reference_arc);
    if (a == arcs.end() || r == arcs.end() || !a->second.valid || !r->second.valid || a->second.simulated_arc == 0 ||
        r->second.simulated_arc == 0) {
      ++out.not_compared;
      return {Verdict::NotCompared};
    }
    ++out.held;
    if (n.satellite.system != n.reference_satellite.system) ++out.cross_system;
    const long true_wide_lane = a->second.wide_lane_cycles - r->second.wide_lane_cycles;
    const SimulatedBands bands = simulatedIonosphereFreeBands(n.satellite.system);
    const double f1 = *carrierFrequency_hz(n.satellite.system, bands.band1);
    const double f2 = *carrierFrequency_hz(n.satellite.system, bands.band2);
    const double k_wl = ionosphereFreeAmbiguity_m(f1, f2, 0.0, 1.0);
    const double true_dn1 = (a->second.truth_m - r->second.truth_m - k_wl * static_cast<double>(n.wide_lane_cycles)) /
                            narrowLaneWavelength_m(f1, f2);
    const double error = static_cast<double>(*n.held_cycles) - true_dn1;
    const bool right_wide_lane = n.wide_lane_cycles == true_wide_lane;
    if (right_wide_lane) out.max_abs_error_cycles = std::max(out.max_abs_error_cycles, std::abs(error));
    const Verdict verdict =
        right_wide_lane && std::abs(error) <= kWrongHoldThresholdCycles ? Verdict::Right : Verdict::Wrong;
    if (verdict == Verdict::Wrong) ++out.wrong;
    return {verdict, true_wide_lane, true_dn1};
  }

  /// The record of a wrong hold `n` (its judgement `j`), first held at `time_s` by the search `fix`.
  static void recordWrongHold(double time_s, const AmbiguityFixSummary& fix, const NarrowLaneFloat& n,
                              const Judgement& j, HeldIntegerCheck& out) {
    WrongHold w;
    w.time_s = time_s;
    w.satellite = n.satellite;
    w.reference_satellite = n.reference_satellite;
    w.wide_lane_cycles = n.wide_lane_cycles;
    w.true_wide_lane_cycles = j.true_wide_lane_cycles;
    w.held_cycles = *n.held_cycles;
    w.true_cycles = j.true_cycles;
    w.float_cycles = n.float_cycles;
    w.sigma_cycles = n.sigma_cycles;
    w.ratio = fix.ratio;
    w.bootstrap_success_rate = fix.bootstrap_success_rate;
    out.wrong_holds.push_back(w);
  }

  const SimulatedFlight& f_;
  std::map<Key, Verdict> verdicts_;
};

double error3d(const SimulatedFlight& f, std::size_t k, const std::optional<Eigen::Vector3d>& p) {
  if (!p || k >= f.truth.size()) return kNaN;
  return (*p - f.truth[k].trajectory.position_ecef_m).norm();
}

double percentileSorted(const std::vector<double>& v, double p) {
  if (v.empty()) return kNaN;
  const double x = p * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(x));
  const std::size_t j = std::min(v.size() - 1, i + 1);
  return v[i] + (x - static_cast<double>(i)) * (v[j] - v[i]);
}

QuantileBin quantileBin(double t_s, std::vector<double>& values) {
  QuantileBin b;
  b.t_s = t_s;
  b.count = values.size();
  if (values.empty()) {
    b.p05 = b.p50 = b.p95 = b.abs_p50 = b.abs_p90 = kNaN;
    return b;
  }
  std::sort(values.begin(), values.end());
  b.p05 = percentileSorted(values, 0.05);
  b.p50 = percentileSorted(values, 0.50);
  b.p95 = percentileSorted(values, 0.95);
  for (double& v : values) v = std::abs(v);
  std::sort(values.begin(), values.end());
  b.abs_p50 = percentileSorted(values, 0.50);
  b.abs_p90 = percentileSorted(values, 0.90);
  return b;
}

/// Bins (t, value) pairs by t into bins of width `bin_s`.
std::vector<QuantileBin> binQuantiles(const std::vector<std::pair<double, double>>& samples, double bin_s) {
  std::map<long, std::vector<double>> bins;
  for (const auto& [t, v] : samples)
    if (std::isfinite(v)) bins[static_cast<long>(std::floor(t / bin_s + 1e-9))].push_back(v);
  std::vector<QuantileBin> out;
  for (auto& [k, values] : bins) out.push_back(quantileBin(static_cast<double>(k) * bin_s, values));
  return out;
}

}  // namespace

PppInMemoryInputs simulatedFlightInputs(const SimulatedFlight& f, int index) {
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  if (!f.phase_biases.empty()) in.phase_biases = &f.phase_biases;
  in.name = "flight " + std::to_string(index);
  return in;
}

PppConfig flightPppConfig(const PppConfig& ppp, const SimulatedFlight& f) {
  PppConfig c = ppp;
  MeasurementModelOptions m = f.model_options;  // the physics of the simulation
  m.elevation_cutoff_rad = c.model.elevation_cutoff_rad;  // the estimators' weighting and cutoff
  m.phase_sigma_zenith_m = c.model.phase_sigma_zenith_m;
  m.code_phase_ratio = c.model.code_phase_ratio;
  m.scale_sigma_for_ionosphere_free = c.model.scale_sigma_for_ionosphere_free;
  m.estimate_troposphere_gradients = c.model.estimate_troposphere_gradients;  // a state choice, not physics
  m.zwd_at_ellipsoid = c.model.zwd_at_ellipsoid;  // a state choice too
  c.model = m;
  c.signals.systems = f.config.systems;
  return c;
}

namespace {

/// The solution `index` of the studied estimators (kMonteCarloStudy, in order).
std::optional<EstimatorSolution> studiedSolution(int index) {
  for (const std::string_view name : kMonteCarloStudy) {
    const std::vector<EstimatorSolution> solutions = solutionOutputs(*findEstimator(name));
    if (index < static_cast<int>(solutions.size())) return solutions[static_cast<std::size_t>(index)];
    index -= static_cast<int>(solutions.size());
  }
  return std::nullopt;
}

}  // namespace

std::string monteCarloEstimatorKey(int estimator) {
  const auto s = estimator >= 0 ? studiedSolution(estimator) : std::nullopt;
  return s ? s->tag : "?";
}

std::string monteCarloEstimatorLabel(int estimator) {
  const auto s = estimator >= 0 ? studiedSolution(estimator) : std::nullopt;
  return s ? s->table_label : "?";
}

PppConfig monteCarloDefaultPppConfig() {
  PppConfig c = methodTablePppConfig();  // config/method_table.yaml
  c.stochastic.position.initial_sigma_m = 30.0;  // as config/ppp_simulated.yaml (monte_carlo.h)
  c.smoother.relinearize_position_m = 0.5;       // as config/ppp_simulated.yaml (monte_carlo.h)
  // As config/ppp_simulated.yaml: the simulated errors are the estimators' model.
  c.ambiguity_resolution.narrow_lane.success_rate_variance_factor = 1.0;
  return c;
}

MonteCarloFlightSetup monteCarloFlightSetup(const MonteCarloOptions& options, int index) {
  MonteCarloFlightSetup s;
  s.index = index;
  s.seed = RandomStream(options.seed).derive(static_cast<std::uint64_t>(index)).seed();
  s.profile = options.profiles.empty() ? FlightProfile::Loiter
                                       : options.profiles[static_cast<std::size_t>(index) % options.profiles.size()];
  RandomStream r = RandomStream(s.seed).derive(kSetupStreamTag);
  const GnssTime day = GnssTime::fromCalendar(CalendarTime{2026, 5, 13, 0, 0, 0.0}, TimeSystem::GPS);
  const double start_offset_s = options.randomize_start ? std::floor(r.uniform(0.0, 86400.0)) : 36000.0;
  s.start = day + start_offset_s;
  s.origin = options.simulation.origin;
  if (options.randomize_origin) {
    s.origin.latitude_rad = r.uniform(-60.0, 60.0) * kDegToRad;
    s.origin.longitude_rad = r.uniform(-180.0, 180.0) * kDegToRad;
    s.origin.height_m = r.uniform(0.0, 1000.0);
  }
  return s;
}

SimulationConfig monteCarloSimulationConfig(const MonteCarloOptions& options, const MonteCarloFlightSetup& setup) {
  SimulationConfig c = options.simulation;
  c.profile = setup.profile;
  c.rate_hz = options.rate_hz;
  c.duration_s = options.duration_s;
  c.start = setup.start;
  c.origin = setup.origin;
  return c;
}

ErrorSummary MonteCarloFlightRun::summary(int estimator, double window_s) const {
  std::vector<double> v;
  const auto& e = error_3d_m[static_cast<std::size_t>(estimator)];
  for (std::size_t k = 0; k < e.size(); ++k)
    if (std::isfinite(e[k]) && (window_s < 0.0 || time_s[k] < window_s)) v.push_back(e[k]);
  return summarizeErrors(std::move(v));
}

namespace {

/// An estimator's configuration in the study: one that smooths runs with the
/// study's fixed lag (its filtered solution), keeping its whole graph for the
/// exact smoothed solution at the end (options.smoother_filtered_lag_s > 0).
PppConfig studiedConfig(const PppConfig& flight_config, const EstimatorEntry& entry, double lag_s) {
  PppConfig c = flight_config;
  if (entry.smoothed() && lag_s > 0.0) {
    c.smoother.fixed_lag_s = lag_s;
    c.smoother.record_graph = true;
  }
  return c;
}

/// The epoch index of a smoothed state (states exist only for solved epochs).
std::optional<std::size_t> epochIndex(const SimulatedFlight& f, const GnssTime& time, double rate_hz) {
  const double dt = time - f.epochs.front().time;
  const std::size_t k = static_cast<std::size_t>(std::max(0.0, std::round(dt * rate_hz)));
  if (k < f.epochs.size() && f.epochs[k].time == time) return k;
  std::optional<std::size_t> found;
  for (std::size_t j = 0; j < f.epochs.size(); ++j)
    if (f.epochs[j].time == time) found = j;
  return found;
}

/// The smoothed solution's columns: its 3D errors, and its arcs' bias errors at
/// the ages the filtered run sampled them.
void recordSmoothed(const SimulatedFlight& f, const MonteCarloOptions& options, const SmoothedSolution& smoothed,
                    const BiasSampler& sampler, std::size_t column, MonteCarloFlightRun& run) {
  for (const auto& s : smoothed.trajectory)
    if (const auto k = epochIndex(f, s.time, options.rate_hz)) run.error_3d_m[column][*k] = error3d(f, *k, s.state.position_ecef_m);
  for (const auto& [arc, a] : sampler.arcs()) {
    if (a.simulated_arc == 0 || a.ages.empty()) continue;
    ++run.bias_arcs_compared;
    if (a.missed_slip) ++run.bias_arcs_missed_slip;
    const std::optional<double> b = smoothed.bias_m(a.satellite, arc);
    if (!b) continue;
    const double err = *b - a.truth_m;
    for (float age : a.ages) run.bias[column].push_back({age, static_cast<float>(err)});
  }
}

/// Runs studied estimator `study` (kMonteCarloStudy) on the flight, its solutions
/// into the columns from `column` on. The first studied estimator's positions go
/// to `reference`; an estimator that smooths is compared with them epoch by epoch
/// (filtered_minus_ekf_m).
void runStudiedEstimator(const SimulatedFlight& f, int index, const MonteCarloOptions& options,
                         const PppConfig& flight_config, std::size_t study, std::size_t column,
                         std::vector<std::optional<Eigen::Vector3d>>& reference, MonteCarloFlightRun& run) {
  const EstimatorEntry& entry = *findEstimator(kMonteCarloStudy[study]);
  const PppConfig config = studiedConfig(flight_config, entry, options.smoother_filtered_lag_s);
  PppPipeline pipeline(simulatedFlightInputs(f, index), config);
  const std::unique_ptr<PppEstimator> estimator = makeEstimator(entry.name, config);
  BiasSampler sampler(f, options.bias_bin_s);
  HeldIntegerChecker checker(f);
  std::vector<double>& errors = run.error_3d_m[column];
  std::vector<char>& fixed = run.fixed[study];
  std::size_t k = 0;
  const PppRunSummary summary = pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    const std::optional<Eigen::Vector3d>& p = rec.solution.position_ecef_m;
    errors[k] = error3d(f, k, p);
    fixed[k] = rec.solution.status == SolutionStatus::PppFixed ? 1 : 0;
    if (study == 0) reference[k] = p;
    else if (entry.smoothed() && p && reference[k]) run.filtered_minus_ekf_m[k] = (*p - *reference[k]).norm();
    sampler.epoch(k, rec, [&](ArcId a) { return estimator->biasEstimate_m(a); }, run.bias[column]);
    checker.epoch(f.epochs[k].time - f.epochs.front().time, estimator->lastResult().ambiguity_fix, fixed[k] != 0,
                  sampler.arcs(), run.held_check[study]);
    ++k;
  });
  run.estimator_arcs = summary.arcs;  // the arc tracker's: the same front end in every run
  run.slips_detected = summary.slips;
  if (const SmoothedTrajectoryProvider* smoothing = estimator->smoothing())
    recordSmoothed(f, options, smoothing->finalSmoothedSolution(), sampler, column + 1, run);
}

}  // namespace

FlightEstimatorTrack trackEstimatorOnFlight(
    const SimulatedFlight& f, const PppConfig& config, const std::string& name,
    const std::function<void(std::size_t, const PppEpochRecord&, const PppEstimator&)>& on_epoch) {
  PppPipeline pipeline(simulatedFlightInputs(f, 0), config);
  if (!f.imu.samples.empty()) pipeline.setImu(f.imu.samples);
  std::string why;
  const std::unique_ptr<PppEstimator> estimator = makeEstimator(name, config, &why);
  if (!estimator) throw std::invalid_argument("estimator " + name + ": " + why);
  FlightEstimatorTrack track;
  track.position_ecef_m.assign(f.epochs.size(), std::nullopt);
  track.fixed.assign(f.epochs.size(), 0);
  BiasSampler sampler(f, 10.0);
  HeldIntegerChecker checker(f);
  std::vector<BiasErrorSample> bias_samples;
  std::size_t k = 0;
  const PppRunSummary summary = pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    if (k >= f.epochs.size()) return;
    track.position_ecef_m[k] = rec.solution.position_ecef_m;
    track.fixed[k] = rec.solution.status == SolutionStatus::PppFixed ? 1 : 0;
    sampler.epoch(k, rec, [&](ArcId a) { return estimator->biasEstimate_m(a); }, bias_samples);
    checker.epoch(f.epochs[k].time - f.epochs.front().time, estimator->lastResult().ambiguity_fix,
                  track.fixed[k] != 0, sampler.arcs(), track.held_check);
    if (on_epoch) on_epoch(k, rec, *estimator);
    ++k;
  });
  track.arcs = summary.arcs;
  track.slips = summary.slips;
  return track;
}

MonteCarloFlightRun runMonteCarloFlight(const MonteCarloOptions& options, int index) {
  MonteCarloFlightRun run;
  run.setup = monteCarloFlightSetup(options, index);
  try {
    auto t0 = Clock::now();
    const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(options, run.setup), run.setup.seed);
    run.simulate_s = secondsSince(t0);
    run.drawn = f.drawn.describe();
    run.epochs = f.epochs.size();
    run.simulated_arcs = f.arcs.size();
    run.phase_breaks = f.breaks.size();
    run.time_s.resize(f.epochs.size());
    for (std::size_t k = 0; k < f.epochs.size(); ++k) run.time_s[k] = f.epochs[k].time - f.epochs.front().time;
    for (auto& e : run.error_3d_m) e.assign(f.epochs.size(), kNaN);
    for (auto& x : run.fixed) x.assign(f.epochs.size(), 0);
    run.filtered_minus_ekf_m.assign(f.epochs.size(), kNaN);
    const PppConfig config = flightPppConfig(options.ppp, f);
    std::vector<std::optional<Eigen::Vector3d>> reference(f.epochs.size());  // the first estimator's positions
    std::size_t column = 0;
    for (std::size_t study = 0; study < kMonteCarloStudy.size(); ++study) {
      t0 = Clock::now();
      runStudiedEstimator(f, index, options, config, study, column, reference, run);
      run.estimator_s[study] = secondsSince(t0);
      column += static_cast<std::size_t>(findEstimator(kMonteCarloStudy[study])->solutionCount());
    }
  } catch (const std::exception& e) {
    run.failure = e.what();
  }
  return run;
}

void HeldIntegerCheck::add(const HeldIntegerCheck& o) {
  held += o.held;
  wrong += o.wrong;
  cross_system += o.cross_system;
  not_compared += o.not_compared;
  fixed_epochs += o.fixed_epochs;
  fixed_epochs_with_wrong_hold += o.fixed_epochs_with_wrong_hold;
  max_abs_error_cycles = std::max(max_abs_error_cycles, o.max_abs_error_cycles);
  wrong_holds.insert(wrong_holds.end(), o.wrong_holds.begin(), o.wrong_holds.end());
}

MonteCarloSummary summarizeMonteCarlo(const std::vector<MonteCarloFlightRun>& flights,
                                      const MonteCarloOptions& options) {
  MonteCarloSummary s;
  s.flights = static_cast<int>(flights.size());
  std::vector<const MonteCarloFlightRun*> ok;
  for (const auto& f : flights) {
    if (!f.failure.empty()) {
      ++s.failed;
      s.failures.push_back("flight " + std::to_string(f.setup.index) + ": " + f.failure);
    } else {
      ok.push_back(&f);
    }
    s.simulate_s += f.simulate_s;
    for (std::size_t i = 0; i < s.estimator_s.size(); ++i) s.estimator_s[i] += f.estimator_s[i];
    s.bias_arcs_compared += f.bias_arcs_compared;
    s.bias_arcs_missed_slip += f.bias_arcs_missed_slip;
  }
  // Representative flight: median EKF mean (lower middle, ties by index).
  std::vector<std::pair<double, int>> means;
  for (std::size_t i = 0; i < flights.size(); ++i)
    if (flights[i].failure.empty()) {
      const double m = flights[i].summary(0).mean_m;
      means.push_back({std::isfinite(m) ? m : std::numeric_limits<double>::infinity(), static_cast<int>(i)});
    }
  std::sort(means.begin(), means.end());
  if (!means.empty()) s.representative = means[(means.size() - 1) / 2].second;

  {
    std::vector<double> all;
    std::vector<std::pair<double, double>> vs_time;
    for (const auto* f : ok)
      for (std::size_t k = 0; k < f->filtered_minus_ekf_m.size(); ++k)
        if (std::isfinite(f->filtered_minus_ekf_m[k])) {
          all.push_back(f->filtered_minus_ekf_m[k]);
          vs_time.push_back({f->time_s[k], f->filtered_minus_ekf_m[k]});
        }
    s.filtered_minus_ekf = summarizeErrors(std::move(all));
    s.filtered_minus_ekf_vs_time = binQuantiles(vs_time, options.time_bin_s);
  }
  for (std::size_t e = 0; e < 2; ++e) {  // PPP-AR: fixed share and time to first fix
    std::size_t solved = 0, fixed = 0;
    std::vector<double> first_fix;
    for (const auto* f : ok) {
      std::optional<double> t;
      // fixed[0] / fixed[1] belong to the EKF / filtered, error_3d_m[0] / [1] likewise.
      for (std::size_t k = 0; k < f->fixed[e].size() && k < f->error_3d_m[e].size(); ++k) {
        if (!std::isfinite(f->error_3d_m[e][k])) continue;
        ++solved;
        if (!f->fixed[e][k]) continue;
        ++fixed;
        if (!t) t = f->time_s[k];
      }
      if (!t) ++s.never_fixed[e];
      first_fix.push_back(t ? *t : std::numeric_limits<double>::infinity());
    }
    for (const auto* f : ok) s.held_check[e].add(f->held_check[e]);
    s.fixed_share[e] = solved ? static_cast<double>(fixed) / static_cast<double>(solved) : kNaN;
    s.first_fix_median_s[e] = medianOf(std::move(first_fix));
  }
  for (int e = 0; e < kMonteCarloEstimators; ++e) {
    const auto ei = static_cast<std::size_t>(e);
    std::vector<double> all, first, after;
    std::vector<std::pair<double, double>> vs_time, vs_age;
    for (const auto* f : ok) {
      const auto& err = f->error_3d_m[ei];
      for (std::size_t k = 0; k < err.size(); ++k) {
        if (!std::isfinite(err[k])) {
          ++s.epochs_without_solution[ei];
          continue;
        }
        all.push_back(err[k]);
        (f->time_s[k] < options.first_window_s ? first : after).push_back(err[k]);
        vs_time.push_back({f->time_s[k], err[k]});
      }
      for (const auto& b : f->bias[ei]) vs_age.push_back({b.age_s, b.error_m});
    }
    // Convergence times per threshold: median over flights (never = +inf).
    for (double thr : options.convergence_thresholds_m) {
      std::vector<double> times;
      int never = 0;
      for (const auto* f : ok) {
        std::vector<double> t_ok, e_ok;
        for (std::size_t k = 0; k < f->error_3d_m[ei].size(); ++k)
          if (std::isfinite(f->error_3d_m[ei][k])) {
            t_ok.push_back(f->time_s[k]);
            e_ok.push_back(f->error_3d_m[ei][k]);
          }
        const std::optional<double> c = e_ok.empty() ? std::nullopt : convergenceTime_s(t_ok, e_ok, thr);
        if (!c) ++never;
        times.push_back(c ? *c : std::numeric_limits<double>::infinity());
      }
      s.convergence_median_s[ei].push_back(medianOf(std::move(times)));
      s.convergence_never[ei].push_back(never);
    }
    s.error_vs_time[ei] = binQuantiles(vs_time, options.time_bin_s);
    s.bias_vs_age[ei] = binQuantiles(vs_age, options.bias_bin_s);
    // CDF quantiles.
    std::sort(all.begin(), all.end());
    std::sort(first.begin(), first.end());
    if (s.cdf_levels.empty())
      for (int j = 0; j <= 1000; ++j) s.cdf_levels.push_back(j / 1000.0);
    for (double q : s.cdf_levels) {
      s.cdf_all_m[ei].push_back(percentileSorted(all, q));
      s.cdf_first_window_m[ei].push_back(percentileSorted(first, q));
    }
    s.all[ei] = summarizeErrors(std::move(all));
    s.first_window[ei] = summarizeErrors(std::move(first));
    s.after_window[ei] = summarizeErrors(std::move(after));
    if (s.representative >= 0)
      s.representative_flight[ei] = flights[static_cast<std::size_t>(s.representative)].summary(e);
  }
  return s;
}

const std::vector<MonteCarloConfiguration>& monteCarloConfigurations() {
  static const std::vector<MonteCarloConfiguration> kConfigurations = {
      {"gps_float", {GnssSystem::GPS}, false},
      {"gps_ar", {GnssSystem::GPS}, true},
      {"gps_galileo_float", {GnssSystem::GPS, GnssSystem::Galileo}, false},
      {"gps_galileo_ar", {GnssSystem::GPS, GnssSystem::Galileo}, true},
  };
  return kConfigurations;
}

const MonteCarloConfiguration* findMonteCarloConfiguration(const std::string& name) {
  for (const auto& c : monteCarloConfigurations())
    if (c.name == name) return &c;
  return nullptr;
}

MonteCarloOptions withConfiguration(MonteCarloOptions options, const MonteCarloConfiguration& configuration) {
  options.simulation.systems = configuration.systems;
  options.simulation.errors.ambiguity.satellite_phase_biases = true;
  // Products consistent with the phase biases (monte_carlo.h): the truth, or an analysis centre's errors.
  if (options.simulation.errors.products.model != ErrorModelConfig::ProductErrorModel::AnalysisCentre)
    options.simulation.errors.products.enabled = false;
  options.ppp.ambiguity_resolution.enabled = configuration.ambiguity_resolution;
  return options;
}

MonteCarloResult runMonteCarlo(const MonteCarloOptions& options, const std::function<void(int, int)>& progress) {
  const auto t0 = Clock::now();
  MonteCarloResult result;
  result.options = options;
  const int n = std::max(0, options.flights);
  result.flights.resize(static_cast<std::size_t>(n));
  unsigned threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  threads = std::min<unsigned>(threads, static_cast<unsigned>(std::max(1, n)));
  result.threads_used = threads;
  std::atomic<int> next{0};
  std::mutex mutex;
  int done = 0;
  auto worker = [&]() {
    for (int i = next++; i < n; i = next++) {
      MonteCarloFlightRun r = runMonteCarloFlight(options, options.first_flight + i);  // fully independent
      std::lock_guard<std::mutex> lock(mutex);
      result.flights[static_cast<std::size_t>(i)] = std::move(r);
      ++done;
      if (progress) progress(done, n);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  result.summary = summarizeMonteCarlo(result.flights, options);
  result.wall_s = secondsSince(t0);
  return result;
}

}  // namespace ppp
