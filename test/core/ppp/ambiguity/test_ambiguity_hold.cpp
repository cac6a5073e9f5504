// Validation across epochs and hold of the PPP-AR resolver
// (AmbiguityResolver::resolveAndHold, ppp/ambiguity/ambiguity_resolution.h):
//  - a deliberately wrong integer (a float biased by one narrow-lane cycle that
//    the validation accepts) is held, detected once the float moves away from
//    it, released and counted, and the fixed estimate returns to the truth
//    within its bounds; the right integer is then validated and held again;
//  - on CCJ2 (WUM clocks and phase OSBs), the narrow-lane integers held by the
//    EKF in a static run are checked against their float values across arcs
//    (integer residuals near 0, histogram printed).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <sstream>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/evaluation/rtklib_pos.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/types/constants.h"
#include "esbc_stream_fixture.h"
#include "ppp_dataset.h"
#include "table_biases.h"
#include "test_support.h"

namespace ppp {
namespace {

constexpr double kF1 = 1575.42e6, kF2 = 1227.60e6;  // GPS L1/L2 (IS-GPS-200)

struct SyntheticArc {
  ArcId arc;
  int prn;
  int n1, nwl;
  double osb_l1_m, osb_l2_m;
};

/// Six arcs with integer ambiguities, satellite OSBs, a receiver phase bias and
/// a filter covariance in which the biases are correlated with the receiver
/// states (a wrong integer pulls the position).
struct SyntheticProblem {
  std::vector<SyntheticArc> arcs = {{1, 3, 12, 5, 0.031, -0.044}, {2, 7, -40, 17, -0.12, 0.07},
                                    {3, 11, 7, -3, 0.2, 0.15},     {4, 19, 101, 44, -0.05, -0.2},
                                    {5, 22, -9, 0, 0.0, 0.09},     {6, 30, 55, -21, 0.11, 0.013}};
  static constexpr int receiver_dim = 5;
  TableBiases osb;
  Eigen::VectorXd truth;
  Eigen::MatrixXd P;
  std::vector<ArcId> bias_arcs;

  SyntheticProblem() {
    const int n = static_cast<int>(arcs.size());
    const auto k_if = ionosphereFreeCoefficients(kF1, kF2);
    truth.resize(receiver_dim + n);
    truth.head(receiver_dim) << 1.0, 2.0, 3.0, 0.1, 5.0;
    for (int i = 0; i < n; ++i) {
      const auto& a = arcs[static_cast<std::size_t>(i)];
      const SatelliteId sat{GnssSystem::GPS, a.prn};
      osb.table[{sat, "L1C"}] = a.osb_l1_m;
      osb.table[{sat, "L2W"}] = a.osb_l2_m;
      truth(receiver_dim + i) = ionosphereFreeAmbiguity_m(kF1, kF2, a.n1, a.nwl) +
                                ionosphereFree(a.osb_l1_m, a.osb_l2_m, k_if) + 0.4321;
      bias_arcs.push_back(a.arc);
    }
    // x = J z with independent z: receiver states (sigma 5 cm), per-arc biases
    // (NL sigma ~0.05 cycle) and a common receiver phase bias (10 cm).
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> g(-1.0, 1.0);
    const int dim = receiver_dim + n;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(dim, receiver_dim + n + 1);
    J.topLeftCorner(receiver_dim, receiver_dim) = 0.05 * Eigen::MatrixXd::Identity(receiver_dim, receiver_dim);
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) J(receiver_dim + i, k) = 0.05 * g(rng);  // geometry
      J(receiver_dim + i, receiver_dim + i) = 0.005;
      J(receiver_dim + i, receiver_dim + n) = 0.1;
    }
    P = J * J.transpose();
  }

  /// MW samples of every arc for `epochs` epochs (wide lanes clearly integer).
  void feedWideLanes(AmbiguityResolver& resolver, int epochs) const {
    std::mt19937 rng(9);
    std::normal_distribution<double> noise(0.0, 0.2);
    for (int k = 0; k < epochs; ++k) {
      std::vector<DualFrequencyObservation> obs;
      std::vector<ArcId> ids;
      for (const auto& a : arcs) {
        DualFrequencyObservation o;
        o.satellite = SatelliteId{GnssSystem::GPS, a.prn};
        o.code1 = *ObservationCode::parse("C1W");
        o.code2 = *ObservationCode::parse("C2W");
        o.phase1 = *ObservationCode::parse("L1C");
        o.phase2 = *ObservationCode::parse("L2W");
        o.frequency1_hz = kF1;
        o.frequency2_hz = kF2;
        const double range_m = 2.2e7 + 1000.0 * k;
        o.code1_m = o.code2_m = range_m;
        o.phase1_cycles = range_m * kF1 / kSpeedOfLight_mps + a.n1 + a.osb_l1_m * kF1 / kSpeedOfLight_mps + 0.29 +
                          noise(rng);
        o.phase2_cycles = range_m * kF2 / kSpeedOfLight_mps + (a.n1 - a.nwl) + a.osb_l2_m * kF2 / kSpeedOfLight_mps;
        o.code1_osb_m = 0.0;
        o.code2_osb_m = 0.0;
        obs.push_back(o);
        ids.push_back(a.arc);
      }
      resolver.addEpoch(obs, ids, &osb);
    }
  }
};

/// The options for the synthetic problem's hold mechanics: its subsets' success
/// rate is 0.68 (the geometry and the common receiver phase bias of its
/// covariance), so they are accepted on the ratio test alone here; the default
/// acceptance is tested in SubsetWithAHighRatioButALowSuccessRateIsNotFixed.
/// Its covariance is the floats' true one: variance factor 1.
AmbiguityResolutionOptions ratioTestOptions() {
  AmbiguityResolutionOptions opt;
  opt.enabled = true;
  opt.hold.require_subset_success_rate = false;
  opt.narrow_lane.success_rate_variance_factor = 1.0;
  return opt;
}

