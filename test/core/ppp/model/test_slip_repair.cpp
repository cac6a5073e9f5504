// Slip repair (slip_repair.h): known slips injected into synthetic
// Melbourne-Wubbena and geometry-free series across a 30-s gap are recovered; a
// wide lane wrong by one cycle and a half-cycle L1 offset are refused by the L1
// fraction bound; where the geometry-free phase leaves several wide lanes (Galileo
// E1/E5a, a noisy Melbourne-Wubbena jump) they are candidates with the true slip
// among them, or refused as ambiguous without candidates; a wide lane just over the
// L1 fraction bound that fits both jumps better than one just under it is kept as a
// candidate; noise beyond the sigma bounds and too short a fit are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ppp_bayes_tree/ppp/model/slip_repair.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

// GPS L1/L2 (IS-GPS-200: 154 and 120 x 10.23 MHz) and Galileo E1/E5a (Galileo OS SIS ICD: 154 and 115 x 10.23 MHz).
constexpr double kGpsLambda1 = kSpeedOfLight_mps / 1575.42e6, kGpsLambda2 = kSpeedOfLight_mps / 1227.60e6;
constexpr double kGalLambda1 = kSpeedOfLight_mps / 1575.42e6, kGalLambda2 = kSpeedOfLight_mps / 1176.45e6;

/// A smooth ionosphere in the GF phase [m]: offset, drift and a slow curvature.
double ionosphere_m(double t_s) { return 0.8 + 2.0e-4 * t_s + 5.0e-7 * t_s * t_s; }

/// A 60-s arc at 1 Hz (phase noise 3 mm per frequency, MW noise 0.15 cycles over
/// 60 epochs), then a gap of gap_s and the epoch after it with the slip (dN1, dN2).
SlipRepairInput arcAcrossGap(unsigned seed, long dn1, long dn2, double lambda1, double lambda2, double gap_s = 30.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gf_noise(0.0, std::sqrt(2.0) * 0.003), mw_noise(0.0, 0.15);
  SlipRepairInput in;
  for (int k = 0; k < 60; ++k) in.gf_before.emplace_back(k, ionosphere_m(k) + gf_noise(rng));
  in.time_after_s = 59.0 + gap_s;
  in.gf_after_m = ionosphere_m(in.time_after_s) + lambda1 * dn1 - lambda2 * dn2 + gf_noise(rng);
  in.mw_jump_cycles = static_cast<double>(dn1 - dn2) + mw_noise(rng);
  in.mw_sigma_cycles = 0.15;
  in.mw_samples = 60;
  in.wavelength1_m = lambda1;
  in.wavelength2_m = lambda2;
  return in;
}

TEST(SlipRepair, KnownSlipsAreRecovered) {
  const std::vector<std::pair<long, long>> slips = {{3, 0}, {-7, -5}, {1, 1}, {250, -610}, {0, 1}, {-1000, 999}};
  unsigned seed = 1;
  for (const auto& [dn1, dn2] : slips) {
    const SlipRepair r = repairSlip(arcAcrossGap(seed++, dn1, dn2, kGpsLambda1, kGpsLambda2), {});
    EXPECT_EQ(r.outcome, SlipRepairOutcome::Repaired) << r.text;
    EXPECT_EQ(r.dn1_cycles, dn1) << r.text;
    EXPECT_EQ(r.dn2_cycles, dn2) << r.text;
    EXPECT_LE(r.l1_sigma_cycles, 0.15) << r.text;
    EXPECT_TRUE(r.alternatives.empty()) << r.text;
    // Galileo E1/E5a: a wide lane one off gives an integer L1 too (-3.95 cycles):
    // candidates for the gap bridge (the true one applied, the MW being 0.15 cycles
    // off), or refused without candidates.
    const unsigned gal_seed = seed++;
    const SlipRepair g = repairSlip(arcAcrossGap(gal_seed, dn1, dn2, kGalLambda1, kGalLambda2), {});
    EXPECT_EQ(g.outcome, SlipRepairOutcome::Repaired) << g.text;
    EXPECT_EQ(g.dn1_cycles, dn1) << g.text;
    EXPECT_EQ(g.dn2_cycles, dn2) << g.text;
    ASSERT_FALSE(g.alternatives.empty()) << g.text;
    for (const SlipCandidate& c : g.alternatives) {
      const long dnw = (c.dn1_cycles - c.dn2_cycles) - (dn1 - dn2);
      EXPECT_EQ(std::abs(dnw), 1) << g.text;             // within 1.5 cycles of the MW
      EXPECT_EQ(c.dn1_cycles - dn1, 4 * dnw) << g.text;  // L1 moves by 3.95 cycles per wide-lane cycle
    }
    SlipRepairOptions unique_only;
    unique_only.max_candidate_wide_lane_sigma_cycles = 0.0;
    EXPECT_EQ(repairSlip(arcAcrossGap(gal_seed, dn1, dn2, kGalLambda1, kGalLambda2), unique_only).outcome,
              SlipRepairOutcome::Ambiguous);
  }
}

