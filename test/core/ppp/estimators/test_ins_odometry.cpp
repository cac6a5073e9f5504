// ppp::InsOdometry (ins_odometry.h): the GNSS/INS filter's state carried at the IMU
// rate between epochs moves as the mechanization does, its covariance grows, a
// restart runs through the readings already received, and a gap stops it.
#include <gtest/gtest.h>

#include <deque>

#include "ins_odometry_states.h"
#include "ppp_bayes_tree/navigation/ins_mechanization.h"
#include "ppp_bayes_tree/ppp/estimators/ins_odometry.h"

namespace ppp {
namespace {

const GnssTime kT0 = GnssTime::fromGpsWeek(2418, 259200.0);  // 2026-05-13 00:00 GPST

TEST(InsOdometry, PropagatesLikeTheMechanizationRestartsThroughLaterReadingsAndStopsAtAGap) {
  InsEkfOptions options;
  InsOdometry odo(options);
  const InsState start = test::movingState(kT0);
  const ImuSample held = test::steadyReading(start, kT0);
  std::deque<ImuSample> later;
  for (int k = 1; k <= 10; ++k) later.push_back(test::steadyReading(start, kT0 + 0.01 * k));
  odo.restart(start, held, later);
  ASSERT_TRUE(odo.current().has_value());
  EXPECT_EQ(odo.current()->time - (kT0 + 0.1), 0.0);
  // The same ten steps of the mechanization by hand.
  NavState by_hand = start.nav;
  for (int k = 0; k < 10; ++k) by_hand = ecefInsStep(by_hand, held.specific_force_mps2, held.angular_rate_radps, 0.01);
  EXPECT_LT((odo.current()->nav.position_world_m - by_hand.position_world_m).norm(), 1e-9);
  EXPECT_NEAR((odo.current()->nav.position_world_m - start.nav.position_world_m).norm(), 1.0, 1e-3);  // 10 m/s, 0.1 s
  EXPECT_GT(odo.current()->covariance(6, 6), start.covariance(6, 6));  // the covariance grows
  // A reading not after the state: nothing; the next one: a state; one after a gap: the odometry stops.
  EXPECT_FALSE(odo.step(later.back()).has_value());
  EXPECT_TRUE(odo.step(test::steadyReading(start, kT0 + 0.11)).has_value());
  EXPECT_FALSE(odo.step(test::steadyReading(start, kT0 + 0.5)).has_value());
  EXPECT_FALSE(odo.current().has_value());
}

}  // namespace
}  // namespace ppp
