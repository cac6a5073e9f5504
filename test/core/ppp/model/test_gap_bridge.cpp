// Gap bridge (gap_bridge.h) on synthetic rows: a position error within the prior,
// one clock per system, 3 mm of phase noise. Arcs without a slip go on; a slip of
// cycles ends its arc; of a slip repair's candidates the true one is chosen (GPS
// L1/L2 candidates 9 L1 cycles apart, Galileo E1/E5a ones 4), also where the slip
// applied is wrong; a shift common to a system's arcs is told apart by the wide lanes'
// prior costs or ends the arcs while another arc holds that system's clock, and is
// taken with the least prior cost when none does (twins); candidates that only the
// position prior could tell apart, and an assignment whose cost does not fit the
// noise, end arcs: the arc whose share of that cost is the largest, which is the
// arc of a wide lane far from its Melbourne-Wubbena jump when the excess is there.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/gap_bridge.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kLambda1 = kSpeedOfLight_mps / 1575.42e6;  // GPS L1 = Galileo E1 (IS-GPS-200, Galileo OS SIS ICD)

struct Scene {
  std::vector<GapBridgeRow> rows;
  Eigen::Matrix3d prior = Eigen::Matrix3d::Identity();  // 1 m per axis
};

/// n_gps + n_gal rows: unit lines of sight above 15 degrees, a position error of
/// (0.6, -0.4, 0.5) m, clocks 0.3 and -1.2 m, 3 mm noise; no slip.
Scene scene(int n_gps, int n_gal, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> azimuth(0.0, 2.0 * kPi), elevation(15.0 * kPi / 180.0, 85.0 * kPi / 180.0);
  std::normal_distribution<double> noise(0.0, 0.003);
  const Eigen::Vector3d dp(0.6, -0.4, 0.5);
  const double clock_m[2] = {0.3, -1.2};
  Scene s;
  for (int i = 0; i < n_gps + n_gal; ++i) {
    const double az = azimuth(rng), el = elevation(rng);
    GapBridgeRow r;
    r.position_jacobian = -Eigen::RowVector3d(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
    r.clock = i < n_gps ? 0 : 1;
    r.residual_m = r.position_jacobian.dot(dp) + clock_m[r.clock] + noise(rng);
    r.sigma_m = 0.003;
    r.wavelength_m = kLambda1;
    s.rows.push_back(r);
  }
  return s;
}

/// The row's repair applied `applied_off` L1 cycles off the truth; its candidates are
/// the slips `steps` L1 cycles from the applied one (one of them -applied_off when the
/// truth is among them).
void withCandidates(GapBridgeRow& r, int applied_off, const std::vector<int>& steps) {
  r.residual_m += applied_off * kLambda1;
  for (const int step : steps) r.candidate_offsets_m.push_back(step * kLambda1);
}

TEST(GapBridge, ArcsWithoutASlipGoOnAndASlipEndsItsArc) {
  Scene s = scene(7, 5);
  s.rows[2].residual_m += 2.0 * kLambda1;
  const std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior);
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(v[i].keep, i != 2) << i << " " << v[i].reason;
    EXPECT_EQ(v[i].candidate, -1);
  }
  // The postfit residual: part of the slip goes into the position and clock.
  EXPECT_GT(v[2].slip_cycles, 1.0) << v[2].reason;
}

TEST(GapBridge, TheTrueCandidateIsChosen) {
  Scene s = scene(7, 5);
  withCandidates(s.rows[0], 0, {9});        // GPS, applied right
  withCandidates(s.rows[1], 9, {-9, 9});    // GPS, applied 9 cycles off: candidate 0
  withCandidates(s.rows[3], -9, {9});       // GPS: candidate 0
  withCandidates(s.rows[7], 4, {-4, 4});    // Galileo, applied 4 off: candidate 0
  withCandidates(s.rows[8], 0, {4, -4});    // Galileo, applied right
  withCandidates(s.rows[9], -4, {-4, 4});   // Galileo: candidate 1
  const std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior);
  const std::vector<int> expected = {-1, 0, -1, 0, -1, -1, -1, 0, -1, 1, -1, -1};
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
    EXPECT_EQ(v[i].candidate, expected[i]) << i;
    EXPECT_LT(std::abs(v[i].slip_cycles), 0.1) << i;
  }
}

