// Flight profiles, body-frame elevation, the nominal constellation, and the
// trajectory CSV reader (valid files, malformed fixtures, fuzz corpus).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "fuzz/trajectory_csv_fuzz_entry.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/simulation/flight_trajectory.h"
#include "ppp_bayes_tree/simulation/gps_constellation.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

namespace ppp {
namespace {

constexpr double kG = 9.80665;

struct ProfileFacts {
  FlightProfile profile;
  double speed_mps;    // horizontal speed of the definition (flight_trajectory.h)
  double max_bank_deg; // atan(V^2 / (R g))
};

TEST(SimulationTrajectory, ProfilesFlyAtTheirSpeedWithCoordinatedBanks) {
  const ProfileFacts facts[] = {
      {FlightProfile::Loiter, 15.0, std::atan(15.0 * 15.0 / (250.0 * kG)) * kRadToDeg},   // 5.24
      {FlightProfile::Survey, 15.0, std::atan(15.0 * 15.0 / (50.0 * kG)) * kRadToDeg},    // 24.65
      {FlightProfile::Figure8, 22.0, std::atan(22.0 * 22.0 / (90.0 * kG)) * kRadToDeg},   // 28.74
      {FlightProfile::Climb, 22.0, std::atan(22.0 * 22.0 / (110.0 * kG)) * kRadToDeg},    // 24.16
  };
  for (const auto& pf : facts) {
    TrajectoryOptions o;
    o.profile = pf.profile;
    o.start = test::gpst(2026, 5, 13, 10);
    o.duration_s = 1800.0;
    o.rate_hz = 10.0;
    const auto s = generateTrajectory(o);
    ASSERT_EQ(s.size(), 18001u);
    EXPECT_EQ(s.back().time - s.front().time, 1800.0);
    const Eigen::Vector3d origin = geodeticToEcef(defaultSimulationOrigin());
    double max_roll = 0.0;
    for (std::size_t k = 1; k + 1 < s.size(); ++k) {
      const Geodetic g = ecefToGeodetic(s[k].position_ecef_m);
      const Eigen::Vector3d v = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad) * s[k].velocity_ecef_mps;
      ASSERT_NEAR(std::hypot(v.x(), v.y()), pf.speed_mps, 0.01 * pf.speed_mps);
      // Velocity is the derivative of the positions (central difference over 0.2 s).
      const Eigen::Vector3d fd = (s[k + 1].position_ecef_m - s[k - 1].position_ecef_m) / 0.2;
      ASSERT_LT((fd - s[k].velocity_ecef_mps).norm(), 0.01 * pf.speed_mps) << flightProfileName(pf.profile) << " " << k;
      // Coordinated turn: roll = atan(V psi_dot / g), psi_dot from the yaw differences.
      const double psi_dot = std::remainder(s[k + 1].yaw_rad - s[k - 1].yaw_rad, 2.0 * kPi) / 0.2;
      ASSERT_NEAR(s[k].roll_rad, std::atan(pf.speed_mps * psi_dot / kG), 0.02) << flightProfileName(pf.profile);
      max_roll = std::max(max_roll, std::abs(s[k].roll_rad));
      ASSERT_LT((s[k].position_ecef_m - origin).norm(), 6000.0);
    }
    EXPECT_NEAR(max_roll * kRadToDeg, pf.max_bank_deg, 0.05) << flightProfileName(pf.profile);
  }
}

TEST(SimulationTrajectory, ClimbProfileClimbsCruisesAndDescends) {
  TrajectoryOptions o;
  o.profile = FlightProfile::Climb;
  o.duration_s = 3600.0;
  o.rate_hz = 10.0;
  const auto s = generateTrajectory(o);
  ASSERT_EQ(s.size(), 36001u);
  auto height = [&](std::size_t k) { return ecefToGeodetic(s[k].position_ecef_m).height_m - 950.0; };
  EXPECT_NEAR(height(0), 100.0, 0.5);
  EXPECT_NEAR(height(18000), 1000.0, 5.0);  // cruise at 100 + 3 m/s * 300 s (tangent plane ~1 m)
  EXPECT_NEAR(height(36000), 100.0, 5.0);
  EXPECT_NEAR(s[1000].pitch_rad, std::atan2(3.0, 22.0), 1e-3);  // climbing flight-path angle 7.8 deg
}

TEST(SimulationTrajectory, BodyElevationOfABankedAircraft) {
  TrajectorySample s;
  s.position_ecef_m = geodeticToEcef(defaultSimulationOrigin());
  const Geodetic g = defaultSimulationOrigin();
  const Eigen::Matrix3d ecef_from_enu = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).transpose();
  const double el = 20.0 * kDegToRad;
  const Eigen::Vector3d east_los = ecef_from_enu * Eigen::Vector3d(std::cos(el), 0.0, std::sin(el));
  const Eigen::Vector3d west_los = ecef_from_enu * Eigen::Vector3d(-std::cos(el), 0.0, std::sin(el));
  EXPECT_NEAR(bodyElevation_rad(s, east_los), el, 1e-12);  // level: body = local elevation
  s.yaw_rad = 0.0;                                          // heading north: the right wing points east
  s.roll_rad = 30.0 * kDegToRad;                            // right wing down
  // Banked right, the canopy faces the inside of the turn: the satellite on the
  // right (east) rises by the bank, the one on the left (outside) sinks.
  EXPECT_NEAR(bodyElevation_rad(s, east_los) * kRadToDeg, 50.0, 1e-9);
  EXPECT_NEAR(bodyElevation_rad(s, west_los) * kRadToDeg, -10.0, 1e-9);
  s.roll_rad = 0.0;
  s.pitch_rad = 10.0 * kDegToRad;  // nose up: a satellite ahead (north) sinks in the body frame
  const Eigen::Vector3d north_los = ecef_from_enu * Eigen::Vector3d(0.0, std::cos(el), std::sin(el));
  EXPECT_NEAR(bodyElevation_rad(s, north_los) * kRadToDeg, 10.0, 1e-9);
}