TEST(SlipRepair, NoSlipIsIdentifiedAsSuch) {
  const SlipRepair r = repairSlip(arcAcrossGap(3, 0, 0, kGpsLambda1, kGpsLambda2, 60.0), {});
  EXPECT_EQ(r.outcome, SlipRepairOutcome::NoSlip) << r.text;
  EXPECT_TRUE(r.accepted());
  EXPECT_EQ(r.dn1_cycles, 0);
  EXPECT_EQ(r.dn2_cycles, 0);
}

// A Melbourne-Wubbena jump one cycle off (the true wide lane beyond the 0.6-cycle
// search): the L1 estimate moves by lambda2 / (lambda1 - lambda2) = -4.53 cycles,
// half a cycle from an integer: refused without candidates; with them (1.5 cycles
// either side) the true slip and the wide lane two off (L1 9 cycles off) are the
// candidates.
TEST(SlipRepair, AWideLaneOneCycleOffIsRefusedOrLeftToCandidates) {
  SlipRepairInput in = arcAcrossGap(4, 3, 0, kGpsLambda1, kGpsLambda2);
  in.mw_jump_cycles = std::round(in.mw_jump_cycles) + 1.0;
  SlipRepairOptions unique_only;
  unique_only.max_candidate_wide_lane_sigma_cycles = 0.0;
  const SlipRepair r = repairSlip(in, unique_only);
  EXPECT_EQ(r.outcome, SlipRepairOutcome::L1NotInteger) << r.text;
  EXPECT_FALSE(r.accepted());
  EXPECT_NEAR(std::abs(r.l1_cycles - std::round(r.l1_cycles)), 0.47, 0.15) << r.text;
  const SlipRepair c = repairSlip(in, {});
  ASSERT_TRUE(c.accepted()) << c.text;
  ASSERT_EQ(c.alternatives.size(), 1u) << c.text;
  const auto is = [](const SlipCandidate& s, long dn1, long dn2) { return s.dn1_cycles == dn1 && s.dn2_cycles == dn2; };
  EXPECT_TRUE(is(c.applied(), 3, 0) || is(c.alternatives[0], 3, 0)) << c.text;
  EXPECT_TRUE(is(c.applied(), 12, 7) || is(c.alternatives[0], 12, 7)) << c.text;
}

// Half a cycle of L1 in the geometry-free jump: no wide lane within 0.6 cycles gives
// an integer L1 (refused without candidates); the neighbours 1 cycle either side do
// (L1 -4.53 + 0.5 and 4.53 + 0.5 cycles from the true one: dN1 -1 and +8): wrong
// candidates, left to the gap bridge, which finds them 4 and 5 L1 cycles off.
TEST(SlipRepair, HalfACycleOfL1IsRefusedOrLeftToCandidates) {
  SlipRepairInput in = arcAcrossGap(5, 3, 0, kGpsLambda1, kGpsLambda2);
  in.gf_after_m += 0.5 * (kGpsLambda1 - kGpsLambda2);
  SlipRepairOptions unique_only;
  unique_only.max_candidate_wide_lane_sigma_cycles = 0.0;
  EXPECT_EQ(repairSlip(in, unique_only).outcome, SlipRepairOutcome::L1NotInteger);
  const SlipRepair c = repairSlip(in, {});
  ASSERT_TRUE(c.accepted()) << c.text;
  std::vector<SlipCandidate> all{c.applied()};
  all.insert(all.end(), c.alternatives.begin(), c.alternatives.end());
  ASSERT_EQ(all.size(), 2u) << c.text;
  for (const SlipCandidate& s : all) {
    EXPECT_EQ(std::abs((s.dn1_cycles - s.dn2_cycles) - 3), 1) << c.text;
    EXPECT_NEAR(std::abs(s.dn1_cycles - 3), 4.5, 0.5) << c.text;  // -1 or +8
  }
}

