#pragma once
// The estimator registry: the one table of the PPP estimators, and the only
// place that makes them (makeEstimator). The tools, the campaign manifests, the
// benchmarks, the ROS node and the Monte Carlo study offer and make estimators
// by name through it. Each row gives the estimator's name (option value,
// file-name part), its table label, a one-line description (ppp_solve --help),
// the solutions it gives (filtered only, or filtered and smoothed), the state it
// estimates, whether the Monte Carlo study runs it, and its factory.
//
// Adding an estimator: its own files (a PppEstimator, ppp_estimator.h) and one
// row in kEstimators below; option parsing, help texts, the output files of
// ppp_solve (one set per solution, solutionOutputs()), "both", the campaign
// manifests and the Monte Carlo study (kMonteCarloStudy: the rows marked for
// it) follow from the table. An estimator of another state (e.g. a GNSS/INS
// state) is one more EstimatedState and its rows, in the same family.
//
// The table is a constant (no registration at static initialisation, no global
// mutable state).
#include <array>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "ppp_bayes_tree/ppp/estimators/estimator_options.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_estimator.h"

namespace ppp {

/// The state an estimator estimates.
enum class EstimatedState {
  GnssReceiver,  // receiver position, zenith wet delay, clocks (gradients), phase biases
  GnssInertial,  // INS error state (attitude, velocity, position, IMU biases), zenith wet delay, clocks, phase biases
};

constexpr std::string_view estimatedStateText(EstimatedState state) {
  switch (state) {
    case EstimatedState::GnssReceiver:
      return "GNSS receiver (position, zenith wet delay, clocks, phase biases)";
    case EstimatedState::GnssInertial:
      return "GNSS and inertial (attitude, velocity, position, IMU biases, zenith wet delay, clocks, phase biases)";
  }
  return "unknown";
}

/// The solutions an estimator gives.
enum class EstimatorSolutions {
  Filtered,             // one causal solution per epoch (a filter)
  FilteredAndSmoothed,  // the causal one and the smoothed trajectory (PppEstimator::smoothing())
};

using EstimatorFactory = std::unique_ptr<PppEstimator> (*)(const EstimatorOptions& options);

struct EstimatorEntry {
  std::string_view name;         // "ekf": option value and file-name part (PppEstimator::name())
  std::string_view label;        // "EKF": its (filtered) column in tables
  std::string_view description;  // one line for --help
  EstimatorSolutions solutions = EstimatorSolutions::Filtered;
  EstimatedState state = EstimatedState::GnssReceiver;
  bool monte_carlo_study = false;  // the Monte Carlo study runs it (kMonteCarloStudy)
  EstimatorFactory make = nullptr;

