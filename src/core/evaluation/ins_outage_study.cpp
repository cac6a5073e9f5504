#include "ppp_bayes_tree/evaluation/ins_outage_study.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "ppp_bayes_tree/evaluation/ins_coast_from_truth.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/simulated_imu.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double wrapped_rad(double a) { return std::atan2(std::sin(a), std::cos(a)); }

/// What an estimator gave at each epoch (index = the flight's epochs).
struct EpochTrack {
  std::vector<std::optional<Eigen::Vector3d>> predicted_m;  // the position before the update
  std::vector<char> fixed;
  std::size_t fixed_over_threshold = 0;  // fixed epochs > kWrongFixThreshold_m from the truth
  std::vector<char> attitude_scored;
  std::vector<Eigen::Vector3d> attitude_error_rad;  // roll, pitch, heading (estimate - truth)
};

/// The simulation of flight `setup` with the study's IMU grade; outages every
/// outage_every_s after `first_fix_s` (none without it).
SimulationConfig outageSimulation(const InsOutageStudyOptions& o, const MonteCarloFlightSetup& setup,
                                  std::optional<double> first_fix_s) {
  SimulationConfig c = monteCarloSimulationConfig(o.flights, setup);
  c.imu.enabled = true;
  c.imu.grade = o.grade;
  c.imu.rate_hz = o.imu_rate_hz;
  c.imu.errors = o.imu_errors;
  if (!first_fix_s) return c;
  // Each outage with its whole period before the end (the re-fix window is outage_every_s - outage_s).
  for (double t = *first_fix_s + o.outage_every_s; t + o.outage_every_s <= o.flights.duration_s; t += o.outage_every_s)
    c.outages.push_back({t, o.outage_s, o.outage_keeps_lock});
  return c;
}

/// Whether the registered estimator has inertial states (EstimatedState::GnssInertial):
/// it takes the IMU and the study's start (insConfig), and is scored with its coast
/// and attitude.
bool hasInertialStates(const EstimatorEntry& entry) { return entry.state == EstimatedState::GnssInertial; }

/// The registered estimator `name` (insOutageEstimatorsProblem has checked the names).
const EstimatorEntry& studiedEntry(const std::string& name) {
  const EstimatorEntry* entry = findEstimator(name);
  if (!entry) throw std::invalid_argument(insOutageEstimatorsProblem({name}));
  return *entry;
}

/// The GNSS/INS estimator's start from the truth of the first epoch moved by the study's errors.
PppConfig insConfig(PppConfig c, const SimulatedFlight& f, const InsOutageStudyOptions& o) {
  const TrajectorySample& first = f.truth.front().trajectory;
  c.ins.noise = f.imu.noise;
  c.ins.initial_rotation_ecef_body =
      ecefFromBody(first) * so3::expMap(Eigen::Vector3d::Constant(o.start_attitude_error_rad));
  c.ins.initial_velocity_ecef_mps = first.velocity_ecef_mps + Eigen::Vector3d::Constant(o.start_velocity_error_mps);
  return c;
}

/// Estimator `entry`'s configuration on flight `f` (config: the flight's): with inertial
/// states, the study's start (insConfig); one that smooths, the Monte Carlo study's fixed
/// lag for its filtered solution (MonteCarloOptions::smoother_filtered_lag_s; 0: the config's).
PppConfig estimatorConfig(const PppConfig& config, const SimulatedFlight& f, const EstimatorEntry& entry,
                          const InsOutageStudyOptions& o) {
  PppConfig c = hasInertialStates(entry) ? insConfig(config, f, o) : config;
  if (entry.smoothed() && o.flights.smoother_filtered_lag_s > 0.0) c.smoother.fixed_lag_s = o.flights.smoother_filtered_lag_s;
  return c;
}

/// Roll, pitch and heading of the estimate minus the truth's.
Eigen::Vector3d attitudeError_rad(const NavState& s, const TrajectorySample& truth) {
  const EulerAngles e = eulerAngles(rotationEcefNed(truth.position_ecef_m).transpose() * s.rotation_world_body);
  return {wrapped_rad(e.roll_rad - truth.roll_rad), wrapped_rad(e.pitch_rad - truth.pitch_rad),
          wrapped_rad(e.yaw_rad - truth.yaw_rad)};
}

/// The time of ekf_ins's first fixed epoch on the flight without outages (since its start).
std::optional<double> insFirstFix_s(const SimulatedFlight& f, const PppConfig& config) {
  const FlightEstimatorTrack track = trackEstimatorOnFlight(f, config, "ekf_ins");
  const auto first = std::find(track.fixed.begin(), track.fixed.end(), 1);
  if (first == track.fixed.end()) return std::nullopt;
  return f.epochs[static_cast<std::size_t>(first - track.fixed.begin())].time - f.epochs.front().time;
}

