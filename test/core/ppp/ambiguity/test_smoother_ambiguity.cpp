// Ambiguity resolution in the Bayes-tree smoother: the fixed-ambiguity
// factor, the smoother's held fixes against a batch solve of the same graph,
// the fixes on simulated flights with integer ambiguities and published satellite
// phase biases (true integers, the smoothed trajectory improved before the fix
// epoch, the filtered solution near the EKF's fixed one), and a wrong fix
// injected, detected and removed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/ambiguity/integer_ambiguity_factor.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_bayes_tree/ppp/model/ppp_factors.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/smoother/numerical_jacobian.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"

using namespace ppp;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A flight with integer ambiguities and satellite phase biases published as OSBs.
MonteCarloOptions arStudy(double minutes, FlightProfile profile = FlightProfile::Loiter) {
  MonteCarloOptions o;
  o.flights = 1;
  o.seed = 7;
  o.duration_s = minutes * 60.0;
  o.profiles = {profile};
  o.simulation.errors.ambiguity.satellite_phase_biases = true;
  // Orbit and clock errors of several cm per satellite (products: enabled) are not
  // integer-consistent with the phase biases, as IGS clocks are not with CODE's
  // biases: the tests need products consistent with their biases.
  o.simulation.errors.products.enabled = false;
  // White code errors (no multipath), and the estimators told so: these tests are
  // about what the smoother does with its fixes, and need fixes within minutes on
  // a short GPS flight (with the simulator's 15-s Gauss-Markov multipath and the
  // time-correlated code and MW model that matches it, GPS alone fixes after
  // 25.7 min in the median, doc/studies/ar_real_data.md).
  o.simulation.errors.multipath.enabled = false;
  o.ppp.stochastic.code_correlation_time_s = 0.0;
  o.ppp.ambiguity_resolution.wide_lane.correlation_time_s = 0.0;
  o.ppp.ambiguity_resolution.enabled = true;
  return o;
}

struct EpochOutcome {
  std::optional<Eigen::Vector3d> position;
  bool fixed = false;
};

struct FlightRun {
  std::vector<EpochOutcome> epochs;
  std::vector<double> smoothed_error_m;  // per epoch index, NaN when none
  std::map<ArcId, std::pair<SatelliteId, std::size_t>> arc_start;  // estimator arc: satellite, first epoch
};

void recordArcs(const PppEpochRecord& rec, std::size_t k, FlightRun& run) {
  for (const auto& r : rec.residuals)
    if (!run.arc_start.count(r.arc)) run.arc_start[r.arc] = {r.satellite, k};
}

FlightRun runEkf(const SimulatedFlight& f, const PppConfig& config) {
  FlightRun run;
  PppPipeline pipeline(simulatedFlightInputs(f, 0), config);
  const std::unique_ptr<PppEstimator> ekf_made = makeEstimator("ekf", config);
  PppEstimator& ekf = *ekf_made;
  std::size_t k = 0;
  pipeline.run(ekf, [&](const PppEpochRecord& rec) {
    run.epochs.push_back({rec.solution.position_ecef_m, rec.solution.status == SolutionStatus::PppFixed});
    recordArcs(rec, k++, run);
  });
  return run;
}

/// `on_epoch` is called after each epoch with the smoother estimator.
FlightRun runSmoother(const SimulatedFlight& f, const PppConfig& config,
                      const std::function<void(std::size_t, PppSmoother&)>& on_epoch = {},
                      PppSmoother** keep = nullptr, bool record_graph = false) {
  FlightRun run;
  PppPipeline pipeline(simulatedFlightInputs(f, 0), config);
  PppConfig smoother_config = config;
  smoother_config.smoother.record_graph = record_graph;
  static thread_local std::unique_ptr<PppSmoother> last;
  last = makeEstimatorAs<PppSmoother>("smoother", smoother_config);
  PppSmoother& sm = *last;
  std::size_t k = 0;
  pipeline.run(sm, [&](const PppEpochRecord& rec) {
    run.epochs.push_back({rec.solution.position_ecef_m, rec.solution.status == SolutionStatus::PppFixed});
    recordArcs(rec, k, run);
    if (on_epoch) on_epoch(k, sm);
    if (std::getenv("AR_DEBUG") && k % 60 == 0 && sm.lastResult().ambiguity_fix)
      std::printf("  %zu: %s\n", k, sm.lastResult().ambiguity_fix->text().c_str());
    ++k;
  });
  run.smoothed_error_m.assign(f.epochs.size(), kNaN);
  for (const auto& s : sm.smoothedTrajectory())
    for (std::size_t j = 0; j < f.epochs.size(); ++j)
      if (f.epochs[j].time == s.time)
        run.smoothed_error_m[j] = (s.state.position_ecef_m - f.truth[j].trajectory.position_ecef_m).norm();
  if (keep) *keep = &sm;
  return run;
}

