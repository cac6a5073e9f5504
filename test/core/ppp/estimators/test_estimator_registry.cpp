// The estimator registry (ppp/estimators/estimator_registry.h): every registered name
// round-trips through the option parser and the factory, an unknown name is
// refused with the registered names listed, and every registered estimator
// solves a short simulated flight through the offline pipeline.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/ppp/estimators/epoch_estimator.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

namespace ppp {
namespace {

TEST(EstimatorRegistry, NamesRoundTripThroughTheParserAndTheFactory) {
  ASSERT_FALSE(kEstimators.empty());
  std::set<std::string> tags;
  for (const EstimatorEntry& entry : kEstimators) {
    const std::string name(entry.name);
    SCOPED_TRACE(name);
    EXPECT_FALSE(entry.description.empty());
    EXPECT_EQ(findEstimator(name), &entry);
    const auto selected = selectEstimators(name);
    ASSERT_TRUE(selected.has_value());
    ASSERT_EQ(selected->size(), 1u);
    EXPECT_EQ(selected->front(), &entry);
    EXPECT_EQ(estimatorChoices().count(name), 1u);
    std::string why;
    const std::unique_ptr<EpochEstimator> estimator = makeEstimator(name, PppConfig{}, &why);
    ASSERT_TRUE(estimator) << why;
    EXPECT_EQ(estimator->name(), name);
    // What the table says about the solutions is what the estimator gives.
    EXPECT_EQ(entry.smoothed(), estimator->smoothing() != nullptr);
    const std::vector<EstimatorSolution> solutions = solutionOutputs(entry);
    ASSERT_EQ(static_cast<int>(solutions.size()), entry.solutionCount());
    EXPECT_FALSE(solutions.front().smoothed);
    for (const EstimatorSolution& s : solutions) {
      EXPECT_EQ(s.tag.rfind(name, 0), 0u) << s.tag;  // file names start with the estimator's name
      EXPECT_TRUE(tags.insert(s.tag).second) << "tag " << s.tag << " given twice";
    }
  }
  // "both" selects every registered estimator, in the table's order.
  const auto all = selectEstimators(kAllEstimators);
  ASSERT_TRUE(all.has_value());
  ASSERT_EQ(all->size(), kEstimators.size());
  for (std::size_t i = 0; i < kEstimators.size(); ++i) EXPECT_EQ((*all)[i], &kEstimators[i]);
  EXPECT_EQ(estimatorChoices().size(), kEstimators.size() + 1);
  EXPECT_EQ(kDefaultEstimator, kEstimators.front().name);
  EXPECT_EQ(registeredSolutionCount(), static_cast<int>(tags.size()));
}

/// `text` names every registered estimator.
void expectListsEveryEstimator(const std::string& text) {
  for (const EstimatorEntry& e : kEstimators)
    EXPECT_NE(text.find(std::string(e.name)), std::string::npos) << "'" << e.name << "' missing in: " << text;
}

TEST(EstimatorRegistry, UnknownNameIsRefusedWithTheRegisteredNames) {
  std::string why;
  EXPECT_FALSE(selectEstimators("kalman", &why).has_value());
  EXPECT_NE(why.find("unknown estimator 'kalman'"), std::string::npos) << why;
  expectListsEveryEstimator(why);
  EXPECT_NE(why.find(std::string(kAllEstimators)), std::string::npos) << why;
  EXPECT_FALSE(selectEstimators("", &why).has_value());
  EXPECT_FALSE(selectEstimators("EKF").has_value());  // names are case-sensitive

  why.clear();
  EXPECT_EQ(makeEstimator("kalman", PppConfig{}, &why), nullptr);
  expectListsEveryEstimator(why);
  // "both" is no single estimator: the caller runs one pipeline per estimator.
  why.clear();
  EXPECT_EQ(makeEstimator(std::string(kAllEstimators), PppConfig{}, &why), nullptr);
  expectListsEveryEstimator(why);

  // ppp_solve's entry point refuses it before reading any file.
  PppSolveRequest request;
  request.estimator = "kalman";
  request.files.obs = "/nonexistent/obs.rnx";
  request.out_dir = "/nonexistent/out";
  try {
    solvePppEstimators(request);
    ADD_FAILURE() << "an unknown estimator was accepted";
  } catch (const std::invalid_argument& e) {
    expectListsEveryEstimator(e.what());
  }
}

// Each registered estimator, made by its factory, through the offline pipeline
// on a 4-minute simulated loiter flight (GPS, the Monte Carlo's error model and
// estimator configuration): it solves nearly every epoch and converges below
// 1 m (measured at seed 7: 241 of 241 epochs solved by both, mean 3D error of
// the last minute 0.643 m EKF, 0.644 m smoother filtered: the code-dominated
// start of a 4-minute flight); a smoothing estimator's smoothed trajectory
// covers the solved epochs.
TEST(EstimatorRegistry, EveryRegisteredEstimatorSolvesASimulatedFlight) {
  MonteCarloOptions o;
  o.flights = 1;
  o.seed = 7;
  o.duration_s = 240.0;
  o.profiles = {FlightProfile::Loiter};
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, 0);
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  const PppConfig config = flightPppConfig(o.ppp, f);
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  for (const EstimatorEntry& entry : kEstimators) {
    SCOPED_TRACE(std::string(entry.name));
    PppPipeline pipeline(in, config);
    const std::unique_ptr<EpochEstimator> estimator = entry.make(config);
    ASSERT_TRUE(estimator);
    std::size_t k = 0, solved = 0;
    double last_minute_sum_m = 0.0;
    std::size_t last_minute_n = 0;
    pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
      const std::size_t e = k++;
      if (!rec.solution.position_ecef_m) return;
      ++solved;
      if (f.epochs[e].time - f.epochs.front().time < o.duration_s - 60.0) return;
      last_minute_sum_m += (*rec.solution.position_ecef_m - f.truth[e].trajectory.position_ecef_m).norm();
      ++last_minute_n;
    });
    ASSERT_EQ(k, f.epochs.size());
    EXPECT_GE(solved, k * 95 / 100);
    ASSERT_GT(last_minute_n, 0u);
    const double last_minute_mean_m = last_minute_sum_m / static_cast<double>(last_minute_n);
    std::printf("%s: %zu of %zu epochs solved, mean 3D error of the last minute %.3f m\n",
                std::string(entry.name).c_str(), solved, k, last_minute_mean_m);
    EXPECT_LT(last_minute_mean_m, 1.0);
    if (entry.smoothed()) {
      ASSERT_NE(estimator->smoothing(), nullptr);
      EXPECT_EQ(estimator->smoothing()->smoothedTrajectory().size(), solved);
    }
  }
}

}  // namespace
}  // namespace ppp