TEST(AmbiguityHold, SubsetWithAHighRatioButALowSuccessRateIsNotFixed) {
  // The floats sit on their integers (ratio ~1e25), but the covariance says the
  // integers are not determined (bootstrapped success rate 0.68 < 0.999): by
  // default nothing is held, whatever the ratio; on the ratio test alone all five
  // single differences are.
  SyntheticProblem s;
  const int rd = SyntheticProblem::receiver_dim;
  const auto held = [&](const AmbiguityResolutionOptions& opt, AmbiguityFixSummary& summary) {
    AmbiguityResolver resolver(opt);
    s.feedWideLanes(resolver, 60);
    for (int k = 0; k < 30; ++k) resolver.resolveAndHold(s.truth, s.P, rd, s.bias_arcs, &s.osb, summary);
    return resolver.heldCount();
  };
  AmbiguityResolutionOptions defaults;
  defaults.enabled = true;
  AmbiguityFixSummary summary;
  EXPECT_EQ(held(defaults, summary), 0) << summary.text();
  EXPECT_EQ(summary.ils_reason, IlsFloatReason::LowSuccessRate) << summary.text();
  EXPECT_GT(summary.ratio, 1e6);
  EXPECT_LT(summary.bootstrap_success_rate, defaults.narrow_lane.min_success_rate);
  EXPECT_EQ(held(ratioTestOptions(), summary), 5) << summary.text();
  // The variance factor only lowers the success rate: the same floats with a
  // covariance 100 times smaller pass with factor 1 and 2, not with 100.
  const auto heldScaled = [&](double factor) {
    AmbiguityResolutionOptions opt = defaults;
    opt.narrow_lane.success_rate_variance_factor = factor;
    AmbiguityResolver resolver(opt);
    s.feedWideLanes(resolver, 60);
    AmbiguityFixSummary sm;
    for (int k = 0; k < 30; ++k) resolver.resolveAndHold(s.truth, 0.01 * s.P, rd, s.bias_arcs, &s.osb, sm);
    return resolver.heldCount();
  };
  EXPECT_EQ(heldScaled(1.0), 5);
  EXPECT_EQ(heldScaled(2.0), 5);
  EXPECT_EQ(heldScaled(100.0), 0);
}

TEST(AmbiguityHold, WrongIntegerIsHeldThenDetectedReleasedAndTheEstimateReturns) {
  SyntheticProblem s;
  const int rd = SyntheticProblem::receiver_dim;
  const AmbiguityResolutionOptions opt = ratioTestOptions();
  AmbiguityResolver resolver(opt);
  s.feedWideLanes(resolver, 60);
  const double lambda_nl = narrowLaneWavelength_m(kF1, kF2);

  // 1. A float biased by one NL cycle on arc 4 (e.g. an unmodelled
  //    error during convergence): consistent over the window, so validated and
  //    held with the wrong integer.
  Eigen::VectorXd x_bad = s.truth;
  x_bad(rd + 3) += lambda_nl;
  AmbiguityFixSummary summary;
  std::optional<AmbiguityFixedState> fixed;
  int epoch_held = -1;
  for (int k = 0; k < 20 && epoch_held < 0; ++k) {
    fixed = resolver.resolveAndHold(x_bad, s.P, rd, s.bias_arcs, &s.osb, summary);
    if (fixed) epoch_held = k;
  }
  ASSERT_TRUE(fixed.has_value()) << summary.text();
  // Not before the float history and the repeated searches allow it.
  EXPECT_GE(epoch_held, opt.hold.consistency_epochs - 1 + opt.hold.validation_epochs - 1);
  EXPECT_EQ(resolver.heldCount(), 5);
  const double wrong_sd = (fixed->x(rd + 3) - fixed->x(rd)) - (s.truth(rd + 3) - s.truth(rd));
  EXPECT_NEAR(std::abs(wrong_sd), lambda_nl, 1e-6);  // the wrong integer is in use
  {
    // Kept against the converged float (below), it would pull the position far
    // outside its bounds: the same five constraints applied to the truth.
    Eigen::MatrixXd A(5, s.truth.size());
    Eigen::VectorXd y(5);
    A.setZero();
    for (int i = 1; i < 6; ++i) {
      A(i - 1, rd + i) = 1.0;
      A(i - 1, rd) = -1.0;
      y(i - 1) = fixed->x(rd + i) - fixed->x(rd);
    }
    const auto kept = applyIntegerConstraints(s.truth, s.P, A, y);
    ASSERT_TRUE(kept.has_value());
    double worst = 0.0;
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(kept->x(k) - s.truth(k)) / std::sqrt(kept->P(k, k)));
    EXPECT_GT(worst, 3.0);
  }

  // 2. The float converges to the truth: the held wrong integer departs from it
  //    by one cycle and is released (counted, with the reason); the others stay.
  fixed = resolver.resolveAndHold(s.truth, s.P, rd, s.bias_arcs, &s.osb, summary);
  ASSERT_EQ(summary.released.size(), 1u);
  EXPECT_EQ(summary.released[0].reason, AmbiguityReleaseReason::FloatDeparted);
  EXPECT_EQ(summary.released[0].satellite.prn, 19);
  EXPECT_GT(std::abs(summary.released[0].departure_cycles), 0.5);
  EXPECT_EQ(resolver.releasesTotal(), 1);
  ASSERT_TRUE(fixed.has_value()) << summary.text();  // 4 right ones still held (min_fixed 4)
  for (int k = 0; k < 3; ++k) {
    const double sigma = std::sqrt(fixed->P(k, k));
    EXPECT_LE(std::abs(fixed->x(k) - s.truth(k)), 3.0 * sigma + 1e-9) << "receiver state " << k;
  }

  // 3. After the float history and the validation, the right integer is held.
  for (int k = 0; k < 20; ++k) fixed = resolver.resolveAndHold(s.truth, s.P, rd, s.bias_arcs, &s.osb, summary);
  ASSERT_TRUE(fixed.has_value());
  EXPECT_EQ(resolver.heldCount(), 5);
  EXPECT_EQ(resolver.releasesTotal(), 1);
  for (int i = 1; i < 6; ++i)
    EXPECT_NEAR(fixed->x(rd + i) - fixed->x(rd), s.truth(rd + i) - s.truth(rd), 1e-6) << "arc " << i + 1;
  EXPECT_LT((fixed->x.head(3) - s.truth.head(3)).norm(), 1e-6);
}