// Every Galileo arc's repair off by the same 4 cycles (one wide-lane cycle): the
// Galileo clock takes the shift, so only the wide lanes' prior costs tell it apart.
// Without them the arcs end (an arc starting later would not share the shift); with
// them (the Melbourne-Wubbena jump 0.2 cycles from the truth, sigma 0.3: the shift
// costs 5 x (0.8^2 - 0.2^2) / 0.3^2 = 33 more) the true candidate is chosen for each.
TEST(GapBridge, AShiftCommonToASystemIsToldApartByTheWideLanesAlone) {
  Scene s = scene(7, 5);
  for (int i = 7; i < 12; ++i) withCandidates(s.rows[static_cast<std::size_t>(i)], 4, {-4});
  std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior);
  for (std::size_t i = 0; i < 7; ++i) EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
  for (std::size_t i = 7; i < 12; ++i) {
    EXPECT_FALSE(v[i].keep) << i;
    EXPECT_NE(v[i].reason.find("not told apart"), std::string::npos) << v[i].reason;
  }
  for (int i = 7; i < 12; ++i) {
    GapBridgeRow& r = s.rows[static_cast<std::size_t>(i)];
    r.applied_prior_cost = std::pow((1.0 - 0.2) / 0.3, 2);  // the applied wide lane 1 cycle off, the MW 0.2
    r.candidate_prior_costs = {std::pow(0.2 / 0.3, 2)};
  }
  v = bridgeGap(s.rows, s.prior);
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
    EXPECT_EQ(v[i].candidate, i < 7 ? -1 : 0) << i;
  }
}

// Every Galileo arc's repair has a candidate one wide-lane cycle away (4 L1 cycles,
// the E1/E5a candidates' spacing), with equal prior costs: the two assignments are
// twins. With no arc outside the bridge on the Galileo clock (clock_free), the
// integer differences between the arcs are the same with either, so the arcs go on
// with the applied slips (the first of equal costs) and the shift reported undecided
// until the prior costs tell the twins apart; with one row shifted differently the
// assignment is no twin and the arcs concerned end.
TEST(GapBridge, TwinsOnAFreeClockKeepTheirArcs) {
  Scene s = scene(7, 5);
  for (int i = 7; i < 12; ++i) {
    GapBridgeRow& r = s.rows[static_cast<std::size_t>(i)];
    withCandidates(r, 0, {4});
    r.candidate_wide_lane_offsets_cycles = {1};
    r.clock_free = true;
  }
  std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior);
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
    EXPECT_EQ(v[i].candidate, -1) << i;
    EXPECT_EQ(v[i].common_shift_undecided, i >= 7) << i;  // only the Galileo rows' shift
  }
  // The wide lanes' prior prefers the candidate: it is taken on every row.
  for (int i = 7; i < 12; ++i) {
    GapBridgeRow& r = s.rows[static_cast<std::size_t>(i)];
    r.applied_prior_cost = 1.0;
    r.candidate_prior_costs = {0.5};
  }
  v = bridgeGap(s.rows, s.prior);
  for (std::size_t i = 7; i < v.size(); ++i) {
    EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
    EXPECT_EQ(v[i].candidate, 0) << i;
    EXPECT_TRUE(v[i].common_shift_undecided) << i;  // 2.5 of prior cost apart, not 25
  }
  // Prior costs 50 apart (the MW jumps clear): decided.
  for (int i = 7; i < 12; ++i) s.rows[static_cast<std::size_t>(i)].applied_prior_cost = 10.5;
  v = bridgeGap(s.rows, s.prior);
  for (std::size_t i = 7; i < v.size(); ++i) {
    EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
    EXPECT_EQ(v[i].candidate, 0) << i;
    EXPECT_FALSE(v[i].common_shift_undecided) << i;
  }
  for (int i = 7; i < 12; ++i) s.rows[static_cast<std::size_t>(i)].applied_prior_cost = 1.0;
  // Row 11's candidate has another wide lane: the L1 shift alone is common, no twin.
  s.rows[11].candidate_wide_lane_offsets_cycles = {2};
  v = bridgeGap(s.rows, s.prior);
  for (std::size_t i = 0; i < 7; ++i) EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
  for (std::size_t i = 7; i < 12; ++i) {
    EXPECT_FALSE(v[i].keep) << i;
    EXPECT_NE(v[i].reason.find("not told apart"), std::string::npos) << v[i].reason;
  }
}

// Row 0 alone sees the height (the others horizontal) and the prior is 10 m: each of
// its candidates fits by moving the height, so they are not told apart and it ends;
// the others go on.
TEST(GapBridge, CandidatesOnlyThePriorCouldTellApartEndTheirArc) {
  Scene s = scene(8, 0);
  for (std::size_t i = 1; i < s.rows.size(); ++i) {
    s.rows[i].position_jacobian.z() = 0.0;
    s.rows[i].residual_m = s.rows[i].position_jacobian.dot(Eigen::Vector3d(0.6, -0.4, 0.5)) + 0.3;
  }
  withCandidates(s.rows[0], 0, {9, -9});
  GapBridgeOptions o;
  o.min_position_sigma_m = 10.0;
  const std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior, o);
  EXPECT_FALSE(v[0].keep);
  EXPECT_NE(v[0].reason.find("not told apart"), std::string::npos) << v[0].reason;
  for (std::size_t i = 1; i < v.size(); ++i) EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
}

