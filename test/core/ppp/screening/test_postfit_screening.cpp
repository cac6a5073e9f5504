// The postfit checks both estimators share (postfit_screening.h): the worst
// normalised postfit residual, the chi-square quantile and the epoch consistency test.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"

namespace ppp {
namespace {

TEST(PostfitScreening, WorstResidualIsTheLargestNormalisedOneAboveTheThreshold) {
  const std::vector<PostfitResidualPair> pairs{
      {1.0, 0.010, 1.0, 0.01},   // code 1 sigma, phase 1 sigma
      {-3.0, 0.004, 1.0, 0.01},  // code 3 sigma
      {0.5, -0.062, 1.0, 0.01},  // phase 6.2 sigma: the worst
  };
  const auto worst = worstPostfitResidual(pairs, 5.0);
  ASSERT_TRUE(worst.has_value());
  EXPECT_EQ(worst->index, 2u);
  EXPECT_FALSE(worst->code);
  EXPECT_DOUBLE_EQ(worst->residual_m, -0.062);
  EXPECT_NEAR(worst->normalised, 6.2, 1e-12);
  EXPECT_FALSE(worstPostfitResidual(pairs, 6.5).has_value());  // nothing above 6.5 sigma
  EXPECT_FALSE(worstPostfitResidual({}, 5.0).has_value());

  const RejectedSatellite r = postfitRejection(SatelliteId{GnssSystem::GPS, 15}, *worst, 5.0);
  EXPECT_EQ(r.reason, RejectionReason::PostfitPhase);
  EXPECT_EQ(r.detail, "postfit phase residual -0.062 m = 6.2 sigma > 5.0 sigma");
  // Ties: the code residual first (the EKF's order before the shared function).
  const auto tie = worstPostfitResidual({{2.0, 0.02, 1.0, 0.01}}, 1.0);
  ASSERT_TRUE(tie.has_value());
  EXPECT_TRUE(tie->code);
}

// Reference quantiles: NIST/SEMATECH e-Handbook of Statistical Methods, 1.3.6.7.4
// "Critical values of the chi-square distribution" (upper tail): 10 dof 18.307
// (0.05) and 29.588 (0.001), 100 dof 124.342 (0.05) and 149.449 (0.001).
TEST(PostfitScreening, ChiSquareQuantileMatchesTablesWithinOnePercent) {
  EXPECT_NEAR(chiSquareUpperQuantile(10, 0.05), 18.307, 0.01 * 18.307);
  EXPECT_NEAR(chiSquareUpperQuantile(10, 0.001), 29.588, 0.01 * 29.588);
  EXPECT_NEAR(chiSquareUpperQuantile(100, 0.05), 124.342, 0.01 * 124.342);
  EXPECT_NEAR(chiSquareUpperQuantile(100, 0.001), 149.449, 0.01 * 149.449);
  EXPECT_GT(chiSquareUpperQuantile(20, 1e-6), chiSquareUpperQuantile(20, 1e-3));  // rarer: larger
  EXPECT_EQ(chiSquareUpperQuantile(0, 0.05), 0.0);
}

TEST(PostfitScreening, QuantilesOfOneFalseAlarmProbabilityAreChiSquareUpperQuantileBitForBit) {
  // ChiSquareUpperQuantile computes the normal quantile once; every threshold must
  // be the one chiSquareUpperQuantile computes on its own (EXPECT_EQ: bit for bit).
  for (const double alpha : {0.05, 1e-3, 1e-6, 1e-9}) {
    const ChiSquareUpperQuantile quantile(alpha);
    EXPECT_EQ(quantile.alpha(), alpha);
    for (int dof = -1; dof <= 300; ++dof) EXPECT_EQ(quantile(dof), chiSquareUpperQuantile(dof, alpha)) << dof;
  }
  const std::vector<PostfitResidualPair> pairs{{0.3, 0.004, 0.3, 0.003}, {-0.6, -0.002, 0.3, 0.003}};
  const ConsistencyTest a = postfitConsistency(pairs, 1e-6);
  const ConsistencyTest b = postfitConsistency(pairs, ChiSquareUpperQuantile(1e-6));
  EXPECT_EQ(a.statistic, b.statistic);
  EXPECT_EQ(a.dof, b.dof);
  EXPECT_EQ(a.threshold, b.threshold);
}

TEST(PostfitScreening, ConsistencyTestSumsNormalisedSquaresOverCodeAndPhase) {
  std::vector<PostfitResidualPair> pairs(5, {0.5, 0.005, 1.0, 0.01});  // each 0.25 + 0.25
  const ConsistencyTest ok = postfitConsistency(pairs, 1e-6);
  EXPECT_EQ(ok.dof, 10);
  EXPECT_DOUBLE_EQ(ok.statistic, 2.5);
  EXPECT_TRUE(ok.consistent());
  EXPECT_DOUBLE_EQ(ok.threshold, chiSquareUpperQuantile(10, 1e-6));

  for (auto& p : pairs) p.phase_m = 0.04;  // 4 sigma on every phase: 5 x 16.25 = 81.25
  const ConsistencyTest bad = postfitConsistency(pairs, 1e-6);
  EXPECT_DOUBLE_EQ(bad.statistic, 81.25);
  EXPECT_FALSE(bad.consistent());
  EXPECT_DOUBLE_EQ(bad.varianceFactor(), 8.125);
  EXPECT_NE(bad.describe(1e-6).find("postfit chi-square 81."), std::string::npos) << bad.describe(1e-6);
  EXPECT_NE(bad.describe(1e-6).find("(10 measurements"), std::string::npos) << bad.describe(1e-6);
}

}  // namespace
}  // namespace ppp