TEST(SimulationTrajectory, WalkerConstellationGeometry) {
  WalkerConstellationOptions o;
  o.satellites = 31;
  o.reference_time = test::gpst(2026, 5, 13);
  const WalkerConstellation w(o);
  ASSERT_EQ(w.satellites().size(), 31u);
  const double mean_motion = std::sqrt(kGmGps_m3ps2 / std::pow(26559.7e3, 3));
  const double period = 2.0 * kPi / mean_motion;
  EXPECT_NEAR(period, 43082.0, 6.0);  // half a sidereal day, 11 h 58 min (IS-GPS-200 nominal)
  double max_z = 0.0;
  for (std::size_t i = 0; i < 31; ++i) {
    for (double dt : {0.0, 3000.0, 10000.0, 20000.0}) {
      Eigen::Vector3d p, v, p2, v2, p0, v0;
      const GnssTime t = o.reference_time + dt;
      w.state(i, t, p, v);
      EXPECT_NEAR(p.norm(), 26559.7e3, 1e-3);
      max_z = std::max(max_z, std::abs(p.z()));
      // ECEF velocity = derivative of the ECEF position (includes -omega x r).
      w.state(i, t + 0.5, p2, v2);
      w.state(i, t - 0.5, p0, v0);
      EXPECT_LT(((p2 - p0) - v).norm(), 1e-3);
      // Inertial speed of a circular orbit: sqrt(GM / a) = 3873.9 m/s.
      const Eigen::Vector3d v_inertial = v + Eigen::Vector3d(-kEarthRotationRate_radps * p.y(), kEarthRotationRate_radps * p.x(), 0.0);
      EXPECT_NEAR(v_inertial.norm(), std::sqrt(kGmGps_m3ps2 / 26559.7e3), 1e-6);
    }
  }
  EXPECT_LE(max_z, 26559.7e3 * std::sin(55.0 * kDegToRad) + 1.0);
  EXPECT_GT(max_z, 0.95 * 26559.7e3 * std::sin(55.0 * kDegToRad));
  // Planes: 31 satellites -> 6 planes holding 6,5,5,5,5,5.
  EXPECT_NEAR(w.satellites()[0].raan_rad, w.satellites()[6].raan_rad, 1e-12);
  EXPECT_NEAR(w.satellites()[1].raan_rad - w.satellites()[0].raan_rad, kPi / 3.0, 1e-12);
}