  constexpr bool smoothed() const { return solutions == EstimatorSolutions::FilteredAndSmoothed; }
  /// Number of solutions (1 or 2).
  constexpr int solutionCount() const { return smoothed() ? 2 : 1; }
};

// The factories of the registered estimators (estimator_registry.cpp); reached
// through the table (makeEstimator), not called by name.
std::unique_ptr<PppEstimator> makePppEkf(const EstimatorOptions& options);
std::unique_ptr<PppEstimator> makePppSmoother(const EstimatorOptions& options);
std::unique_ptr<PppEstimator> makePppInsEkf(const EstimatorOptions& options);
std::unique_ptr<PppEstimator> makePppInsSmoother(const EstimatorOptions& options);

/// Every estimator, in the order in which "both" runs them and tables list them.
/// "both" runs the estimators of the GNSS receiver state only (runsInAll): an
/// estimator with inertial states needs IMU readings and is run by its name.
inline constexpr std::array<EstimatorEntry, 4> kEstimators{{
    {"ekf", "EKF", "forward extended Kalman filter (PppEkf): filtered solution",
     EstimatorSolutions::Filtered, EstimatedState::GnssReceiver, true, &makePppEkf},
    {"smoother", "smoother", "incremental smoother (iSAM2, PppSmoother): filtered and smoothed solutions",
     EstimatorSolutions::FilteredAndSmoothed, EstimatedState::GnssReceiver, true, &makePppSmoother},
    {"ekf_ins", "EKF GNSS/INS",
     "tightly coupled GNSS/INS error-state Kalman filter (PppInsEkf, needs --imu): filtered solution",
     EstimatorSolutions::Filtered, EstimatedState::GnssInertial, false, &makePppInsEkf},
    {"smoother_ins", "smoother GNSS/INS",
     "tightly coupled GNSS/INS incremental smoother (iSAM2 with IMU preintegration, PppInsSmoother, needs --imu): "
     "filtered and smoothed solutions",
     EstimatorSolutions::FilteredAndSmoothed, EstimatedState::GnssInertial, false, &makePppInsSmoother},
}};

/// Whether kAllEstimators ("both") runs the estimator: the GNSS receiver state only.
constexpr bool runsInAll(const EstimatorEntry& entry) { return entry.state == EstimatedState::GnssReceiver; }

/// Number of estimators the Monte Carlo study runs.
constexpr std::size_t monteCarloStudyCount() {
  std::size_t n = 0;
  for (const EstimatorEntry& e : kEstimators) n += e.monte_carlo_study ? 1 : 0;
  return n;
}

/// The estimators the Monte Carlo study runs, by name, in registry order (the
/// rows with monte_carlo_study). The first is the study's reference.
inline constexpr std::array<std::string_view, monteCarloStudyCount()> kMonteCarloStudy = [] {
  std::array<std::string_view, monteCarloStudyCount()> names{};
  std::size_t i = 0;
  for (const EstimatorEntry& e : kEstimators)
    if (e.monte_carlo_study) names[i++] = e.name;
  return names;
}();

/// The option value that runs every registered estimator of the GNSS receiver
/// state (runsInAll; one pipeline each).
inline constexpr std::string_view kAllEstimators = "both";

/// Total number of solutions of all registered estimators (the Monte Carlo columns).
constexpr int registeredSolutionCount() {
  int n = 0;
  for (const EstimatorEntry& e : kEstimators) n += e.solutionCount();
  return n;
}

/// The entry of `name`; nullptr when none is registered under it.
const EstimatorEntry* findEstimator(std::string_view name);

/// The estimator registered as `name`, made from `options`; nullptr for another
/// name (kAllEstimators included: the caller runs one pipeline each), with `why`
/// (when given) saying so.
std::unique_ptr<PppEstimator> makeEstimator(std::string_view name, const EstimatorOptions& options,
                                            std::string* why = nullptr);

/// makeEstimator as the estimator class the caller needs (e.g. PppSmoother for
/// its live sink); nullptr, with `why`, when the name is not registered or its
/// estimator is not an `Estimator`.
template <class Estimator>
std::unique_ptr<Estimator> makeEstimatorAs(std::string_view name, const EstimatorOptions& options,
                                           std::string* why = nullptr) {
  std::unique_ptr<PppEstimator> made = makeEstimator(name, options, why);
  if (auto* as = dynamic_cast<Estimator*>(made.get())) {
    made.release();
    return std::unique_ptr<Estimator>(as);
  }
  if (made && why) *why = "estimator '" + std::string(name) + "' is not of the class asked for";
  return nullptr;
}

/// The registered names joined by `separator` ("ekf, smoother").
std::string registeredEstimatorNames(std::string_view separator = ", ");

/// The values an estimator option accepts: every registered name and kAllEstimators.
std::set<std::string> estimatorChoices();

/// The default estimator (the first registered one).
inline constexpr std::string_view kDefaultEstimator = kEstimators.front().name;

/// The estimators an option value selects: one registered name, or kAllEstimators
/// for those that runsInAll (registry order). nullopt for anything else, with `why` (when
/// given) naming the value and listing the accepted ones.
std::optional<std::vector<const EstimatorEntry*>> selectEstimators(std::string_view value, std::string* why = nullptr);

/// One solution of an estimator: its file-name tag and label.
struct EstimatorSolution {
  std::string tag;          // "ekf"; "smoother_filtered", "smoother_smoothed"
  std::string label;        // "ekf"; "smoother filtered", "smoother smoothed"
  std::string table_label;  // "EKF"; "smoother filtered", "smoother smoothed"
  bool smoothed = false;
};

/// The solutions of an estimator, filtered first: a filter's one solution under
/// its name; a smoother's filtered and smoothed ones under name_filtered and
/// name_smoothed.
std::vector<EstimatorSolution> solutionOutputs(const EstimatorEntry& entry);

}  // namespace ppp