// Between two integers the L1 test picks the wide lane (GPS: the other gives a
// half-cycle L1); for Galileo E1/E5a both give a near-integer L1 (-3.95 cycles
// apart): both are candidates, the nearer applied.
TEST(SlipRepair, AWideLaneBetweenIntegersIsChosenByL1OrRefused) {
  SlipRepairInput gps = arcAcrossGap(6, 3, 0, kGpsLambda1, kGpsLambda2);
  gps.mw_jump_cycles = 3.45;
  const SlipRepair r = repairSlip(gps, {});
  EXPECT_EQ(r.outcome, SlipRepairOutcome::Repaired) << r.text;
  EXPECT_EQ(r.dn1_cycles, 3);
  EXPECT_EQ(r.dn2_cycles, 0);
  SlipRepairInput gal = arcAcrossGap(6, 3, 0, kGalLambda1, kGalLambda2);
  gal.mw_jump_cycles = 3.45;
  const SlipRepair g = repairSlip(gal, {});
  EXPECT_EQ(g.outcome, SlipRepairOutcome::Repaired) << g.text;
  EXPECT_EQ(g.dn1_cycles - g.dn2_cycles, 3) << g.text;
  // Within 1.5 cycles of 3.45: wide lanes 2, 3, 4; 3 nearest, then 4, then 2.
  ASSERT_EQ(g.alternatives.size(), 2u) << g.text;
  EXPECT_EQ(g.alternatives[0].dn1_cycles - g.alternatives[0].dn2_cycles, 4) << g.text;
  EXPECT_EQ(g.alternatives[0].dn1_cycles, g.dn1_cycles + 4) << g.text;
  EXPECT_EQ(g.alternatives[1].dn1_cycles - g.alternatives[1].dn2_cycles, 2) << g.text;
  EXPECT_EQ(g.alternatives[1].dn1_cycles, g.dn1_cycles - 4) << g.text;
}

// A Melbourne-Wubbena jump too noisy to round (sigma 0.6 cycles, as under
// time-correlated code multipath) and 1.3 cycles off the true wide lane: GPS
// candidates are 2 wide-lane cycles apart (the odd ones give a half-cycle L1): L1
// 9 and L2 7 cycles apart, 9 x 0.1903 m - 7 x 0.2442 m = 3 mm in the geometry-free
// phase; the true one is among them. Choosing another makes it the applied one.
TEST(SlipRepair, ANoisyWideLaneGivesCandidates) {
  SlipRepairInput in = arcAcrossGap(12, 5, -2, kGpsLambda1, kGpsLambda2);
  in.mw_jump_cycles = 7.0 + 1.3;
  in.mw_sigma_cycles = 0.6;
  const SlipRepair r = repairSlip(in, {});
  ASSERT_TRUE(r.accepted()) << r.text;
  std::vector<SlipCandidate> all{r.applied()};
  all.insert(all.end(), r.alternatives.begin(), r.alternatives.end());
  ASSERT_GE(all.size(), 2u) << r.text;
  bool true_one = false;
  for (const SlipCandidate& c : all) {
    EXPECT_EQ(((c.dn1_cycles - c.dn2_cycles) - 7) % 2, 0) << r.text;
    EXPECT_EQ((c.dn1_cycles - 5) * 7, (c.dn2_cycles + 2) * 9) << r.text;  // steps of (9, 7)
    true_one = true_one || (c.dn1_cycles == 5 && c.dn2_cycles == -2);
  }
  EXPECT_TRUE(true_one) << r.text;
  // The applied one is the nearest the MW estimate (8.3): wide lane 9.
  EXPECT_EQ(r.dn1_cycles - r.dn2_cycles, 9) << r.text;
  SlipRepair chosen = r;
  chosen.choose({5, -2, 5.0});
  EXPECT_EQ(chosen.dn1_cycles, 5);
  EXPECT_EQ(chosen.dn2_cycles, -2);
  EXPECT_EQ(chosen.alternatives.size(), r.alternatives.size());
  EXPECT_NE(chosen.text.find("chosen by the gap bridge over dN1 +14 dN2 +5"), std::string::npos) << chosen.text;
  // More candidates than allowed: refused.
  SlipRepairOptions few;
  few.max_candidates = 1;
  EXPECT_EQ(repairSlip(in, few).outcome, SlipRepairOutcome::TooManyCandidates);
}