double error3d(const SimulatedFlight& f, const FlightRun& run, std::size_t k) {
  if (k >= run.epochs.size() || !run.epochs[k].position) return kNaN;
  return (*run.epochs[k].position - f.truth[k].trajectory.position_ecef_m).norm();
}

double meanOver(const std::vector<double>& v, std::size_t from, std::size_t to) {
  double s = 0.0;
  int n = 0;
  for (std::size_t k = from; k < to && k < v.size(); ++k)
    if (std::isfinite(v[k])) s += v[k], ++n;
  return n ? s / n : kNaN;
}

/// The true IF bias [m] of an estimator arc in the estimator's convention: the
/// simulated arc's integer part, the satellite's UPD (IF of the phase OSBs) and
/// the wind-up integer at the estimator arc's start (monte_carlo.h).
double trueEstimatorBias_m(const SimulatedFlight& f, const SatelliteId& sat, std::size_t first_epoch) {
  const SignalTruth* s = f.signal(first_epoch, sat);
  if (!s) return kNaN;
  const double f1 = *carrierFrequency_hz(GnssSystem::GPS, '1'), f2 = *carrierFrequency_hz(GnssSystem::GPS, '2');
  const auto k = ionosphereFreeCoefficients(f1, f2);
  const auto u = f.phase_biases.upd(sat);
  const double upd_m = ionosphereFree(u.l1_cycles * kSpeedOfLight_mps / f1, u.l2_cycles * kSpeedOfLight_mps / f2, k);
  return f.arcs[s->arc - 1].bias_if_m + upd_m + std::round(s->windup_cycles) * narrowLaneWavelength_m(f1, f2);
}

}  // namespace

TEST(IntegerAmbiguityFactor, ErrorAndJacobiansOfASingleDifferenceAndACombination) {
  using smoother::Values;
  const smoother::Key b1 = biasKey(*SatelliteId::parse("G05"), 3), b2 = biasKey(*SatelliteId::parse("G12"), 4),
                      b3 = biasKey(*SatelliteId::parse("G20"), 9);
  Values x;
  x.insert(b1, smoother::Vector::Constant(1, 1.234));
  x.insert(b2, smoother::Vector::Constant(1, -0.456));
  x.insert(b3, smoother::Vector::Constant(1, 7.89));
  const double inv_nl = 1.0 / 0.10695;
  const IntegerAmbiguityFactor sd({b1, b2}, {inv_nl, -inv_nl}, 15.0, 1e-3);
  EXPECT_NEAR(sd.unwhitenedError(x, nullptr)(0), (1.234 + 0.456) * inv_nl - 15.0, 1e-12);
  EXPECT_TRUE(smoother::checkJacobians(sd, x, 1e-7).ok);
  const IntegerAmbiguityFactor combo({b1, b2, b3}, {2 * inv_nl, -inv_nl, -inv_nl}, -3.0, 1e-3);
  EXPECT_NEAR(combo.unwhitenedError(x, nullptr)(0), (2 * 1.234 + 0.456 - 7.89) * inv_nl + 3.0, 1e-12);
  const smoother::JacobianCheck c = smoother::checkJacobians(combo, x, 1e-7);
  EXPECT_TRUE(c.ok) << c.report;
  // Whitened: sigma 1e-3 cycle.
  EXPECT_NEAR(combo.error(x), 0.5 * std::pow(combo.unwhitenedError(x, nullptr)(0) / 1e-3, 2), 1e-6);
  EXPECT_THROW(IntegerAmbiguityFactor({b1, b2}, {1.0}, 0.0, 1e-3), std::invalid_argument);
  EXPECT_THROW(IntegerAmbiguityFactor({b1}, {1.0}, 0.0, 0.0), std::invalid_argument);
}


