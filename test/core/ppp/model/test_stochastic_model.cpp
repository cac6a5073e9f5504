// StochasticModel: the defaults (the method's table, except the
// position a priori sigma, 30 m instead of 1 m, and the ZWD random walk, 1e-4
// instead of 3e-5 m/sqrt(s)), the method's table itself
// (methodTableStochasticModel: position 1 m / 5 m/sqrt(s) random walk; ZWD
// 0.3 m / 3e-5 m/sqrt(s) random walk; clock 3e6 m / 2000 m/sqrt(s) white; phase
// bias 100 m / 0) and the conversion of process noise to per-epoch variances over dt
// and, for the wet delay's height-driven term, over the height change.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/ppp/model/stochastic_model.h"

using ppp::ProcessKind;
using ppp::StochasticModel;

TEST(StochasticModel, DefaultsAreTheMethodTable) {
  const StochasticModel table = ppp::methodTableStochasticModel();
  EXPECT_EQ(table.position.initial_sigma_m, 1.0);  // the method's table
  // The defaults: position a priori 30 m (uninformative start, see stochastic_model.h).
  EXPECT_EQ(StochasticModel{}.position.initial_sigma_m, 30.0);
  // ... and the wet delay's random walk 1e-4 m/sqrt(s) (RTKLIB's; the table's 3e-5).
  EXPECT_EQ(table.zwd.process_noise_m_per_sqrt_s, 3.0e-5);
  EXPECT_EQ(StochasticModel{}.zwd.process_noise_m_per_sqrt_s, 1.0e-4);
  for (const StochasticModel& m : {table, StochasticModel{}}) {
    EXPECT_EQ(m.position.process_noise_m_per_sqrt_s, 5.0);
    EXPECT_EQ(m.position.kind, ProcessKind::RandomWalk);
    EXPECT_EQ(m.zwd.initial_sigma_m, 0.3);
    EXPECT_EQ(m.zwd.kind, ProcessKind::RandomWalk);
    EXPECT_EQ(m.initial_zwd_m, 0.1);
    EXPECT_EQ(m.clock.initial_sigma_m, 3.0e6);
    EXPECT_EQ(m.clock.process_noise_m_per_sqrt_s, 2000.0);
    EXPECT_EQ(m.clock.kind, ProcessKind::White);
    EXPECT_EQ(m.phase_bias.initial_sigma_m, 100.0);
    EXPECT_EQ(m.phase_bias.process_noise_m_per_sqrt_s, 0.0);
    EXPECT_TRUE(m.validate().empty());
  }
}

TEST(StochasticModel, RandomWalkVarianceGrowsLinearlyWithDt) {
  const StochasticModel m;
  EXPECT_DOUBLE_EQ(m.position.processVariance_m2(30.0), 25.0 * 30.0);   // q^2 dt = 750 m^2
  EXPECT_DOUBLE_EQ(m.position.processVariance_m2(600.0), 25.0 * 600.0);  // a 10-minute gap
  EXPECT_DOUBLE_EQ(m.zwd.processVariance_m2(3600.0), 1.0e-8 * 3600.0);  // (1e-4 m/sqrt(s))^2 x 1 h
  EXPECT_EQ(m.phase_bias.processVariance_m2(1e5), 0.0);  // constant per arc
  EXPECT_EQ(m.position.processVariance_m2(-5.0), 0.0);   // negative dt treated as 0
}

