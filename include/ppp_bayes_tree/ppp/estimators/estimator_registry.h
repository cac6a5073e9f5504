#pragma once
// The estimator registry: the one table of the PPP estimators that the tools,
// the campaign manifests and the Monte Carlo study offer by name. Each row gives
// the estimator's name (option value, file-name part), its table label, a
// one-line description (ppp_solve --help), the solutions it gives (filtered
// only, or filtered and smoothed) and its factory.
//
// Adding an estimator: its own files (an EpochEstimator, epoch_estimator.h) and
// one row in kEstimators below; option parsing, help texts, the output files of
// ppp_solve (one set per solution, solutionOutputs()), "both" and the campaign
// manifests follow from the table. The Monte Carlo study runs the estimators
// that evaluation/monte_carlo.h kMonteCarloStudy names, through their factories
// and the EpochEstimator interface (bias estimates by arc, the last result, and
// for one that smooths its final smoothed solution); its solutions are the
// study's columns (kMonteCarloEstimators).
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

namespace ppp {

class EpochEstimator;
struct EstimatorOptions;

/// The solutions an estimator gives.
enum class EstimatorSolutions {
  Filtered,             // one causal solution per epoch (a filter)
  FilteredAndSmoothed,  // the causal one and the smoothed trajectory (EpochEstimator::smoothing())
};

using EstimatorFactory = std::unique_ptr<EpochEstimator> (*)(const EstimatorOptions& options);

struct EstimatorEntry {
  std::string_view name;         // "ekf": option value and file-name part (EpochEstimator::name())
  std::string_view label;        // "EKF": its (filtered) column in tables
  std::string_view description;  // one line for --help
  EstimatorSolutions solutions = EstimatorSolutions::Filtered;
  EstimatorFactory make = nullptr;

  constexpr bool smoothed() const { return solutions == EstimatorSolutions::FilteredAndSmoothed; }
  /// Number of solutions (1 or 2).
  constexpr int solutionCount() const { return smoothed() ? 2 : 1; }
};

// The factories of the registered estimators (epoch_estimator.cpp).
std::unique_ptr<EpochEstimator> makeEkfEstimator(const EstimatorOptions& options);
std::unique_ptr<EpochEstimator> makeSmootherEstimator(const EstimatorOptions& options);

/// Every estimator, in the order in which "both" runs them and tables list them.
inline constexpr std::array<EstimatorEntry, 2> kEstimators{{
    {"ekf", "EKF", "forward extended Kalman filter (EkfPpp): filtered solution",
     EstimatorSolutions::Filtered, &makeEkfEstimator},
    {"smoother", "smoother", "incremental smoother (iSAM2, PppSmoother): filtered and smoothed solutions",
     EstimatorSolutions::FilteredAndSmoothed, &makeSmootherEstimator},
}};

/// The option value that runs every registered estimator (one pipeline each).
inline constexpr std::string_view kAllEstimators = "both";

/// Total number of solutions of all registered estimators (the Monte Carlo columns).
constexpr int registeredSolutionCount() {
  int n = 0;
  for (const EstimatorEntry& e : kEstimators) n += e.solutionCount();
  return n;
}

/// The entry of `name`; nullptr when none is registered under it.
const EstimatorEntry* findEstimator(std::string_view name);

/// The registered names joined by `separator` ("ekf, smoother").
std::string registeredEstimatorNames(std::string_view separator = ", ");

/// The values an estimator option accepts: every registered name and kAllEstimators.
std::set<std::string> estimatorChoices();

/// The default estimator (the first registered one).
inline constexpr std::string_view kDefaultEstimator = kEstimators.front().name;

/// The estimators an option value selects: one registered name, or kAllEstimators
/// for all of them (registry order). nullopt for anything else, with `why` (when
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