/// The arc of arcAcrossGap with the epoch after the gap set exactly: the MW jump at
/// mw_jump_cycles and the geometry-free jump off the slip (dN1, dN2) by gf_error_m
/// (the fit's own prediction taken as the ionosphere).
SlipRepairInput arcWithJumps(long dn1, long dn2, double lambda1, double lambda2, double gap_s, double mw_jump_cycles,
                             double mw_sigma_cycles, double gf_error_m) {
  SlipRepairInput in = arcAcrossGap(13, dn1, dn2, lambda1, lambda2, gap_s);
  const SlipRepairOptions defaults;
  const auto fit = predictGeometryFreeFit(in.gf_before, in.time_after_s, defaults.gf_fit_order,
                                          std::sqrt(2.0) * defaults.phase_sigma_m);
  in.gf_after_m = fit->value_m + lambda1 * static_cast<double>(dn1) - lambda2 * static_cast<double>(dn2) + gf_error_m;
  in.mw_jump_cycles = mw_jump_cycles;
  in.mw_sigma_cycles = mw_sigma_cycles;
  return in;
}

/// A wide lane's L1 estimate [cycles], its distance to an integer and its joint misfit
/// (MW offset and L1 fraction in their sigmas, squared and summed), recomputed from
/// the jumps and the sigmas of `r`.
struct WideLaneFit {
  double l1_cycles, fraction_cycles, misfit;
};
WideLaneFit fitOf(const SlipRepairInput& in, const SlipRepair& r, long nw) {
  const double jump_m = in.gf_after_m - r.gf_prediction_m;
  const double l1 = (jump_m - in.wavelength2_m * static_cast<double>(nw)) / (in.wavelength1_m - in.wavelength2_m);
  const double fraction = std::abs(l1 - std::round(l1));
  const double mw = (static_cast<double>(nw) - r.wide_lane_cycles) / r.wide_lane_sigma_cycles;
  return {l1, fraction, mw * mw + std::pow(fraction / r.l1_sigma_cycles, 2)};
}