// Fewer validation epochs for a subset whose bootstrapped success rate reaches
// fast_validation_success_rate (here the floats sit on their integers, but the
// subset's success rate is 0.68: the geometry part of the covariance); below
// it, and with 1 (the default), validation_epochs.
TEST(AmbiguityHold, HighSuccessRateSubsetIsHeldAfterFewerValidationEpochs) {
  SyntheticProblem s;
  const int rd = SyntheticProblem::receiver_dim;
  const auto firstHeld = [&](double fast_success_rate) {
    AmbiguityResolutionOptions opt = ratioTestOptions();
    opt.hold.fast_validation_success_rate = fast_success_rate;
    opt.hold.fast_validation_epochs = 2;
    AmbiguityResolver resolver(opt);
    s.feedWideLanes(resolver, 60);
    AmbiguityFixSummary summary;
    for (int k = 0; k < 30; ++k) {
      if (resolver.resolveAndHold(s.truth, s.P, rd, s.bias_arcs, &s.osb, summary)) {
        return k;
      }
    }
    return -1;
  };
  const AmbiguityHoldOptions defaults;
  EXPECT_EQ(firstHeld(1.0), defaults.consistency_epochs - 1 + defaults.validation_epochs - 1);
  EXPECT_EQ(firstHeld(0.9), defaults.consistency_epochs - 1 + defaults.validation_epochs - 1);
  EXPECT_EQ(firstHeld(0.5), defaults.consistency_epochs - 1 + 2 - 1);
}

TEST(AmbiguityHold, HeldIntegersSurviveTheEndOfTheirReferenceArc) {
  // Five integers held against one reference arc; the reference arc ends. With
  // hold.rereference_on_arc_end the held set is re-expressed between the other
  // arcs (N(a - e) - N(b - e) = N(a - b)) and the next epoch is fixed at once
  // with the true differences; without it nothing is held and the integers are
  // searched and validated again.
  SyntheticProblem s;
  const int rd = SyntheticProblem::receiver_dim;
  for (const bool rereference : {true, false}) {
    AmbiguityResolutionOptions opt = ratioTestOptions();
    opt.hold.rereference_on_arc_end = rereference;
    AmbiguityResolver resolver(opt);
    s.feedWideLanes(resolver, 60);
    AmbiguityFixSummary summary;
    std::optional<AmbiguityFixedState> fixed;
    for (int k = 0; k < 20 && resolver.heldCount() < 5; ++k)
      fixed = resolver.resolveAndHold(s.truth, s.P, rd, s.bias_arcs, &s.osb, summary);
    ASSERT_EQ(resolver.heldCount(), 5) << summary.text();
    ASSERT_TRUE(summary.reference_satellite.has_value());
    // The reference arc ends: it leaves the state.
    int gone = -1;
    for (int i = 0; i < static_cast<int>(s.arcs.size()); ++i)
      if (s.arcs[static_cast<std::size_t>(i)].prn == summary.reference_satellite->prn) gone = i;
    ASSERT_GE(gone, 0);
    EndedArc ended;
    ended.satellite = *summary.reference_satellite;
    ended.arc = s.arcs[static_cast<std::size_t>(gone)].arc;
    resolver.arcsEnded({ended});
    EXPECT_EQ(resolver.heldCount(), rereference ? 4 : 0);
    std::vector<int> keep;
    for (int i = 0; i < static_cast<int>(s.truth.size()); ++i)
      if (i != rd + gone) keep.push_back(i);
    const int n = static_cast<int>(keep.size());
    Eigen::VectorXd x(n);
    Eigen::MatrixXd P(n, n);
    for (int i = 0; i < n; ++i) {
      x(i) = s.truth(keep[static_cast<std::size_t>(i)]);
      for (int j = 0; j < n; ++j) P(i, j) = s.P(keep[static_cast<std::size_t>(i)], keep[static_cast<std::size_t>(j)]);
    }
    std::vector<ArcId> arcs = s.bias_arcs;
    arcs.erase(arcs.begin() + gone);
    fixed = resolver.resolveAndHold(x, P, rd, arcs, &s.osb, summary);
    if (!rereference) {
      EXPECT_FALSE(fixed.has_value()) << summary.text();
      continue;
    }
    ASSERT_TRUE(fixed.has_value()) << summary.text();
    EXPECT_EQ(summary.held, 4);
    EXPECT_TRUE(summary.released.empty());
    for (int i = rd + 1; i < n; ++i) EXPECT_NEAR(fixed->x(i) - fixed->x(rd), x(i) - x(rd), 1e-6) << "state " << i;
  }
}

