// The GNSS/INS estimators' gap bridge (ins_gap_bridge.h) on synthetic measurements:
// 7 GPS and 5 Galileo arcs back after a gap, every Galileo arc repaired with a
// candidate one wide-lane cycle away (4 E1 and 3 E5a cycles, the E1/E5a spacing)
// whose Melbourne-Wubbena cost equals the applied slip's. With no other Galileo arc
// holding a bias, the two are twins on a free clock: the arcs go on, their shift
// reported undecided and their wide-lane means started again (the line says so).
// With one more Galileo arc that went on without a gap (its bias held), the Galileo
// clock is not free: the same candidates are not told apart and the Galileo arcs end
// (the GPS arcs, enough to test alone, go on).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/estimators/ins_gap_bridge.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kLambda1 = kSpeedOfLight_mps / 1575.42e6;  // GPS L1 = Galileo E1 (IS-GPS-200, Galileo OS SIS ICD)

struct Scene {
  std::vector<BridgedArc> bridged;
  std::vector<SatelliteMeasurement> usable;
  std::map<ArcId, double> bias_m;
};

/// Arc `arc` of `sat` seen along a random line of sight above 15 degrees: its phase
/// residual is the position error's projection, its system's clock and its bias.
SatelliteMeasurement measurement(const SatelliteId& sat, ArcId arc, double bias_m, std::mt19937& rng) {
  std::uniform_real_distribution<double> azimuth(0.0, 2.0 * kPi), elevation(15.0 * kPi / 180.0, 85.0 * kPi / 180.0);
  const double az = azimuth(rng), el = elevation(rng);
  const Eigen::Vector3d dp(0.6, -0.4, 0.5);
  const double clock_m = sat.system == GnssSystem::GPS ? 0.3 : -1.2;
  SatelliteMeasurement m;
  m.satellite = sat;
  m.arc = arc;
  m.jacobian = Eigen::RowVectorXd::Zero(5);
  m.jacobian.head<3>() = -Eigen::Vector3d(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
  m.observed_phase_m = m.jacobian.head<3>().dot(dp) + clock_m + bias_m;
  m.phase_sigma_m = 0.003;
  return m;
}

Scene scene() {
  std::mt19937 rng(5);
  Scene s;
  for (int i = 0; i < 12; ++i) {
    const bool gps = i < 7;
    BridgedArc b;
    b.satellite = SatelliteId{gps ? GnssSystem::GPS : GnssSystem::Galileo, i + 1};
    b.arc = static_cast<ArcId>(i + 1);
    b.gap_s = 30.0;
    b.gf_jump_m = 0.0;
    b.wavelength1_m = kLambda1;
    b.geometry_free_factor = 1.0;
    if (!gps) {
      SlipRepair r;
      r.outcome = SlipRepairOutcome::Repaired;
      r.dn1_cycles = 10;
      r.dn2_cycles = 10;
      r.wide_lane_cycles = 0.5;  // halfway between the two wide lanes: equal costs
      r.wide_lane_sigma_cycles = 0.5;
      r.alternatives = {SlipCandidate{14, 13, 14.0}};
      b.repair = r;
    }
    s.bias_m[b.arc] = 0.1 * (i + 1);
    s.usable.push_back(measurement(b.satellite, b.arc, s.bias_m[b.arc], rng));
    s.bridged.push_back(b);
  }
  return s;
}

std::vector<BridgedArcVerdict> verdicts(const Scene& s) {
  const auto held = [&s](ArcId arc) -> std::optional<double> {
    const auto it = s.bias_m.find(arc);
    if (it == s.bias_m.end()) return std::nullopt;
    return it->second;
  };
  return insGapBridgeVerdicts(s.bridged, s.usable, held, 0, Eigen::Matrix3d::Identity(), GapBridgeOptions{});
}

TEST(InsGapBridgeVerdicts, TwinsOnAFreeClockGoOnWithTheirWideLanesStartedAgain) {
  const Scene s = scene();
  const std::vector<BridgedArcVerdict> v = verdicts(s);
  ASSERT_EQ(v.size(), 12u);
  for (const BridgedArcVerdict& x : v) {
    const bool galileo = x.arc->satellite.system == GnssSystem::Galileo;
    EXPECT_TRUE(x.keep) << x.text;
    EXPECT_EQ(x.common_shift_undecided, galileo) << x.text;
  }
  AmbiguityResolver resolver;
  EstimatorEpochResult result;
  applyBridgedArcVerdicts(
      v, [](const BridgedArc&, const std::string&) { ADD_FAILURE() << "no arc ends"; },
      [](const BridgedArc&, const SlipCandidate&) { return true; }, resolver, result);
  EXPECT_EQ(result.bridged_arcs_kept, 12);
  EXPECT_EQ(result.repaired_arcs_kept, 5);
  int started_again = 0;
  for (const std::string& line : result.gap_bridge)
    started_again += line.find("wide-lane mean started again") != std::string::npos ? 1 : 0;
  EXPECT_EQ(started_again, 5);
}

TEST(InsGapBridgeVerdicts, AnArcOutsideTheBridgeHoldsTheClockAndTheTwinsEnd) {
  Scene s = scene();
  std::mt19937 rng(9);
  s.bias_m[99] = 0.7;
  s.usable.push_back(measurement(SatelliteId{GnssSystem::Galileo, 30}, 99, 0.7, rng));
  const std::vector<BridgedArcVerdict> v = verdicts(s);
  ASSERT_EQ(v.size(), 12u);
  for (const BridgedArcVerdict& x : v) {
    const bool galileo = x.arc->satellite.system == GnssSystem::Galileo;
    EXPECT_EQ(x.keep, !galileo) << x.text;
    EXPECT_FALSE(x.common_shift_undecided) << x.text;
    if (galileo) EXPECT_NE(x.text.find("not told apart"), std::string::npos) << x.text;
  }
}

}  // namespace
}  // namespace ppp
