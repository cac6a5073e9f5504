// The IMU grade names of the configuration keys and command lines (imu_noise.h).
#include <gtest/gtest.h>

#include "ppp_bayes_tree/navigation/imu_noise.h"

namespace ppp {
namespace {

TEST(ImuGradeFromName, TakesTheKeysAndTheShortForms) {
  EXPECT_EQ(imuGradeFromName("consumer_mems"), ImuGrade::ConsumerMems);
  EXPECT_EQ(imuGradeFromName("consumer"), ImuGrade::ConsumerMems);
  EXPECT_EQ(imuGradeFromName("industrial_mems"), ImuGrade::IndustrialMems);
  EXPECT_EQ(imuGradeFromName("industrial"), ImuGrade::IndustrialMems);
  EXPECT_EQ(imuGradeFromName("tactical"), ImuGrade::Tactical);
}

TEST(ImuGradeFromName, RefusesAnyOtherName) {
  for (const char* name : {"", "Tactical", "navigation", "consumer mems", "industrial_mems "})
    EXPECT_FALSE(imuGradeFromName(name).has_value()) << '"' << name << '"';
}

}  // namespace
}  // namespace ppp