TEST(AmbiguityHold, DriftingFloatIsNotSearchedAndAChangedIntegerIsNotHeld) {
  SyntheticProblem s;
  const int rd = SyntheticProblem::receiver_dim;
  const AmbiguityResolutionOptions opt = ratioTestOptions();
  AmbiguityResolver resolver(opt);
  s.feedWideLanes(resolver, 60);
  const double lambda_nl = narrowLaneWavelength_m(kF1, kF2);
  AmbiguityFixSummary summary;
  // Arc i's float drifts by 0.05 i NL cycles per epoch (every single
  // difference spreads by at least 0.45 cycle over the 10-epoch window):
  // nothing may be searched, nothing held.
  for (int k = 0; k < 40; ++k) {
    Eigen::VectorXd x = s.truth;
    for (int i = 0; i < 6; ++i) x(rd + i) += 0.05 * i * lambda_nl * k;
    EXPECT_FALSE(resolver.resolveAndHold(x, s.P, rd, s.bias_arcs, &s.osb, summary).has_value());
  }
  EXPECT_EQ(resolver.heldCount(), 0);
  EXPECT_EQ(summary.narrow_lane_candidates, 0);
  EXPECT_EQ(summary.float_reason, AmbiguityFloatReason::FloatsDrifting) << summary.text();
  EXPECT_FALSE(summary.narrow_lanes.empty());  // the floats are reported
}

// A converging float: the covariance shrinks like 1 / (1 + 0.3 k) (a filter
// accumulating independent epochs; the synthetic covariance / 4, single-
// difference sigmas 0.2-0.4 cycle at k = 0) while the floats close in on their
// integers, every other arc from 0.2 NL cycle off (0.4 in the single
// differences) to 0 at k = 9: within 3 sigmas of the change the covariance
// explains, sqrt(sigma_0^2 - sigma_k^2). Over the first 10-epoch window they
// spread by 0.4 cycle, more than max_float_spread_cycles 0.2: the raw spread
// keeps them out until the moving epochs leave the window (searched from
// k = 14, held at 18), the drift relative to the covariance
// (max_float_drift_sigmas 3) offers them as soon as the window is full
// (searched from k = 9, held at 9 + validation_epochs - 1 = 13). Both hold the
// true integers. A float that moves while its covariance stays is not steady
// either way (DriftingFloatIsNotSearchedAndAChangedIntegerIsNotHeld).
TEST(AmbiguityHold, ConvergingFloatIsSearchedWhenItsDriftIsWhatItsCovarianceExplains) {
  SyntheticProblem s;
  const int rd = SyntheticProblem::receiver_dim;
  const double lambda_nl = narrowLaneWavelength_m(kF1, kF2);
  struct FirstHold {
    int epoch = -1;
    std::vector<NarrowLaneFloat> held;
  };
  const auto firstHeld = [&](double drift_sigmas) {
    AmbiguityResolutionOptions opt = ratioTestOptions();
    opt.hold.max_float_drift_sigmas = drift_sigmas;
    AmbiguityResolver resolver(opt);
    s.feedWideLanes(resolver, 60);
    AmbiguityFixSummary summary;
    for (int k = 0; k < 80; ++k) {
      const double f = 1.0 / (1.0 + 0.3 * k);
      Eigen::VectorXd x = s.truth;
      for (int i = 0; i < 6; ++i) x(rd + i) += (i % 2 ? 0.2 : -0.2) * lambda_nl * std::max(0.0, 1.0 - k / 9.0);
      if (resolver.resolveAndHold(x, 0.25 * f * s.P, rd, s.bias_arcs, &s.osb, summary))
        return FirstHold{k, summary.narrow_lanes};
    }
    return FirstHold{};
  };
  const FirstHold spread_only = firstHeld(0.0), with_drift = firstHeld(3.0);
  std::printf("[ figures  ] first held: epoch %d with the drift test, %d with the spread alone\n", with_drift.epoch,
              spread_only.epoch);
  const int window = AmbiguityHoldOptions{}.consistency_epochs, validation = AmbiguityHoldOptions{}.validation_epochs;
  ASSERT_GE(with_drift.epoch, 0);
  ASSERT_GE(spread_only.epoch, 0);
  EXPECT_EQ(with_drift.epoch, window - 1 + validation - 1);  // searched from the first full window
  EXPECT_GE(spread_only.epoch, with_drift.epoch + 4);        // the raw spread waits for the float to settle
  for (const FirstHold* h : {&spread_only, &with_drift})
    for (const NarrowLaneFloat& f : h->held) {
      if (!f.held_cycles) continue;
      const auto& a = s.arcs[static_cast<std::size_t>(f.arc - 1)];
      const auto& r = s.arcs[static_cast<std::size_t>(f.reference_arc - 1)];
      EXPECT_EQ(*f.held_cycles, a.n1 - r.n1) << f.satellite.toString() << "-" << f.reference_satellite.toString();
    }
}