TEST(StochasticModel, HeightDrivenWetDelayVarianceIsQh2TimesTheHeightChange) {
  StochasticModel m;
  EXPECT_EQ(m.zwd_per_sqrt_height_m_per_sqrt_m, 3.2e-3);  // the default (stochastic_model.h)
  m.zwd_per_sqrt_height_m_per_sqrt_m = 0.0;                // off
  EXPECT_EQ(m.zwdHeightVariance_m2(900.0), 0.0);
  // q_h = 3.2e-3 m/sqrt(m): a change of 1e-4 m/m over a 1000-m climb, (0.1 m)^2 = 1e-2 m^2, is
  // about one sigma (q_h^2 x 1000 m = 1.02e-2 m^2).
  m.zwd_per_sqrt_height_m_per_sqrt_m = 3.2e-3;
  EXPECT_DOUBLE_EQ(m.zwdHeightVariance_m2(1000.0), 3.2e-3 * 3.2e-3 * 1000.0);
  EXPECT_DOUBLE_EQ(m.zwdHeightVariance_m2(-3.0), 3.2e-3 * 3.2e-3 * 3.0);  // a descent as a climb
  EXPECT_EQ(m.zwdHeightVariance_m2(0.0), 0.0);
  EXPECT_EQ(m.zwdHeightVariance_m2(std::nan("")), 0.0);
  // Linear in |dh|: 300 epochs of 3 m add what one epoch of 900 m adds (the epoch rate does not matter).
  EXPECT_NEAR(300.0 * m.zwdHeightVariance_m2(3.0), m.zwdHeightVariance_m2(900.0), 1e-15);
  EXPECT_TRUE(m.validate().empty());
  m.zwd_per_sqrt_height_m_per_sqrt_m = -1e-3;
  EXPECT_NE(m.validate().find("process_noise_m_per_sqrt_m_of_height"), std::string::npos);
}

TEST(StochasticModel, HeightChangeBeyondNoiseIsItsPartBeyondKSigmas) {
  StochasticModel m;
  EXPECT_EQ(m.zwd_height_change_threshold_sigmas, 3.0);  // the default
  // A 10-s climb at 3 m/s (30 m) between heights of 0.5 m sigma each: sigma of the
  // difference 0.71 m, 2.1 m of noise allowed, 27.9 m counted.
  EXPECT_DOUBLE_EQ(m.zwdHeightChangeBeyondNoise_m(30.0, std::sqrt(0.5)), 30.0 - 3.0 * std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(m.zwdHeightChangeBeyondNoise_m(-30.0, std::sqrt(0.5)), 30.0 - 3.0 * std::sqrt(0.5));
  EXPECT_EQ(m.zwdHeightChangeBeyondNoise_m(2.0, std::sqrt(0.5)), 0.0);   // within 3 sigmas: noise
  EXPECT_EQ(m.zwdHeightChangeBeyondNoise_m(-2.0, std::sqrt(0.5)), 0.0);
  EXPECT_EQ(m.zwdHeightChangeBeyondNoise_m(std::nan(""), 0.1), 0.0);
  EXPECT_EQ(m.zwdHeightChangeBeyondNoise_m(1.0, std::nan("")), 0.0);
  m.zwd_height_change_threshold_sigmas = 0.0;  // every change counts
  EXPECT_EQ(m.zwdHeightChangeBeyondNoise_m(-2.0, std::sqrt(0.5)), 2.0);
  EXPECT_TRUE(m.validate().empty());
  m.zwd_height_change_threshold_sigmas = -1.0;
  EXPECT_NE(m.validate().find("height_change_threshold_sigmas"), std::string::npos);
}

TEST(StochasticModel, WhiteClockVarianceIsQ2DtCappedByTheAPrioriVariance) {
  const StochasticModel m;
  EXPECT_DOUBLE_EQ(m.clock.processVariance_m2(30.0), 2000.0 * 2000.0 * 30.0);  // 1.2e8 m^2, sigma 11 km
  EXPECT_DOUBLE_EQ(m.clock.processVariance_m2(1.0), 4.0e6);
  // 9e12 m^2 / 4e6 m^2/s = 2.25e6 s: longer gaps are capped at (3e6 m)^2.
  EXPECT_DOUBLE_EQ(m.clock.processVariance_m2(1.0e7), 9.0e12);
}

TEST(StochasticModel, ValidateNamesTheBadEntry) {
  StochasticModel m;
  m.zwd.initial_sigma_m = -0.3;
  EXPECT_NE(m.validate().find("zwd.initial_sigma_m"), std::string::npos);
  m = StochasticModel{};
  m.position.process_noise_m_per_sqrt_s = -1.0;
  EXPECT_NE(m.validate().find("position.process_noise_m_per_sqrt_s"), std::string::npos);
  m = StochasticModel{};
  m.clock.process_noise_m_per_sqrt_s = 0.0;  // white with no noise is meaningless
  EXPECT_NE(m.validate().find("clock"), std::string::npos);
}