namespace {

struct ArFlight {
  MonteCarloOptions options = arStudy(12.0);
  SimulatedFlight flight;
  PppConfig config, float_config;
  ArFlight() {
    const MonteCarloFlightSetup setup = monteCarloFlightSetup(options, 0);
    flight = simulateFlight(monteCarloSimulationConfig(options, setup), setup.seed);
    config = flightPppConfig(options.ppp, flight);
    float_config = config;
    float_config.ambiguity_resolution.enabled = false;
  }
};

const ArFlight& arFlight() {
  static const ArFlight f;
  return f;
}

std::size_t firstFixed(const FlightRun& run) {
  for (std::size_t k = 0; k < run.epochs.size(); ++k)
    if (run.epochs[k].fixed) return k;
  return run.epochs.size();
}

}  // namespace

// (b) A 12-min loiter with integer ambiguities, satellite UPDs published as OSBs
// and products consistent with them: the smoother fixes from the same resolver
// decision as the EKF, every held fix is the true integer, the smoothed
// trajectory BEFORE the first fix epoch is better than the float smoother's
// (the fix carried backwards), and at the first fix epoch the filtered solution
// is near the EKF's fixed one. Both go through the resolver's validation and
// hold (resolveAndHold), but on different float states (the EKF's filter, the
// smoother's float joint of all data), so their first fixes may differ by epochs.
TEST(SmootherAmbiguity, FixesAreTrueIntegersAndImproveTheSmoothedTrajectoryBeforeTheFix) {
  const ArFlight& a = arFlight();
  const SimulatedFlight& f = a.flight;
  const FlightRun ekf = runEkf(f, a.config);
  PppSmoother* sm = nullptr;
  const FlightRun fix = runSmoother(f, a.config, {}, &sm);
  const std::vector<PppSmoother::HeldFix> held = sm->heldFixes();
  const std::size_t removed = sm->fixesRemoved();
  const FlightRun flo = runSmoother(f, a.float_config);
  const std::size_t first = firstFixed(fix), ekf_first = firstFixed(ekf);
  std::size_t fixed_epochs = 0;
  for (const auto& e : fix.epochs) fixed_epochs += e.fixed ? 1 : 0;
  std::printf("first fix: smoother epoch %zu, EKF %zu; smoother fixed %zu of %zu epochs; held %zu, removed %zu\n",
              first, ekf_first, fixed_epochs, fix.epochs.size(), held.size(), removed);
  ASSERT_LT(first, fix.epochs.size() - 60);
  ASSERT_LT(ekf_first, fix.epochs.size() - 60);
  EXPECT_GT(fixed_epochs, fix.epochs.size() / 3);
  EXPECT_EQ(removed, 0u);
  ASSERT_FALSE(held.empty());
  for (const auto& h : held) {
    const auto* fa = dynamic_cast<const IntegerAmbiguityFactor*>(h.factor.get());
    ASSERT_NE(fa, nullptr);
    double truth_cycles = 0.0;
    for (std::size_t j = 0; j < h.arcs.size(); ++j) {
      const auto& st = fix.arc_start.at(h.arcs[j]);
      truth_cycles += fa->coefficients_per_m()[j] * trueEstimatorBias_m(f, st.first, st.second);
    }
    EXPECT_NEAR(truth_cycles, fa->value_cycles(), 1e-3) << "fix on " << h.arcs.size() << " arcs";
  }
  const double before_fix = meanOver(fix.smoothed_error_m, 0, first);
  const double before_float = meanOver(flo.smoothed_error_m, 0, first);
  const double after_fix = meanOver(fix.smoothed_error_m, first, f.epochs.size());
  const double after_float = meanOver(flo.smoothed_error_m, first, f.epochs.size());
  std::printf("smoothed mean 3D before the first fix: fixed %.4f m, float %.4f m; after: %.4f / %.4f m\n",
              before_fix, before_float, after_fix, after_float);
  EXPECT_LT(before_fix, 0.7 * before_float);
  EXPECT_LT(after_fix, 0.7 * after_float);
  const double filtered_vs_ekf = (*fix.epochs[first].position - *ekf.epochs[first].position).norm();
  std::printf("first fix epoch: |smoother filtered - EKF fixed| %.4f m\n", filtered_vs_ekf);
  ASSERT_TRUE(ekf.epochs[first].fixed);
  EXPECT_LT(filtered_vs_ekf, 0.03);
}