TEST(AmbiguityHold, FloatFarFromItsIntegerIsGatedAndTheOthersAreHeld) {
  // Arc 4's float sits 0.3 NL cycle off its integer, steadily, at a precision
  // (the synthetic covariance / 100: single-difference sigmas 0.005-0.05
  // cycle) that makes 0.3 cycle an error the covariance does not hold (ESBC:
  // floats 0.2-0.4 cycle off at sigma 0.02). The candidate gate (Ge et al.
  // 2008: beyond max_fraction_cycles 0.25 and 3 sigma) keeps it float, and the other single differences are held with
  // their true integers. Without the gate (0.5 cycle) the off float stays in
  // every subset the partial fixing tries (it is not the worst-determined),
  // the ratio test fails and nothing is held.
  const double offset_cycles = 0.3;
  SyntheticProblem s;
  const int rd = SyntheticProblem::receiver_dim;
  const double lambda_nl = narrowLaneWavelength_m(kF1, kF2);
  Eigen::VectorXd x = s.truth;
  x(rd + 3) += offset_cycles * lambda_nl;
  const Eigen::MatrixXd P = 0.01 * s.P;
  struct Outcome {
    int held = 0;
    bool arc4_held = false;
    std::optional<AmbiguityFixedState> fixed;
    AmbiguityFixSummary summary;
  };
  auto run = [&](double max_fraction_cycles) {
    AmbiguityResolutionOptions opt;
    opt.enabled = true;
    opt.hold.max_fraction_cycles = max_fraction_cycles;
    AmbiguityResolver resolver(opt);
    s.feedWideLanes(resolver, 60);
    Outcome o;
    for (int k = 0; k < 30; ++k) o.fixed = resolver.resolveAndHold(x, P, rd, s.bias_arcs, &s.osb, o.summary);
    o.held = resolver.heldCount();
    for (const auto& n : o.summary.narrow_lanes)
      if (n.held_cycles && (n.arc == 4 || n.reference_arc == 4)) o.arc4_held = true;
    return o;
  };
  const Outcome gated = run(0.25);
  EXPECT_FALSE(gated.arc4_held) << gated.summary.text();
  EXPECT_GE(gated.held, AmbiguityResolutionOptions{}.narrow_lane.min_fixed) << gated.summary.text();
  ASSERT_TRUE(gated.fixed.has_value()) << gated.summary.text();
  for (const auto& n : gated.summary.narrow_lanes)  // held integers are the true ones
    if (n.held_cycles) EXPECT_NEAR(n.float_cycles, static_cast<double>(*n.held_cycles), 1e-6) << n.satellite.toString();
  const Outcome ungated = run(0.5);
  EXPECT_LT(ungated.held, gated.held) << ungated.summary.text();
  EXPECT_EQ(ungated.summary.ils_reason, IlsFloatReason::RatioTestFailed) << ungated.summary.text();
}

/// CCJ2's files (WUM products and phase OSBs, the dataset's ANTEX).
PppInputFiles ccj2InputFiles() {
  const test::PppDataset d = test::ccj2Dataset();
  return test::inputFiles(d);
}

/// A wrong integer injected at one epoch into an estimator's resolver: the held
/// Galileo narrow lane with the smallest sigma gets its integer + 1. Fed after
/// each epoch the estimator processed (the pipeline's callback).
class Injection {
 public:
  Injection(PppEstimator& estimator, int inject_at) : estimator_(estimator), inject_at_(inject_at) {}
  void epoch(const PppEpochRecord& rec) {
    if (rec.refused) return;  // the estimator did not see it
    const EstimatorEpochResult& r = estimator_.lastResult();
    if (r.ambiguity_fix && injected && !released_at)
      for (const auto& rel : r.ambiguity_fix->released)
        if (rel.arc == injected->arc && rel.reference_arc == injected->reference_arc) {
          released_at = epoch_;
          release = rel;
        }
    if (epoch_ == inject_at_ && r.ambiguity_fix) {
      const NarrowLaneFloat* best = nullptr;
      for (const auto& nl : r.ambiguity_fix->narrow_lanes)
        if (nl.held_cycles && nl.satellite.system == GnssSystem::Galileo && (!best || nl.sigma_cycles < best->sigma_cycles))
          best = &nl;
      if (best) {
        injected = *best;
        estimator_.resolver().holdInteger(best->arc, best->reference_arc, best->wide_lane_cycles,
                                          *best->held_cycles + 1);
      }
    }
    ++epoch_;
  }
  std::optional<NarrowLaneFloat> injected;
  std::optional<int> released_at;
  std::optional<AmbiguityRelease> release;

 private:
  PppEstimator& estimator_;
  int inject_at_ = -1;
  int epoch_ = 0;
};

struct InjectionOutcome {
  std::vector<std::pair<std::optional<Eigen::Vector3d>, bool>> clean, wrong;  // filtered position, fixed
  std::optional<NarrowLaneFloat> injected;
  std::optional<int> released_at;
  std::optional<AmbiguityRelease> release;
};

/// The clean run and the run with the injection of the same inputs, on the
/// registered estimator `name`.
InjectionOutcome runInjection(const std::string& name, const PppInputFiles& files, const PppConfig& config,
                              int inject_at) {
  const auto run = [&](Injection* injection, PppEstimator& estimator) {
    PppPipeline pipeline(files, config);
    std::vector<std::pair<std::optional<Eigen::Vector3d>, bool>> out;
    pipeline.run(estimator, [&](const PppEpochRecord& r) {
      if (injection) injection->epoch(r);
      out.emplace_back(r.solution.position_ecef_m, r.solution.status == SolutionStatus::PppFixed);
    });
    return out;
  };
  const std::unique_ptr<PppEstimator> clean = makeEstimator(name, config);
  const std::unique_ptr<PppEstimator> wrong = makeEstimator(name, config);
  Injection injection(*wrong, inject_at);
  InjectionOutcome o;
  o.clean = run(nullptr, *clean);
  o.wrong = run(&injection, *wrong);
  o.injected = injection.injected;
  o.released_at = injection.released_at;
  o.release = injection.release;
  if (o.injected)
    std::cout << "injected " << o.injected->satellite.toString() << "-" << o.injected->reference_satellite.toString()
              << " float " << o.injected->float_cycles << " sigma " << o.injected->sigma_cycles << " held "
              << *o.injected->held_cycles << " -> " << *o.injected->held_cycles + 1 << "; released at epoch "
              << (o.released_at ? std::to_string(*o.released_at) : std::string("never")) << "\n";
  return o;
}