// A half-cycle error on a row without candidates (within the 0.2-cycle slip bound
// only once the position bends to it) and candidates elsewhere: the best assignment's
// cost does not fit 3 mm of noise, the row ends, the candidates are chosen right.
TEST(GapBridge, AnAssignmentThatDoesNotFitTheNoiseEndsItsWorstArc) {
  Scene s = scene(7, 5, 3);
  s.rows[4].residual_m += 0.15 * kLambda1;
  withCandidates(s.rows[1], 9, {-9});
  withCandidates(s.rows[8], -4, {4, -4});
  const std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior);
  EXPECT_FALSE(v[4].keep);
  EXPECT_NE(v[4].reason.find("does not fit"), std::string::npos) << v[4].reason;
  EXPECT_TRUE(v[1].keep) << v[1].reason;
  EXPECT_EQ(v[1].candidate, 0);
  EXPECT_TRUE(v[8].keep) << v[8].reason;
  EXPECT_EQ(v[8].candidate, 0);
}

// Row 9's Melbourne-Wubbena jump is far from both of its wide lanes (prior costs 30
// and 36: an outlier), so the best assignment's cost fails its chi-square bound
// (about 47 against 31.3 for 11 degrees of freedom) although every phase fits; row 2
// has the largest phase residual (2.5 sigmas, within the noise). Row 9 ends: without
// it the cost fits; row 2 and the rest go on.
TEST(GapBridge, ACostFailingInAWideLanesPriorEndsThatArc) {
  Scene s = scene(7, 5, 3);
  s.rows[2].residual_m += 2.5 * s.rows[2].sigma_m;
  GapBridgeRow& r = s.rows[9];
  withCandidates(r, 0, {4});
  r.candidate_wide_lane_offsets_cycles = {1};
  r.applied_prior_cost = 30.0;
  r.candidate_prior_costs = {36.0};
  const std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior);
  EXPECT_FALSE(v[9].keep);
  EXPECT_NE(v[9].reason.find("does not fit"), std::string::npos) << v[9].reason;
  EXPECT_NE(v[9].reason.find("without this arc it costs"), std::string::npos) << v[9].reason;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (i != 9) EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
  // Ranking without each of the 12 rows (2 assignments each) exceeds a bound of 20
  // assignments: the row with the most candidates ends instead, here the same row.
  GapBridgeOptions o;
  o.max_candidate_assignments = 20.0;
  const std::vector<GapBridgeVerdict> bounded = bridgeGap(s.rows, s.prior, o);
  EXPECT_FALSE(bounded[9].keep);
  EXPECT_NE(bounded[9].reason.find("too many assignments to rank"), std::string::npos) << bounded[9].reason;
  for (std::size_t i = 0; i < bounded.size(); ++i)
    if (i != 9) EXPECT_TRUE(bounded[i].keep) << i << " " << bounded[i].reason;
}

// A Galileo arc whose repair was unique but one wide lane off (4 L1 cycles, 0.76 m:
// no candidates, as when the neighbour nearer its MW jump just failed the
// geometry-free test), beside four Galileo arcs whose candidates include the same
// shift (prior costs 0.5 applied, 12 shifted) on a free clock. The phases fit only
// if those four shift with it (the clock takes the common part), at 48 of wide-lane
// cost: the best assignment does not fit. Ending the row of the largest phase
// residual or of the largest wide-lane cost ends right arcs one by one, until the
// wrong arc is kept alone on its clock. Ranking without each row finds it: without
// it the four fit unshifted.
TEST(GapBridge, ACostFailingBecauseOfAWrongUniqueRepairEndsThatArc) {
  Scene s = scene(7, 5, 5);
  s.rows[7].residual_m += 4.0 * kLambda1;
  s.rows[7].clock_free = true;
  for (int i = 8; i < 12; ++i) {
    GapBridgeRow& r = s.rows[static_cast<std::size_t>(i)];
    withCandidates(r, 0, {4});
    r.candidate_wide_lane_offsets_cycles = {1};
    r.applied_prior_cost = 0.5;
    r.candidate_prior_costs = {12.0};
    r.clock_free = true;
  }
  const std::vector<GapBridgeVerdict> v = bridgeGap(s.rows, s.prior);
  EXPECT_FALSE(v[7].keep);
  EXPECT_NE(v[7].reason.find("without this arc it costs"), std::string::npos) << v[7].reason;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i == 7) continue;
    EXPECT_TRUE(v[i].keep) << i << " " << v[i].reason;
    EXPECT_EQ(v[i].candidate, -1) << i;
    EXPECT_FALSE(v[i].common_shift_undecided) << i;
  }
}

}  // namespace
}  // namespace ppp
