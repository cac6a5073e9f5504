// Live smoothing with bounded memory: the fixed-lag PppSmoother hands
// each state leaving its window to a sink (setMarginalizedStateSink) and forgets
// it; SmoothedTrajectoryWriter writes those states as CSV rows. On the synthetic
// generator of ppp_simulator.h (10 s epochs, satellites rising and setting, cycle
// slips): every state is written exactly once, in time order, with the estimate an
// identical smoother without a sink keeps for it; the smoother's structures (states
// kept, graph variables, factors, cliques) stay within bounds set by the lag alone.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/lagged_trajectory_output.h"
#include "ppp_bayes_tree/evaluation/smoothed_trajectory_writer.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_bayes_tree/ppp/model/ppp_factors.h"
#include "ppp_simulator.h"

using namespace ppp;
using namespace ppp::sim;
namespace sm = ppp::smoother;

namespace {

constexpr double kDt_s = 10.0;

PppSmoother lagged(double lag_s) {
  PppSmootherOptions o;
  o.fixed_lag_s = lag_s;
  return PppSmoother(methodTableStochasticModel(), o);
}

/// One epoch of the simulator into the smoother (a slip every 37 epochs); returns the arcs observed.
std::set<ArcId> step(PppSmoother& s, Simulator& sim, int i) {
  if (s.initialised()) sim.t_s += kDt_s;
  std::vector<SimObs> obs = sim.epoch();
  if (i > 0 && i % 37 == 0) {
    sim.slip(obs.front().sat, 0.31);
    obs = sim.epoch();
  }
  const auto r = s.processEpoch(sim.time(), modelOf(obs, SimModelOptions{true}));
  EXPECT_EQ(r.status, EpochStatus::Ok) << "epoch " << i << ": " << r.reason;
  std::set<ArcId> arcs;
  for (const auto& o : obs) arcs.insert(o.arc);
  return arcs;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, ',')) out.push_back(field);
  return out;
}

}  // namespace