/// The injection released at the next epoch as departed by about a cycle, and
/// the filtered solution within 1 cm of the clean run's from then on.
void expectInjectionReleased(const InjectionOutcome& o, int inject_at, int min_fixed_after) {
  ASSERT_EQ(o.clean.size(), o.wrong.size());
  ASSERT_TRUE(o.injected.has_value()) << "no held Galileo integer at the injection epoch";
  EXPECT_EQ(o.injected->reference_satellite.system, GnssSystem::Galileo);
  ASSERT_TRUE(o.released_at.has_value());
  EXPECT_EQ(*o.released_at, inject_at + 1);
  EXPECT_EQ(o.release->reason, AmbiguityReleaseReason::FloatDeparted);
  EXPECT_NEAR(std::abs(o.release->departure_cycles), 1.0, 0.3);
  double worst_m = 0.0;
  int fixed_after = 0;
  for (std::size_t k = static_cast<std::size_t>(inject_at); k < o.clean.size(); ++k) {
    if (!o.clean[k].first || !o.wrong[k].first) continue;
    worst_m = std::max(worst_m, (*o.clean[k].first - *o.wrong[k].first).norm());
    fixed_after += o.wrong[k].second ? 1 : 0;
  }
  std::cout << "largest |injected run - clean run| from the injection on: " << 100.0 * worst_m << " cm; fixed epochs "
            << fixed_after << "\n";
  EXPECT_LT(worst_m, 0.01);
  EXPECT_GE(fixed_after, min_fixed_after);
}