// (a) The held fixes are ordinary factors of the graph: the batch solve of every
// recorded factor (fixed-ambiguity factors included) equals the incremental
// smoothed trajectory.
TEST(SmootherAmbiguity, IncrementalWithFixesEqualsTheBatchSolveOfTheSameGraph) {
  const ArFlight& a = arFlight();
  PppSmoother* sm = nullptr;
  runSmoother(a.flight, a.config, {}, &sm, true);
  ASSERT_FALSE(sm->heldFixes().empty());
  const std::vector<SmoothedEpoch> incremental = sm->smoothedTrajectory();
  const std::vector<SmoothedEpoch> batch = sm->trajectoryFrom(sm->batchSmoothedValues());
  ASSERT_EQ(incremental.size(), batch.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < batch.size(); ++k)
    worst = std::max(worst, (incremental[k].state.position_ecef_m - batch[k].state.position_ecef_m).norm());
  std::printf("largest |incremental - batch| position with %zu held fixes: %.3g m\n",
              sm->heldFixes().size(), worst);
  EXPECT_LT(worst, 1e-3);
}

// (c) A wrong integer (the best-determined single difference's integer plus one
// narrow-lane cycle; held pairs have their right factor taken out first)
// injected as a hold into the resolver and as a factor into the graph, as the
// estimator holds a validated fix: the
// resolver's release check (float departed, on the smoother's float joint)
// releases it, its factor is removed from the graph (remove_factor_indices), and
// the estimate returns to that of the same run without the injection.
TEST(SmootherAmbiguity, AWrongFixIsDetectedAndRemovedAndTheEstimateReturns) {
  const ArFlight& a = arFlight();
  const SimulatedFlight& f = a.flight;
  const FlightRun clean = runSmoother(f, a.config);
  const std::size_t inject = 420;
  std::optional<std::size_t> removed_at;
  std::size_t removed_before = 0;
  double disturbed_m = 0.0;  // the wrong fix's pull on the filtered position
  double held_at_m = 1.0;    // the wrong factor's residual [cycles] right after the injection
  std::optional<AmbiguityReleaseReason> reason;
  const FlightRun wrong = runSmoother(f, a.config, [&](std::size_t k, PppSmoother& sm) {
    PppSmoother& s = sm;
    const auto& fix = sm.lastResult().ambiguity_fix;
    if (k == inject) {
      ASSERT_TRUE(fix.has_value());
      const NarrowLaneFloat* best = nullptr;
      for (const auto& nl : fix->narrow_lanes)
        if (!best || nl.sigma_cycles < best->sigma_cycles) best = &nl;
      ASSERT_NE(best, nullptr) << "no single difference at the injection epoch";
      const long right = best->held_cycles ? *best->held_cycles : std::lround(best->float_cycles);
      const long wrong_integer = right + 1;
      std::printf("injecting %s-%s: float %.3f sigma %.3f cycle, %s %ld, injected %ld\n",
                  best->satellite.toString().c_str(), best->reference_satellite.toString().c_str(),
                  best->float_cycles, best->sigma_cycles, best->held_cycles ? "held" : "unheld", right, wrong_integer);
      // A held pair's right factor leaves the graph first (the wrong one replaces it).
      if (best->held_cycles) ASSERT_EQ(s.releaseFixes({{best->arc, best->reference_arc}}), 1);
      sm.resolver().holdInteger(best->arc, best->reference_arc, best->wide_lane_cycles, wrong_integer);
      const auto flt = s.floatJoint();
      ASSERT_TRUE(flt.has_value());
      const int rx = static_cast<int>(flt->x.size() - flt->arcs.size());
      const double inv_nl = 1.0 / narrowLaneWavelength_m(*carrierFrequency_hz(GnssSystem::GPS, '1'),
                                                         *carrierFrequency_hz(GnssSystem::GPS, '2'));
      Eigen::MatrixXd A = Eigen::MatrixXd::Zero(1, flt->x.size());
      for (std::size_t j = 0; j < flt->arcs.size(); ++j) {
        if (flt->arcs[j] == best->arc) A(0, rx + static_cast<int>(j)) = inv_nl;
        if (flt->arcs[j] == best->reference_arc) A(0, rx + static_cast<int>(j)) = -inv_nl;
      }
      // dN1 = A x - offset and float_cycles = A x_float - offset: the wrong integer's value.
      const Eigen::VectorXd y =
          Eigen::VectorXd::Constant(1, (A * flt->x)(0) + static_cast<double>(wrong_integer) - best->float_cycles);
      ASSERT_EQ(s.holdIntegerConstraints(A, y), 1);
      // The graph now holds the wrong integer: the factor's residual at the filtered estimate.
      held_at_m = (A * s.filteredJoint().x)(0) - y(0);
      removed_before = s.fixesRemoved();
      disturbed_m = (s.filteredSolution().state.position_ecef_m - *clean.epochs[k].position).norm();
    } else if (k > inject && !removed_at && s.fixesRemoved() > removed_before) {
      removed_at = k;
      if (fix)
        for (const auto& rel : fix->released) reason = rel.reason;
    }
  });
  const double held_error = error3d(f, wrong, inject);
  std::printf("wrong fix at epoch %zu: filtered 3D error %.3f m (clean %.3f m); removed at epoch %s (%s)\n", inject,
              held_error, error3d(f, clean, inject), removed_at ? std::to_string(*removed_at).c_str() : "never",
              reason ? toString(*reason).c_str() : "-");
  std::printf("the wrong fix moved the filtered position by %.4f m; residual of the wrong "
              "factor %.4f cycle\n", disturbed_m, held_at_m);
  EXPECT_GT(disturbed_m, 0.005);
  // The graph pulls the single difference from its float (about 1 cycle away) to
  // the wrong integer; one iSAM2 step at a decimetre move of the position
  // (range factors re-evaluated, relinearization thresholds) leaves 0.23 cycle.
  EXPECT_LT(std::abs(held_at_m), 0.3);
  ASSERT_TRUE(removed_at.has_value());
  EXPECT_LE(*removed_at, inject + 10);
  ASSERT_TRUE(reason.has_value());
  EXPECT_EQ(*reason, AmbiguityReleaseReason::FloatDeparted);
  // The wrong factor is gone exactly; the resolver's validation of that pair
  // restarted, so the runs may differ by when it is held again: compare 60 s on.
  double worst_after = 0.0;
  for (std::size_t k = *removed_at + 60; k < f.epochs.size(); ++k)
    worst_after = std::max(worst_after, (*wrong.epochs[k].position - *clean.epochs[k].position).norm());
  const double mean_wrong = meanOver(wrong.smoothed_error_m, 0, f.epochs.size()),
               mean_clean = meanOver(clean.smoothed_error_m, 0, f.epochs.size());
  std::printf("60 s after removal: largest |filtered - clean run| %.3g m; smoothed mean 3D %.4f m (clean %.4f m)\n",
              worst_after, mean_wrong, mean_clean);
  EXPECT_LT(worst_after, 1e-3);
  EXPECT_LT(mean_wrong, mean_clean + 2e-3);
}