// Galileo E1/E5a after a 60-s gap, the slip dN1 +814 dN2 +700 (wide lane 114), MW
// 114.13 +- 0.35, and a geometry-free error of 1.74 cm (0.27 L1 cycle): wide lane
// 114's L1 is 0.27 cycles from an integer, just over the 0.25 bound; 113's 0.22 (E1/E5a
// neighbours differ by 0.05 cycles in their fractions), just under it, but 1.13
// wide-lane cycles (3.2 sigmas) from the MW estimate. Taken alone, 113 would be the
// only candidate and one wide lane off, with nothing for the gap bridge to choose (a
// simulated flight's 60-s outage); 114 fits both jumps better, so it is kept: applied,
// with 113 beside it. 115 (L1 0.32 from an integer, 0.87 from the MW) fits worse than
// 113 and is not.
TEST(SlipRepair, AWideLaneJustOverTheL1BoundIsKeptBesideAFartherOneJustUnder) {
  const double dl = kGalLambda1 - kGalLambda2;
  const SlipRepairInput in = arcWithJumps(814, 700, kGalLambda1, kGalLambda2, 60.0, 114.13, 0.345, -0.27 * dl);
  const SlipRepair r = repairSlip(in, {});
  const WideLaneFit w113 = fitOf(in, r, 113), w114 = fitOf(in, r, 114), w115 = fitOf(in, r, 115);
  // The case as described (the sigmas are the repair's own).
  ASSERT_NEAR(r.wide_lane_sigma_cycles, 0.35, 0.01) << r.text;
  ASSERT_GT(w114.fraction_cycles, 0.25);
  ASSERT_LE(w113.fraction_cycles, 0.25);
  ASSERT_GT(w115.fraction_cycles, 0.25);
  ASSERT_LT(w114.misfit, w113.misfit);
  ASSERT_LT(w114.misfit, 13.82);
  ASSERT_GT(w115.misfit, w113.misfit);
  EXPECT_EQ(r.outcome, SlipRepairOutcome::Repaired) << r.text;
  EXPECT_EQ(r.dn1_cycles, 814) << r.text;
  EXPECT_EQ(r.dn2_cycles, 700) << r.text;
  ASSERT_EQ(r.alternatives.size(), 1u) << r.text;
  EXPECT_EQ(r.alternatives[0].dn1_cycles, 810) << r.text;
  EXPECT_EQ(r.alternatives[0].dn2_cycles, 697) << r.text;
  // Without the joint misfit (as before): 113 alone, one wide lane off.
  SlipRepairOptions fraction_only;
  fraction_only.max_joint_misfit = 0.0;
  const SlipRepair f = repairSlip(in, fraction_only);
  EXPECT_EQ(f.dn1_cycles, 810) << f.text;
  EXPECT_TRUE(f.alternatives.empty()) << f.text;
  // Without candidates the wide lane within 0.6 cycles fails the L1 test: refused.
  SlipRepairOptions unique_only;
  unique_only.max_candidate_wide_lane_sigma_cycles = 0.0;
  EXPECT_EQ(repairSlip(in, unique_only).outcome, SlipRepairOutcome::L1NotInteger);
  // 0.37 cycles of geometry-free error instead: no wide lane within 1.5 cycles passes,
  // so none is taken on its misfit either: refused rather than repaired far from the MW.
  const SlipRepairInput far = arcWithJumps(814, 700, kGalLambda1, kGalLambda2, 60.0, 114.13, 0.345, -0.37 * dl);
  const SlipRepair g = repairSlip(far, {});
  for (const long nw : {113L, 114L, 115L}) ASSERT_GT(fitOf(far, g, nw).fraction_cycles, 0.25) << nw;
  EXPECT_EQ(g.outcome, SlipRepairOutcome::L1NotInteger) << g.text;
}

// GPS L1/L2 after a 30-s gap, the slip dN1 +14 dN2 +3 (wide lane 11), MW 10.59 +- 0.25
// (wide lanes 10 and 11 both within 0.6 cycles), and a geometry-free error making
// 11's L1 0.26 cycles from an integer (just over the bound) and 10's 0.21 (GPS
// neighbours' fractions add up to about 0.47). 10 alone passes and its neighbours fail
// the L1 test: unique by the fraction bound alone, and one wide lane off. But 11 fits
// both jumps better, so the repair is not unique: both are candidates, 11 (the
// nearer) applied.
TEST(SlipRepair, ANeighbourFittingBetterMakesTheRepairNotUnique) {
  const double dl = kGpsLambda1 - kGpsLambda2;
  SlipRepairOptions o;
  o.ionosphere_sigma_mps = 1.5e-4;  // an active ionosphere: the L1 sigma near 0.13 cycles
  const SlipRepairInput in = arcWithJumps(14, 3, kGpsLambda1, kGpsLambda2, 30.0, 10.59, 0.25, -0.26 * dl);
  const SlipRepair r = repairSlip(in, o);
  const WideLaneFit w10 = fitOf(in, r, 10), w11 = fitOf(in, r, 11);
  ASSERT_LE(w10.fraction_cycles, 0.25);
  ASSERT_GT(w11.fraction_cycles, 0.25);
  for (const long nw : {9L, 12L}) ASSERT_GT(fitOf(in, r, nw).fraction_cycles, 0.25) << nw;
  ASSERT_LT(w11.misfit, w10.misfit) << r.text;
  EXPECT_EQ(r.outcome, SlipRepairOutcome::Repaired) << r.text;
  EXPECT_EQ(r.dn1_cycles, 14) << r.text;
  EXPECT_EQ(r.dn2_cycles, 3) << r.text;
  ASSERT_EQ(r.alternatives.size(), 1u) << r.text;
  EXPECT_EQ(r.alternatives[0].dn1_cycles - r.alternatives[0].dn2_cycles, 10) << r.text;
  // Without candidates: ambiguous, and the text says why.
  SlipRepairOptions unique_only = o;
  unique_only.max_candidate_wide_lane_sigma_cycles = 0.0;
  const SlipRepair u = repairSlip(in, unique_only);
  EXPECT_EQ(u.outcome, SlipRepairOutcome::Ambiguous) << u.text;
  EXPECT_NE(u.text.find("wide lane 11 fits the MW and geometry-free jumps better than 10"), std::string::npos)
      << u.text;
  // Without the joint misfit (as before): unique, one wide lane off.
  SlipRepairOptions fraction_only = o;
  fraction_only.max_joint_misfit = 0.0;
  const SlipRepair f = repairSlip(in, fraction_only);
  EXPECT_EQ(f.dn1_cycles - f.dn2_cycles, 10) << f.text;
  EXPECT_TRUE(f.alternatives.empty()) << f.text;
}