// Wrong-fix injection on the EKF with GPS + Galileo (ESBC, GRG integer clocks
// with their GPS and Galileo wide-lane biases, IGS14 satellite antennas as the
// products): one held Galileo integer replaced by a wrong one (+1 narrow-lane
// cycle) at 60 min is released at the next epoch (its float, conditioned on the
// other held integers, departs by about a cycle) before it moves the fixed
// solution; the solution stays within 1 cm of the clean run's.
TEST(AmbiguityHold, RealEsbcGalileoWrongIntegerInjectedIntoTheEkfIsReleased) {
  PPP_REQUIRE_SHARED_DATA();
  PppInputFiles files = test::esbcGrgInputFiles();
  files.atx = {test::dataPath("antex/igs14_2178_satellites.atx"), test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
  const PppConfig config = parsePppConfig(
      "measurement_model:\n  signals:\n    systems: [GPS, Galileo]\nambiguity_resolution:\n  enabled: true\n",
      "ESBC GPS + Galileo AR");
  const int inject_at = 120;  // 60 min (30-s epochs)
  expectInjectionReleased(runInjection("ekf", files, config, inject_at), inject_at, 2000);
}

// The same on the smoother (the held integers are factors of its graph; the
// released one's factor is removed, PppSmoother::updateFixes), on CCJ2 with
// WUM clocks and phase OSBs, GPS + Galileo, injected at 40 min of the hour.
TEST(AmbiguityHold, RealCcj2GalileoWrongIntegerInjectedIntoTheSmootherIsReleased) {
  PPP_REQUIRE_SHARED_DATA();
  PppInputFiles files = ccj2InputFiles();
  files.atx = {test::dataPath("antex/igs14_2178_satellites.atx"), test::dataPath("antex/igs20_zim2_gps_trim.atx")};
  const PppConfig config = parsePppConfig(
      "measurement_model:\n  signals:\n    systems: [GPS, Galileo]\nambiguity_resolution:\n  enabled: true\n"
      // WUM's IGS14_2148 satellite model; the receiver file holds IGS20 satellites too (not used).
      "  allow_antenna_model_mismatch: true\n",
      "CCJ2 GPS + Galileo AR");
  const int inject_at = 80;  // 40 min
  expectInjectionReleased(runInjection("smoother", files, config, inject_at), inject_at, 30);
}

TEST(AmbiguityHold, RealCcj2HeldNarrowLanesAreIntegersAcrossArcs) {
  PPP_REQUIRE_SHARED_DATA();
  const PppInputFiles files = ccj2InputFiles();
  // Static (no position process noise): the float position is then well
  // determined and the single differences show what the products and models
  // leave in them. Wide-lane correlation time 60 s (about the 4 epochs per
  // independent MW sample of 30-s data with which this was measured): with the
  // default 15 s the wide lanes fix earlier and G01 becomes the reference instead
  // of G22; the held integers are the same (G03-G01 = G03-G22 - G01-G22 = 17 - 28),
  // but G03-G01 then carries both satellites' IGS20/IGS14 PCO offsets, 0.28 cycle.
  const PppConfig config = parsePppConfig(
      "stochastic:\n  position:\n    process_noise_m_per_sqrt_s: 0.0\n"
      "ambiguity_resolution:\n  enabled: true\n  wide_lane_correlation_time_s: 60\n"
      // WUM made its products with igs14_2148, the ANTEX is IGS20: measured as it is.
      "  allow_antenna_model_mismatch: true\n",
      "static PPP-AR");
  PppPipeline pipeline(files, config);
  const std::unique_ptr<PppEstimator> ekf_made = makeEstimator("ekf", config);
  PppEstimator& ekf = *ekf_made;
  int fixed_epochs = 0;
  pipeline.run(ekf, [&](const PppEpochRecord& r) { fixed_epochs += r.ambiguity_fix && r.ambiguity_fix->fixed(); });
  ASSERT_TRUE(ekf.lastResult().ambiguity_fix.has_value());
  const AmbiguityFixSummary& s = *ekf.lastResult().ambiguity_fix;
  int bins[5] = {0, 0, 0, 0, 0};
  int held = 0;
  for (const auto& n : s.narrow_lanes) {
    std::cout << "  " << n.satellite.toString() << "-" << n.reference_satellite.toString() << " WL "
              << n.wide_lane_cycles << " NL float " << n.float_cycles << " +- " << n.sigma_cycles
              << (n.held_cycles ? " held " + std::to_string(*n.held_cycles) : std::string(" float")) << "\n";
    if (!n.held_cycles) continue;
    ++held;
    const double residual = n.float_cycles - static_cast<double>(*n.held_cycles);
    ++bins[std::min(4, static_cast<int>(std::abs(residual) * 10.0))];
    EXPECT_LT(std::abs(residual), 0.25) << n.satellite.toString();
  }
  std::cout << "CCJ2 static, held NL |float - integer| <0.1: " << bins[0] << ", 0.1-0.2: " << bins[1]
            << ", 0.2-0.3: " << bins[2] << ", 0.3-0.4: " << bins[3] << ", 0.4-0.5: " << bins[4] << " (" << held
            << " held, " << fixed_epochs << " fixed epochs, " << s.text() << ")\n";
  EXPECT_GE(held, config.ambiguity_resolution.narrow_lane.min_fixed);
}

TEST(AmbiguityHold, RealCcj2PosFileHasQ1AndTheRatioOnFixedEpochs) {
  // ppp_solve's .pos on CCJ2 with the defaults (AR auto on the WUM OSBs, IGS14
  // satellite antennas): RTKLIB's convention (solution.c outsolxyz): Q 1 for a fix,
  // the ratio column the ratio test value of the fix; float epochs Q 6, ratio 0.
  PPP_REQUIRE_SHARED_DATA();
  const std::string dir = test::tempDir("ambiguity_hold_pos").string();
  PppSolveRequest request = test::solveRequest(test::ccj2Dataset(), dir, "ekf");
  request.files.atx = {test::dataPath("antex/igs14_2178_satellites.atx"),
                       test::dataPath("antex/igs20_zim2_gps_trim.atx")};
  request.files.blq = test::dataPath("oceanload/ccj2_fes2004.blq");
  const std::vector<PppSolveOutcome> runs = solvePppEstimators(request);
  ASSERT_EQ(runs.size(), 1u);
  ASSERT_EQ(runs[0].outputs.size(), 1u);
  const PppSolutionOutput& out = runs[0].outputs[0];
  const PosFile pos = readRtklibPos(out.pos_path);
  EXPECT_TRUE(pos.report.clean()) << pos.report.summary();
  std::vector<const SolutionEpoch*> solved;
  for (const auto& e : out.solution)
    if (e.position_ecef_m) solved.push_back(&e);
  ASSERT_EQ(pos.records.size(), solved.size());
  int fixed = 0;
  for (std::size_t i = 0; i < solved.size(); ++i) {
    const SolutionEpoch& e = *solved[i];
    const PosRecord& r = pos.records[i];
    ASSERT_TRUE(r.ratio.has_value());
    if (e.status == SolutionStatus::PppFixed) {
      ++fixed;
      EXPECT_EQ(r.quality, 1);
      ASSERT_TRUE(e.ambiguity_ratio.has_value());
      EXPECT_GT(*r.ratio, 0.0);
      EXPECT_NEAR(*r.ratio, std::min(*e.ambiguity_ratio, 999.9), 0.05 + 1e-9);  // %6.1f
    } else {
      EXPECT_EQ(r.quality, 6);
      EXPECT_EQ(*r.ratio, 0.0);
    }
  }
  EXPECT_GT(fixed, 10) << "CCJ2 with the defaults fixes (test_product_assembly: the gate fixes)";
}

TEST(AmbiguityHold, RealEsbcStaticFixesStayNearTheDaysFloatPosition) {
  // ESBC 2020-177, GRG integer-recovery clocks (wide-lane biases in the clock
  // header), static EKF over the whole day. No external truth: the reference is
  // the day's own float static position (the last solved epoch). After the
  // first hour at least 89.5 % of the epochs are fixed (79.9 % without the
  // candidate gate, 86.2 % with it, 89.9 % when the held integers also survive
  // the end of their reference arc; ppp_ar_study --static, doc/studies/ar_real_data.md) and no fixed epoch is
  // more than 10 cm from the reference (the wrong-fix criterion).
  PPP_REQUIRE_SHARED_DATA();
  const PppInputFiles files = test::esbcGrgInputFiles();
  // The figures above were measured with the method's wet-delay random walk of
  // 3e-5 m/sqrt(s), which this measurement keeps (with the default 1e-4 the
  // mismatched antennas leave 87.6 % fixed, still none > 10 cm off).
  const std::string static_yaml =
      "stochastic:\n  position:\n    process_noise_m_per_sqrt_s: 0.0\n  zwd:\n    process_noise_m_per_sqrt_s: 3.0e-5\n";
  auto run = [&](const std::string& yaml, std::vector<std::pair<Eigen::Vector3d, bool>>& out) {
    const PppConfig config = parsePppConfig(yaml, "ESBC static");
    PppPipeline pipeline(files, config);
    const std::unique_ptr<PppEstimator> ekf_made = makeEstimator("ekf", config);
    PppEstimator& ekf = *ekf_made;
    pipeline.run(ekf, [&](const PppEpochRecord& r) {
      if (r.solution.position_ecef_m)
        out.emplace_back(*r.solution.position_ecef_m, r.solution.status == SolutionStatus::PppFixed);
    });
  };
  std::vector<std::pair<Eigen::Vector3d, bool>> floats, fixes;
  run(static_yaml, floats);
  // GRG made its products with igs14_2108, the ANTEX is IGS20: the mismatch is measured as it is.
  run(static_yaml + "ambiguity_resolution:\n  enabled: true\n  allow_antenna_model_mismatch: true\n", fixes);
  ASSERT_GT(floats.size(), 2000u);
  ASSERT_GT(fixes.size(), 2000u);
  const Eigen::Vector3d reference = floats.back().first;
  const std::size_t first_hour = 120;  // 30-s epochs
  int fixed = 0, after = 0;
  double worst_fixed_m = 0.0, worst_float_m = 0.0;
  for (std::size_t i = first_hour; i < fixes.size(); ++i) {
    ++after;
    if (!fixes[i].second) continue;
    ++fixed;
    worst_fixed_m = std::max(worst_fixed_m, (fixes[i].first - reference).norm());
  }
  for (std::size_t i = first_hour; i < floats.size(); ++i)
    worst_float_m = std::max(worst_float_m, (floats[i].first - reference).norm());
  const double share = static_cast<double>(fixed) / after;
  std::cout << "ESBC static: fixed " << fixed << " of " << after << " epochs after the first hour (" << 100.0 * share
            << " %), largest 3D distance from the day's float position: fixed " << 100.0 * worst_fixed_m
            << " cm, float " << 100.0 * worst_float_m << " cm\n";
  EXPECT_GE(share, 0.895);
  EXPECT_LT(worst_fixed_m, 0.10);
}

TEST(AmbiguityHold, RealEsbcKinematicOffsetsAreConstantPerSingleDifference) {
  // ESBC 2020-177, GRG integer-recovery clocks, kinematic EKF with AR (the
  // defaults), judged against the day's float static position (the last solved
  // epoch). Measured with ppp_ar_study (doc/studies/ar_real_data.md): 78.1 % of the
  // epochs after the first hour fixed (77.7 % before the held integers survived
  // the end of their reference arc), 96 fixed epochs > 10 cm (66 of them where
  // the float is > 10 cm too), first fix 119.5 min.
  // The held narrow lanes' floats lie 0.14 cycle RMS from their integers but
  // only 0.026 cycle about their own single difference's mean over the day: the
  // offsets are constant per satellite (a model/product mismatch: GRG made its
  // clocks with igs14_2108.atx, we use IGS20 satellite antennas), not noise the
  // covariance misses (the held floats' formal sigma is 0.036 cycle median).
  // Without tropospheric gradients, as the figures were measured. With them (the
  // default since) 81.5 % are fixed and 151 fixed epochs are > 10 cm: the hours
  // 13 and 22-23 UTC, whose float and fixed heights lie 7-11 cm off in this GPS-only
  // run without ocean loading either way, move by another centimetre and cross 10 cm
  // (hour 22: 67 -> 97 of 116 fixed epochs).
  PPP_REQUIRE_SHARED_DATA();
  const PppInputFiles files = test::esbcGrgInputFiles();
  const std::string no_gradients = "measurement_model:\n  troposphere:\n    estimate_gradients: false\n";
  std::optional<Eigen::Vector3d> reference;
  {
    const PppConfig config = parsePppConfig(
        "stochastic:\n  position:\n    process_noise_m_per_sqrt_s: 0.0\n" + no_gradients, "ESBC static float");
    PppPipeline pipeline(files, config);
    const std::unique_ptr<PppEstimator> ekf_made = makeEstimator("ekf", config);
    PppEstimator& ekf = *ekf_made;
    pipeline.run(ekf, [&](const PppEpochRecord& r) {
      if (r.solution.position_ecef_m) reference = r.solution.position_ecef_m;
    });
  }
  ASSERT_TRUE(reference.has_value());
  // IGS14 products, IGS20 ANTEX; white code weighting, as the figures of
  // doc/studies/ar_real_data.md (with the default 15-s code correlation: 77.6 % fixed, 96 > 10 cm).
  const PppConfig config = parsePppConfig(
      "stochastic:\n  code_correlation_time_s: 0.0\n"
      "ambiguity_resolution:\n  enabled: true\n  allow_antenna_model_mismatch: true\n" + no_gradients,
      "ESBC kinematic AR");
  PppPipeline pipeline(files, config);
  const std::unique_ptr<PppEstimator> ekf_made = makeEstimator("ekf", config);
  PppEstimator& ekf = *ekf_made;
  std::vector<std::pair<Eigen::Vector3d, bool>> solved;
  std::vector<std::optional<AmbiguityFixSummary>> summaries;  // of each solved epoch
  pipeline.run(ekf, [&](const PppEpochRecord& r) {
    if (!r.solution.position_ecef_m) return;
    solved.emplace_back(*r.solution.position_ecef_m, r.solution.status == SolutionStatus::PppFixed);
    summaries.push_back(r.ambiguity_fix);
  });
  ASSERT_GT(solved.size(), 2000u);
  const std::size_t first_hour = 120;  // 30-s epochs
  int after = 0, fixed = 0, wrong = 0;
  std::map<std::pair<int, int>, std::vector<double>> residuals;  // (satellite, reference) -> float - integer
  for (std::size_t i = first_hour; i < solved.size(); ++i) {
    ++after;
    if (!solved[i].second) continue;
    ++fixed;
    if ((solved[i].first - *reference).norm() > 0.10) ++wrong;
    const auto& summary = summaries[i];
    if (!summary) continue;
    for (const auto& n : summary->narrow_lanes)
      if (n.held_cycles)
        residuals[{n.satellite.prn, n.reference_satellite.prn}].push_back(n.float_cycles -
                                                                          static_cast<double>(*n.held_cycles));
  }
  double sum_sq = 0.0, within_sq = 0.0;
  std::size_t count = 0;
  for (const auto& [pair, r] : residuals) {
    double mean = 0.0;
    for (double v : r) mean += v;
    mean /= static_cast<double>(r.size());
    for (double v : r) sum_sq += v * v, within_sq += (v - mean) * (v - mean);
    count += r.size();
  }
  ASSERT_GT(count, 10000u);
  const double rms = std::sqrt(sum_sq / count), within = std::sqrt(within_sq / count);
  const double share = static_cast<double>(fixed) / after;
  std::cout << "ESBC kinematic AR: fixed " << fixed << " of " << after << " epochs after the first hour (" << 100.0 * share
            << " %), " << wrong << " fixed epochs > 10 cm from the day's float static position; held NL float - integer: "
            << "RMS " << rms << " cycle, about each single difference's mean " << within << " cycle (" << count
            << " values, " << residuals.size() << " single differences)\n";
  EXPECT_GE(share, 0.780);
  EXPECT_LE(wrong, 96);
  EXPECT_GT(rms, 0.10);
  EXPECT_LT(within, 0.04);
}

}  // namespace
}  // namespace ppp