TEST(LiveSmoothing, WriterGetsEveryStateOnceInTimeOrderWithTheMarginalizedEstimate) {
  const int kEpochs = 300;
  Simulator sim_a, sim_b;
  sim_a.noise = sim_b.noise = true;
  PppSmoother a = lagged(120.0), b = lagged(120.0);  // a: live (sink); b: keeps every state
  std::ostringstream csv;
  SmoothedTrajectoryWriter writer(csv);
  std::vector<SmoothedEpoch> handed;
  std::vector<std::size_t> handed_at_epoch;  // epoch at which each state was handed out
  int epoch = 0;
  a.setMarginalizedStateSink([&](const SmoothedEpoch& e) {
    handed.push_back(e);
    handed_at_epoch.push_back(static_cast<std::size_t>(epoch));
    EXPECT_TRUE(writer.write(e)) << writer.lastProblem();
  });
  for (epoch = 0; epoch < kEpochs; ++epoch) {
    step(a, sim_a, epoch);
    step(b, sim_b, epoch);
  }
  const std::size_t during_run = handed.size();
  EXPECT_GT(during_run, 250u);  // all but the window (~13 states of 10 s for a lag of 120 s)
  EXPECT_EQ(a.finishTrajectory(), kEpochs - during_run);

  // Exactly once each, in time order.
  ASSERT_EQ(handed.size(), static_cast<std::size_t>(kEpochs));
  for (std::size_t k = 0; k < handed.size(); ++k) {
    EXPECT_EQ(handed[k].index, k);
    if (k > 0) EXPECT_LT(handed[k - 1].time, handed[k].time);
  }
  // The states handed out during the run: the estimate the smoother without a sink
  // keeps for them once marginalized (identical computations: equal to rounding);
  // the rest (finishTrajectory): its current estimate of the window.
  const std::vector<SmoothedEpoch> kept = b.smoothedTrajectory();
  ASSERT_EQ(kept.size(), static_cast<std::size_t>(kEpochs));
  for (std::size_t k = 0; k < handed.size(); ++k) {
    EXPECT_EQ(kept[k].time, handed[k].time);
    EXPECT_LT((kept[k].state.vector() - handed[k].state.vector()).norm(), 1e-9) << "state " << k;
  }
  // A state handed out during the run was no longer in the graph; the lag held it
  // at least lag seconds (12 epochs) after its own epoch.
  for (std::size_t k = 0; k < during_run; ++k) {
    EXPECT_FALSE(a.isam2().exists(stateKey(handed[k].index)));
    EXPECT_GE(handed_at_epoch[k], k + 12);
  }
  // Only the window is held in memory.
  EXPECT_EQ(a.storedStateCount(), 1u);  // after finishTrajectory: the newest only
  EXPECT_EQ(b.storedStateCount(), static_cast<std::size_t>(kEpochs));

  // The CSV: the header, then one row per state with its index and position.
  std::istringstream in(csv.str());
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, SmoothedTrajectoryWriter::headerRow());
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    const auto f = split(line);
    ASSERT_EQ(f.size(), 12u) << line;
    ASSERT_LT(rows, kept.size());
    EXPECT_EQ(std::stoul(f[11]), kept[rows].index);
    EXPECT_NEAR(std::stod(f[3]), kept[rows].state.position_ecef_m.x(), 5.1e-5);
    EXPECT_NEAR(std::stod(f[5]), kept[rows].state.position_ecef_m.z(), 5.1e-5);
    ++rows;
  }
  EXPECT_EQ(rows, static_cast<std::size_t>(kEpochs));
  EXPECT_EQ(writer.rowsWritten(), static_cast<std::size_t>(kEpochs));

  // A state fed twice (or out of order) is refused and counted, never written.
  EXPECT_FALSE(writer.write(handed.back()));
  EXPECT_FALSE(writer.write(handed.front()));
  EXPECT_EQ(writer.rowsRefused(), 2u);
  EXPECT_NE(writer.lastProblem().find("not after the last row"), std::string::npos) << writer.lastProblem();
  EXPECT_EQ(writer.rowsWritten(), static_cast<std::size_t>(kEpochs));
}

TEST(LiveSmoothing, WriterRefusesAFileItCannotCreate) {
  EXPECT_THROW(SmoothedTrajectoryWriter("/nonexistent-dir/trajectory.csv"), std::runtime_error);
}

TEST(LiveSmoothing, FixedLagStructuresStayWithinBoundsSetByTheLag) {
  // Bounds from the lag alone: the fixed-lag smoother keeps a state for at most
  // 1.1 lag (age buckets of a tenth of the lag) plus one epoch of delay before
  // it reaches the leaves; per state at most 1 random walk + 1 clock prior + 2
  // factors per satellite (<= 30) + one bias prior per new arc; the marginal
  // priors number at most one per clique.
  const int kEpochs = 600;  // 100 min of 10 s epochs: satellites rise and set
  for (const double lag_s : {60.0, 180.0}) {
    SCOPED_TRACE("lag " + std::to_string(lag_s) + " s");
    Simulator sim;
    sim.noise = true;
    PppSmoother s = lagged(lag_s);
    std::size_t handed = 0;
    s.setMarginalizedStateSink([&](const SmoothedEpoch&) { ++handed; });
    const std::size_t window_states = static_cast<std::size_t>(1.1 * lag_s / kDt_s) + 2;
    const std::size_t max_factors_per_state = 1 + 1 + 2 * 30 + 30;
    std::map<int, std::set<ArcId>> arcs_by_epoch;
    std::size_t max_states = 0, max_factors = 0;
    for (int i = 0; i < kEpochs; ++i) {
      arcs_by_epoch[i] = step(s, sim, i);
      const sm::ISAM2& isam = s.isam2();
      std::size_t states = 0, biases = 0;
      for (const auto& [key, value] : isam.linearizationPoint()) (sm::keySymbol(key) == 'x' ? states : biases)++;
      // Arcs observed within the window's span.
      std::set<ArcId> recent;
      for (int j = std::max(0, i - static_cast<int>(window_states)); j <= i; ++j)
        recent.insert(arcs_by_epoch[j].begin(), arcs_by_epoch[j].end());
      ASSERT_LE(states, window_states) << "epoch " << i;
      ASSERT_LE(s.storedStateCount(), window_states) << "epoch " << i;
      ASSERT_LE(biases, recent.size()) << "epoch " << i;
      ASSERT_LE(s.storedBiasCount(), recent.size()) << "epoch " << i;
      const std::size_t cliques = isam.bayesTree().numCliques();
      ASSERT_LE(cliques, states + biases);
      ASSERT_LE(isam.numFactors(), window_states * max_factors_per_state + cliques) << "epoch " << i;
      max_states = std::max(max_states, states);
      max_factors = std::max(max_factors, isam.numFactors());
      arcs_by_epoch.erase(i - static_cast<int>(window_states) - 1);
    }
    // The bounds are reached, not vacuous: the window is (nearly) full and the
    // states left behind were handed out.
    EXPECT_GE(max_states, static_cast<std::size_t>(lag_s / kDt_s));
    EXPECT_GE(handed + s.storedStateCount(), static_cast<std::size_t>(kEpochs));
    EXPECT_GT(max_factors, static_cast<std::size_t>(lag_s / kDt_s) * 2);
  }
}

