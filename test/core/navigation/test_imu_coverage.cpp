// The IMU coverage rule (imu_coverage.h): a reading at or before the start, no hold
// longer than the allowed gap (a hold begun before the start counts whole, the
// last reading holds to the end), readings after the end ignored; the texts.
#include <gtest/gtest.h>

#include <initializer_list>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_coverage.h"

namespace ppp {
namespace {

const GnssTime kStart = GnssTime::fromGpsWeek(2111, 345600.0);

/// Readings at kStart + each offset [s].
std::vector<ImuSample> readingsAt(std::initializer_list<double> offsets_s) {
  std::vector<ImuSample> out;
  for (double dt : offsets_s) {
    ImuSample s;
    s.time = kStart + dt;
    out.push_back(s);
  }
  return out;
}

TEST(ImuCoverage, RegularReadingsCoverTheIntervalWithOneAtTheStart) {
  const ImuCoverage c = imuCoverage(readingsAt({0.0, 0.05, 0.1, 0.15, 0.2}), kStart, kStart + 0.2, 0.1);
  EXPECT_TRUE(c.covered());
  EXPECT_EQ(c.problem, ImuCoverageProblem::None);
  EXPECT_EQ(c.text(), "");
}

TEST(ImuCoverage, NoReadingAtOrBeforeTheStartIsNotCovered) {
  const ImuCoverage c = imuCoverage(readingsAt({0.01, 0.05}), kStart, kStart + 0.05, 0.1);
  EXPECT_EQ(c.problem, ImuCoverageProblem::NoReadingAtStart);
  EXPECT_EQ(c.text(), "no reading at or before " + kStart.toString());
  EXPECT_EQ(imuCoverage({}, kStart, kStart + 1.0, 0.1).problem, ImuCoverageProblem::NoReadingAtStart);
  // Only readings after the end: none holds at the start either.
  EXPECT_EQ(imuCoverage(readingsAt({2.0}), kStart, kStart + 1.0, 0.1).problem, ImuCoverageProblem::NoReadingAtStart);
}

TEST(ImuCoverage, AGapBetweenReadingsInsideTheIntervalIsNamedWithItsReading) {
  const ImuCoverage c = imuCoverage(readingsAt({0.0, 0.1, 0.35, 0.4}), kStart, kStart + 0.4, 0.1);
  EXPECT_EQ(c.problem, ImuCoverageProblem::Gap);
  ASSERT_TRUE(c.held_time.has_value());
  EXPECT_NEAR(*c.held_time - kStart, 0.1, 1e-9);
  EXPECT_NEAR(c.gap_s, 0.25, 1e-9);
  EXPECT_FALSE(c.held_to_end);  // a later reading ends it
  EXPECT_EQ(c.text(), "gap of 0.250000 s after the reading at " + (kStart + 0.1).toString() + " (at most 0.100000 s)");
}

TEST(ImuCoverage, TheLastReadingHoldsToTheEnd) {
  EXPECT_EQ(imuCoverage(readingsAt({0.0, 0.1}), kStart, kStart + 0.5, 0.1).problem, ImuCoverageProblem::Gap);
  const ImuCoverage c = imuCoverage(readingsAt({0.0, 0.1}), kStart, kStart + 0.5, 0.1);
  EXPECT_NEAR(c.gap_s, 0.4, 1e-9);
  EXPECT_TRUE(c.held_to_end);  // a reading still to come could close it
  EXPECT_TRUE(imuCoverage(readingsAt({0.0, 0.1}), kStart, kStart + 0.2, 0.1).covered());
}

TEST(ImuCoverage, AHoldExactlyAsLongAsAllowedCoversAndOneJustLongerDoesNot) {
  EXPECT_TRUE(imuCoverage(readingsAt({0.0, 0.125, 0.25}), kStart, kStart + 0.25, 0.125).covered());
  EXPECT_EQ(imuCoverage(readingsAt({0.0, 0.25}), kStart, kStart + 0.25, 0.124).problem, ImuCoverageProblem::Gap);
}

TEST(ImuCoverage, AHoldBegunBeforeTheStartCountsWhole) {
  // The reading at -0.08 holds to 0.05: 0.13 s, though only 0.05 s of it is in the interval.
  const ImuCoverage c = imuCoverage(readingsAt({-0.2, -0.08, 0.05, 0.1}), kStart, kStart + 0.1, 0.1);
  EXPECT_EQ(c.problem, ImuCoverageProblem::Gap);
  EXPECT_NEAR(*c.held_time - kStart, -0.08, 1e-9);
  // The latest reading at or before the start is the one held: the older ones do not count.
  EXPECT_TRUE(imuCoverage(readingsAt({-5.0, -0.02, 0.05, 0.1}), kStart, kStart + 0.1, 0.1).covered());
}

TEST(ImuCoverage, AReadingAtTheStartOrAtTheEndIsOnTheBoundaryAndLaterOnesAreIgnored) {
  // At the start: held there; at the end: the last hold ends there; after the end: no matter how far.
  EXPECT_TRUE(imuCoverage(readingsAt({0.0, 0.1, 5.0}), kStart, kStart + 0.1, 0.1).covered());
  EXPECT_TRUE(imuCoverage(readingsAt({0.0, 0.1}), kStart + 0.1, kStart + 0.2, 0.1).covered());
}

TEST(ImuCoverage, ProblemsHaveText) {
  EXPECT_EQ(imuCoverageProblemText(ImuCoverageProblem::None), "covered");
  EXPECT_EQ(imuCoverageProblemText(ImuCoverageProblem::NoReadingAtStart), "no reading at or before the start");
  EXPECT_EQ(imuCoverageProblemText(ImuCoverageProblem::Gap), "gap");
}

}  // namespace
}  // namespace ppp