/// Runs one estimator and records, per epoch, its prediction, whether its filtered
/// solution is fixed and (with inertial states) its attitude errors.
EpochTrack trackEpochs(const SimulatedFlight& f, const PppConfig& config, const EstimatorEntry& entry,
                       const InsOutageStudyOptions& o, HeldIntegerCheck& held) {
  EpochTrack t;
  const std::size_t n = f.epochs.size();
  t.predicted_m.assign(n, std::nullopt);
  t.attitude_scored.assign(n, 0);
  t.attitude_error_rad.assign(n, Eigen::Vector3d::Zero());
  const bool inertial = hasInertialStates(entry);
  std::optional<Eigen::Vector3d> last_solution;
  const FlightEstimatorTrack track = trackEstimatorOnFlight(
      f, config, std::string(entry.name), [&](std::size_t k, const PppEpochRecord& rec, const PppEstimator& e) {
        t.predicted_m[k] = inertial ? e.predictedAntennaPosition() : last_solution;
        if (rec.solution.position_ecef_m) last_solution = rec.solution.position_ecef_m;
        const double since_start_s = f.epochs[k].time - f.epochs.front().time;
        if (!inertial || since_start_s < o.alignment_s) return;
        if (const std::optional<InertialState> s = e.inertialState()) {
          t.attitude_scored[k] = 1;
          t.attitude_error_rad[k] = attitudeError_rad(s->nav, f.truth[k].trajectory);
        }
      });
  t.fixed = track.fixed;
  for (std::size_t k = 0; k < n; ++k)
    if (t.fixed[k] && track.position_ecef_m[k] &&
        (*track.position_ecef_m[k] - f.truth[k].trajectory.position_ecef_m).norm() > kWrongFixThreshold_m)
      ++t.fixed_over_threshold;
  held = track.held_check;
  return t;
}

/// The horizontal error of the coast from the truth of epoch k - 1 to epoch k (infinite when not covered).
double truthCoastHorizontal_m(const SimulatedFlight& f, std::size_t k) {
  const auto error = insCoastErrorFromTruth_enu_m(f.imu, f.truth[k - 1].trajectory, f.truth[k].trajectory);
  return error ? error->head<2>().norm() : kInf;
}

/// The outage figures from the epochs: each epoch that follows a gap starts an outage's end
/// (with_truth_coast: the coast from the truth through it as well).
void scoreOutages(const SimulatedFlight& f, const EpochTrack& t, bool with_truth_coast, InsOutageFigures& fig) {
  const std::size_t n = f.epochs.size();
  const double interval_s = n > 1 ? f.epochs[1].time - f.epochs[0].time : 1.0;
  const auto gapBefore = [&](std::size_t k) { return k > 0 && f.epochs[k].time - f.epochs[k - 1].time > 1.5 * interval_s; };
  const auto first_fix = std::find(t.fixed.begin(), t.fixed.end(), 1);
  if (first_fix == t.fixed.end()) return;
  fig.first_fixes = 1;
  const std::size_t first = static_cast<std::size_t>(first_fix - t.fixed.begin());
  for (std::size_t k = first + 1; k < n; ++k) {
    if (!gapBefore(k)) continue;
    ++fig.outages_counted;
    if (t.fixed[k]) ++fig.fix_kept;
    const Eigen::Vector3d truth = f.truth[k].trajectory.position_ecef_m;
    if (t.predicted_m[k]) fig.outage_end_horizontal_m.push_back(ecefToEnu(*t.predicted_m[k], truth).head<2>().norm());
    else fig.outage_end_horizontal_m.push_back(kInf);
    if (with_truth_coast) fig.truth_coast_horizontal_m.push_back(truthCoastHorizontal_m(f, k));
    double refix = kInf;
    for (std::size_t j = k; j < n && (j == k || !gapBefore(j)); ++j)
      if (t.fixed[j]) {
        refix = f.epochs[j].time - f.epochs[k].time;
        break;
      }
    fig.refix_s.push_back(refix);
  }
}