TEST(LiveSmoothing, LaggedOutputKeepsOnlyTheNewestStatesAndJoinsThemToTheWindowOnce) {
  Simulator sim;
  sim.noise = true;
  PppSmoother s = lagged(60.0);
  LaggedTrajectoryOutput out("", 5);  // no file; the 5 newest states handed out
  out.attach(s);
  for (int i = 0; i < 60; ++i) step(s, sim, i);
  ASSERT_GT(out.statesHandedOut(), 40u);
  ASSERT_EQ(out.recent().size(), 5u);
  const std::vector<SmoothedEpoch> window = s.smoothedTrajectory();
  EXPECT_EQ(out.recent().back().index + 1, window.front().index);  // contiguous: nothing lost, nothing twice
  const std::vector<SmoothedEpoch> joined = out.joined(window, 1000);
  ASSERT_EQ(joined.size(), 5u + window.size());
  for (std::size_t k = 1; k < joined.size(); ++k) EXPECT_EQ(joined[k].index, joined[k - 1].index + 1);
  const std::vector<SmoothedEpoch> last3 = out.joined(window, 3);  // the newest 3 only
  ASSERT_EQ(last3.size(), 3u);
  EXPECT_EQ(last3.back().index, window.back().index);
}

TEST(LiveSmoothing, LiveConfigLoadsAFixedLagOverTheDefaults) {
  // config/live.yaml over the built-in defaults (= config/ppp.yaml): the keys it names change.
  const PppConfig c = loadPppConfig(std::string(PPP_REPO_DIR) + "/config/live.yaml");
  EXPECT_DOUBLE_EQ(c.smoother.fixed_lag_s, 60.0);
  EXPECT_DOUBLE_EQ(c.smoother.relinearize_position_m, 0.5);
  EXPECT_DOUBLE_EQ(c.smoother.relinearize_zwd_m, 0.01);
  EXPECT_DOUBLE_EQ(c.smoother.wildfire_threshold_m, 1.0e-3);
  EXPECT_EQ(c.smoother.validate(), "");
  EXPECT_DOUBLE_EQ(c.smoother.relinearize_clock_m, PppConfig{}.smoother.relinearize_clock_m);  // untouched
  ASSERT_TRUE(c.ros["smoothed"]["trajectory_csv"]);
  EXPECT_EQ(c.ros["smoothed"]["trajectory_csv"].as<std::string>(), "smoothed_trajectory.csv");
}