// Fixed lag (60 s): the fixes are held while their biases are in the window;
// once a bias is marginalized its fix lives on in the marginal prior (no longer
// removable) and leaves the held set. The filtered solution keeps the fix.
TEST(SmootherAmbiguity, FixedLagKeepsTheFixThroughMarginalization) {
  const ArFlight& a = arFlight();
  const SimulatedFlight& f = a.flight;
  PppConfig lag = a.config, lag_float = a.float_config;
  lag.smoother.fixed_lag_s = 60.0;
  lag_float.smoother.fixed_lag_s = 60.0;
  PppSmoother* sm = nullptr;
  const FlightRun fix = runSmoother(f, lag, {}, &sm);
  const std::size_t removed = sm->fixesRemoved();
  const FlightRun flo = runSmoother(f, lag_float);
  const std::size_t first = firstFixed(fix);
  std::size_t fixed_epochs = 0;
  for (const auto& e : fix.epochs) fixed_epochs += e.fixed ? 1 : 0;
  std::vector<double> e_fix, e_flo;
  for (std::size_t k = 0; k < f.epochs.size(); ++k) e_fix.push_back(error3d(f, fix, k)), e_flo.push_back(error3d(f, flo, k));
  const double after_fix = meanOver(e_fix, first, f.epochs.size()), after_float = meanOver(e_flo, first, f.epochs.size());
  std::printf("fixed lag 60 s: first fix %zu, fixed %zu of %zu, removed %zu; filtered mean 3D after the first fix "
              "%.4f m (float %.4f m)\n", first, fixed_epochs, fix.epochs.size(), removed, after_fix, after_float);
  ASSERT_LT(first, fix.epochs.size() - 60);
  EXPECT_GT(fixed_epochs, fix.epochs.size() / 3);
  EXPECT_EQ(removed, 0u);
  EXPECT_LT(after_fix, 0.7 * after_float);
}