TEST(SimulationTrajectory, CsvWithAndWithoutAttitude) {
  const GnssTime start = test::gpst(2026, 5, 13, 10);
  const auto a = readTrajectoryCsv(test::fixturePath("simulation/trajectory_with_attitude.csv"), start);
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a[2].time, start + 2.0);
  EXPECT_NEAR(a[2].roll_rad * kRadToDeg, 5.0, 1e-12);  // as written on line 5
  EXPECT_NEAR(a[2].yaw_rad * kRadToDeg, 2.0, 1e-12);
  const Geodetic g = ecefToGeodetic(a[0].position_ecef_m);
  EXPECT_NEAR(g.latitude_rad * kRadToDeg, 46.877, 1e-9);
  EXPECT_NEAR(g.height_m, 1050.0, 1e-6);
  // Without attitude: flying north at 0.00009 deg/s of latitude (~10 m/s), level.
  auto src = memoryLineSource("time_s,latitude_deg,longitude_deg,height_m\n0,46.877,7.465,1050\n1,46.87709,7.465,1050\n"
                              "2,46.87718,7.465,1050\n",
                              "north.csv");
  const auto n = readTrajectoryCsv(*src, start);
  for (const auto& s : n) {
    EXPECT_NEAR(std::remainder(s.yaw_rad, 2.0 * kPi), 0.0, 1e-6);
    EXPECT_NEAR(s.roll_rad, 0.0, 1e-9);
    EXPECT_NEAR(s.velocity_ecef_mps.norm(), 10.0, 0.1);
  }
}

TEST(SimulationTrajectory, MalformedCsvFilesThrowNamingTheLine) {
  struct Case {
    const char* file;
    std::size_t line;
    const char* reason;
  };
  const Case cases[] = {
      {"missing_column.csv", 1, "lacks column 'longitude_deg'"},
      {"bad_number.csv", 4, "malformed latitude_deg '46.9x'"},
      {"time_not_increasing.csv", 4, "not strictly increasing"},
      {"wrong_field_count.csv", 3, "expected 4 fields, found 3"},
      {"partial_attitude.csv", 1, "roll_deg, pitch_deg, yaw_deg"},
      {"one_row.csv", 2, "fewer than two"},
      {"empty.csv", 0, "no header line"},
      {"unknown_column.csv", 1, "unknown column 'speed'"},
      {"latitude_out_of_range.csv", 2, "out of range"},
  };
  for (const auto& c : cases) {
    const std::string path = test::fixturePath(std::string("malformed/trajectory_csv/") + c.file);
    try {
      readTrajectoryCsv(path, GnssTime());
      ADD_FAILURE() << c.file << ": no error";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), c.line) << c.file << ": " << e.what();
      EXPECT_NE(e.reason().find(c.reason), std::string::npos) << c.file << ": " << e.what();
      EXPECT_NE(e.file().find(c.file), std::string::npos);
    }
  }
  EXPECT_THROW(readTrajectoryCsv("/nonexistent/trajectory.csv", GnssTime()), FileOpenError);
}

TEST(SimulationTrajectory, FuzzCorpusAndRandomBytesNeverCrash) {
  for (const auto& entry : std::filesystem::directory_iterator(std::string(PPP_FUZZ_DIR) + "/corpus/trajectory_csv")) {
    const std::string bytes = test::readFileBytes(entry.path().string());
    fuzz::fuzzTrajectoryCsv(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::uint64_t x = 12345;
  std::string bytes;
  for (int k = 0; k < 200; ++k) {
    bytes = "time_s,latitude_deg,longitude_deg,height_m\n";
    for (int i = 0; i < 200; ++i) {
      x = x * 6364136223846793005ull + 1442695040888963407ull;
      bytes += "0123456789.,-e\n#x"[(x >> 33) % 17];
    }
    fuzz::fuzzTrajectoryCsv(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  SUCCEED();
}

}  // namespace
}  // namespace ppp