TEST(SlipRepair, NoiseBeyondTheBoundsIsRefused) {
  // Melbourne-Wubbena noise of 1.2 cycles: sigma above 0.35, and above 1.0 for candidates.
  SlipRepairInput noisy_mw = arcAcrossGap(7, 3, 0, kGpsLambda1, kGpsLambda2);
  noisy_mw.mw_sigma_cycles = 1.2;
  EXPECT_EQ(repairSlip(noisy_mw, {}).outcome, SlipRepairOutcome::WideLaneTooUncertain);
  // 0.5 cycles: refused without candidates.
  noisy_mw.mw_sigma_cycles = 0.5;
  SlipRepairOptions unique_only;
  unique_only.max_candidate_wide_lane_sigma_cycles = 0.0;
  EXPECT_EQ(repairSlip(noisy_mw, unique_only).outcome, SlipRepairOutcome::WideLaneTooUncertain);
  // Geometry-free scatter of 2.5 cm before the gap: the jump's sigma over 0.15 L1 cycle (8 mm).
  SlipRepairInput noisy_gf = arcAcrossGap(8, 3, 0, kGpsLambda1, kGpsLambda2);
  std::mt19937 rng(9);
  std::normal_distribution<double> extra(0.0, 0.025);
  for (auto& s : noisy_gf.gf_before) s.second += extra(rng);
  EXPECT_EQ(repairSlip(noisy_gf, {}).outcome, SlipRepairOutcome::L1TooUncertain);
  // A gap so long that the ionosphere's unmodelled drift alone exceeds the bound.
  SlipRepairInput long_gap = arcAcrossGap(10, 3, 0, kGpsLambda1, kGpsLambda2, 120.0);
  SlipRepairOptions o;
  o.ionosphere_sigma_mps = 1.0e-4;
  EXPECT_EQ(repairSlip(long_gap, o).outcome, SlipRepairOutcome::L1TooUncertain);
}

TEST(SlipRepair, TooFewSamplesAreRefused) {
  SlipRepairInput in = arcAcrossGap(11, 3, 0, kGpsLambda1, kGpsLambda2);
  in.gf_before.resize(4);
  const SlipRepair r = repairSlip(in, {});
  EXPECT_EQ(r.outcome, SlipRepairOutcome::TooFewSamples);
  EXPECT_STREQ(slipRepairOutcomeName(r.outcome), "too few geometry-free samples");
}

TEST(SlipRepair, FitsExtrapolateLinesAndParabolas) {
  std::vector<std::pair<double, double>> line, parabola;
  for (int k = 0; k < 10; ++k) {
    line.emplace_back(100.0 + k, 1.0 + 0.01 * k);
    parabola.emplace_back(100.0 + k, 1.0 + 0.01 * k + 0.001 * k * k);
  }
  const auto l = predictGeometryFreeFit(line, 139.0, 1, 0.001);
  ASSERT_TRUE(l);
  EXPECT_NEAR(l->value_m, 1.39, 1e-9);
  const auto p = predictGeometryFreeFit(parabola, 139.0, 2, 0.001);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->value_m, 1.0 + 0.39 + 0.001 * 39 * 39, 1e-9);
  // The extrapolation's sigma grows with the distance from the samples.
  EXPECT_GT(p->sigma_m, predictGeometryFreeFit(parabola, 110.0, 2, 0.001)->sigma_m);
  EXPECT_FALSE(predictGeometryFreeFit({{0.0, 1.0}, {1.0, 1.0}}, 2.0, 1, 0.001));
}

}  // namespace
}  // namespace ppp