void scoreAttitude(const EpochTrack& t, InsOutageFigures& fig) {
  for (std::size_t k = 0; k < t.attitude_scored.size(); ++k) {
    if (!t.attitude_scored[k]) continue;
    const Eigen::Vector3d& e = t.attitude_error_rad[k];
    fig.roll_sq_sum_rad2 += e.x() * e.x();
    fig.pitch_sq_sum_rad2 += e.y() * e.y();
    fig.heading_sq_sum_rad2 += e.z() * e.z();
    ++fig.attitude_epochs;
  }
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string number(double v, int digits) {
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return "never";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

std::string rmsDeg(double sum_sq_rad2, std::size_t count) {
  return count ? number(std::sqrt(sum_sq_rad2 / static_cast<double>(count)) * kRadToDeg, 3) : "-";
}

/// What the table says of the smoothers' filtered solution; empty without a smoother.
std::string smootherLagText(const InsOutageStudyOptions& o) {
  const bool smoother = std::any_of(o.estimators.begin(), o.estimators.end(), [](const std::string& name) {
    const EstimatorEntry* entry = findEstimator(name);
    return entry && entry->smoothed();
  });
  if (!smoother) return {};
  const double lag_s = o.flights.smoother_filtered_lag_s;
  return std::string(" (a smoother's: its estimate of the newest state as that epoch was solved, ") +
         (lag_s > 0.0 ? "fixed lag " + number(lag_s, 0) + " s" : "the whole graph kept") + "; not its smoothed solution)";
}

}  // namespace

std::string insOutageEstimatorsProblem(const std::vector<std::string>& names) {
  const std::string registered = " (registered: " + registeredEstimatorNames() + ")";
  if (names.empty()) return "no estimator given" + registered;
  std::set<std::string> seen;
  for (const std::string& name : names) {
    if (!findEstimator(name)) return "unknown estimator '" + name + "'" + registered;
    if (!seen.insert(name).second) return "estimator '" + name + "' given twice";
  }
  return {};
}

void InsOutageFigures::add(const InsOutageFigures& o) {
  outage_end_horizontal_m.insert(outage_end_horizontal_m.end(), o.outage_end_horizontal_m.begin(),
                                 o.outage_end_horizontal_m.end());
  truth_coast_horizontal_m.insert(truth_coast_horizontal_m.end(), o.truth_coast_horizontal_m.begin(),
                                  o.truth_coast_horizontal_m.end());
  refix_s.insert(refix_s.end(), o.refix_s.begin(), o.refix_s.end());
  outages_counted += o.outages_counted;
  fix_kept += o.fix_kept;
  first_fixes += o.first_fixes;
  roll_sq_sum_rad2 += o.roll_sq_sum_rad2;
  pitch_sq_sum_rad2 += o.pitch_sq_sum_rad2;
  heading_sq_sum_rad2 += o.heading_sq_sum_rad2;
  attitude_epochs += o.attitude_epochs;
  held_check.add(o.held_check);
  fixed_epochs_over_threshold += o.fixed_epochs_over_threshold;
}

InsOutageFlight runInsOutageFlight(const InsOutageStudyOptions& options, int index) {
  InsOutageFlight out;
  out.setup = monteCarloFlightSetup(options.flights, index);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    // The outages follow ekf_ins's first fix on the same flight without them (the
    // simulation up to the first outage does not depend on the outages).
    const SimulatedFlight clear = simulateFlight(outageSimulation(options, out.setup, std::nullopt), out.setup.seed);
    const PppConfig clear_config = flightPppConfig(options.flights.ppp, clear);
    out.first_fix_s = insFirstFix_s(clear, insConfig(clear_config, clear, options));
    const SimulatedFlight f = simulateFlight(outageSimulation(options, out.setup, out.first_fix_s), out.setup.seed);
    const PppConfig config = flightPppConfig(options.flights.ppp, f);
    for (const std::string& name : options.estimators) {
      const EstimatorEntry& entry = studiedEntry(name);
      InsOutageFigures fig;
      const EpochTrack t = trackEpochs(f, estimatorConfig(config, f, entry, options), entry, options, fig.held_check);
      scoreOutages(f, t, hasInertialStates(entry), fig);
      scoreAttitude(t, fig);
      fig.fixed_epochs_over_threshold = t.fixed_over_threshold;
      out.estimators.push_back(std::move(fig));
    }
  } catch (const std::exception& e) {
    out.failure = e.what();
    out.estimators.clear();
  }
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

InsOutageStudy runInsOutageStudy(const InsOutageStudyOptions& options) {
  if (const std::string problem = insOutageEstimatorsProblem(options.estimators); !problem.empty())
    throw std::invalid_argument("GNSS/INS outage study: " + problem);
  InsOutageStudy study;
  study.options = options;
  const int n = options.flights.flights;
  study.flights.resize(static_cast<std::size_t>(std::max(0, n)));
  const auto t0 = std::chrono::steady_clock::now();
  const unsigned threads =
      std::max(1u, std::min<unsigned>(options.flights.threads ? options.flights.threads : std::thread::hardware_concurrency(),
                                      static_cast<unsigned>(std::max(1, n))));
  std::atomic<int> next{0};
  std::vector<std::thread> pool;
  for (unsigned i = 0; i < threads; ++i)
    pool.emplace_back([&] {
      for (int k = next++; k < n; k = next++)
        study.flights[static_cast<std::size_t>(k)] = runInsOutageFlight(options, options.flights.first_flight + k);
    });
  for (auto& t : pool) t.join();
  study.total.assign(options.estimators.size(), InsOutageFigures{});
  for (const auto& f : study.flights) {
    if (!f.failure.empty()) {
      ++study.failed;
      continue;
    }
    for (std::size_t e = 0; e < study.total.size(); ++e) study.total[e].add(f.estimators[e]);
  }
  study.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return study;
}

std::string insOutageMarkdown(const InsOutageStudy& study) {
  const InsOutageStudyOptions& o = study.options;
  std::ostringstream s;
  s << "GNSS outages of " << number(o.outage_s, 0) << " s every " << number(o.outage_every_s, 0) << " s"
    << (o.outage_keeps_lock ? " (lock kept)" : "") << ", "
    << imuGradeText(o.grade) << " IMU at " << number(o.imu_rate_hz, 0) << " Hz"
    << (o.imu_errors ? "" : " (true readings: no noise, no bias)") << "; " << study.flights.size()
    << " flights (" << study.failed << " failed), " << number(o.flights.duration_s / 60.0, 0)
    << " min each; outages counted after each estimator's first fix; attitude after " << number(o.alignment_s, 0)
    << " s. Every row scores the estimator's filtered (real-time) solution of each epoch"
    << smootherLagText(o) << ".\n";
  std::vector<double> first_fix_s;
  int never_fixed = 0;
  for (const auto& f : study.flights) {
    if (!f.failure.empty()) continue;
    if (f.first_fix_s) first_fix_s.push_back(*f.first_fix_s);
    else ++never_fixed;
  }
  s << "ekf_ins's first fix on the flights without outages: median " << number(median(first_fix_s), 0)
    << " s over the " << first_fix_s.size() << " flights it fixes (" << never_fixed
    << " never fixed: no outage).\n\n";
  s << "| estimator | flights fixed | outages counted | horizontal error at the outage end, median [m] | "
       "coast from the truth, median [m] | re-fix after the outage, median [s] (never) | fixed at the first epoch after | roll RMS [deg] | "
       "pitch RMS [deg] | heading RMS [deg] | held integers (wrong) | fixed epochs with a wrong hold | "
       "fixed epochs > "
    << number(kWrongFixThreshold_m * 100.0, 0) << " cm (of) |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t e = 0; e < study.total.size(); ++e) {
    const InsOutageFigures& f = study.total[e];
    const long never = std::count_if(f.refix_s.begin(), f.refix_s.end(), [](double v) { return std::isinf(v); });
    s << "| " << o.estimators[e] << " | " << f.first_fixes << " | " << f.outages_counted << " | "
      << number(median(f.outage_end_horizontal_m), 2) << " | "
      << (f.truth_coast_horizontal_m.empty() ? "-" : number(median(f.truth_coast_horizontal_m), 2)) << " | "
      << number(median(f.refix_s), 0) << " (" << never
      << ") | " << f.fix_kept << " | " << rmsDeg(f.roll_sq_sum_rad2, f.attitude_epochs) << " | "
      << rmsDeg(f.pitch_sq_sum_rad2, f.attitude_epochs) << " | " << rmsDeg(f.heading_sq_sum_rad2, f.attitude_epochs)
      << " | " << f.held_check.held << " (" << f.held_check.wrong << ") | "
      << f.held_check.fixed_epochs_with_wrong_hold << " | " << f.fixed_epochs_over_threshold << " ("
      << f.held_check.fixed_epochs << ") |\n";
  }
  s << "\nWall time " << number(study.wall_s, 1) << " s.\n";
  return s.str();
}

std::string insOutageWrongHoldsCsv(const InsOutageStudy& study) {
  std::ostringstream s;
  s << "flight,estimator,time_s,satellite,reference,wide_lane_held,wide_lane_true,narrow_lane_held,"
       "narrow_lane_true,float_cycles,sigma_cycles,ratio,success_rate\n";
  for (const InsOutageFlight& f : study.flights)
    for (std::size_t e = 0; e < f.estimators.size(); ++e)
      for (const WrongHold& w : f.estimators[e].held_check.wrong_holds)
        s << f.setup.index << ',' << study.options.estimators[e] << ',' << number(w.time_s, 0) << ','
          << w.satellite.toString() << ',' << w.reference_satellite.toString() << ',' << w.wide_lane_cycles << ','
          << w.true_wide_lane_cycles << ',' << w.held_cycles << ',' << number(w.true_cycles, 3) << ','
          << number(w.float_cycles, 3) << ',' << number(w.sigma_cycles, 3) << ',' << number(w.ratio, 2) << ','
          << number(w.bootstrap_success_rate, 6) << '\n';
  return s.str();
}

}  // namespace ppp
