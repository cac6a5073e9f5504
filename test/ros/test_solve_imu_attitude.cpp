// ppp_solve --imu-attitude on the u-blox walk (shared data): the start attitude of
// the GNSS/INS estimators given whole (roll, pitch, heading), as the nodes'
// ros.imu.initial_attitude given. The walk's first solution comes in motion, where
// --imu-heading (levelling the readings up to the start) cannot start the filter;
// with --imu-attitude it starts there. Both together are refused.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "test_support.h"

namespace {

/// Runs ppp_solve ekf_ins on the walk with `start` (the start options); returns its exit status.
int solveWalk(const std::string& start, const std::string& dir) {
  const std::string u = ppp::test::dataPath("streams/ubx");
  const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_solve --ubx " + u + "/gnss_1730.ubx --nav " + u +
                          "/gnss_1730.ubx --atx " + ppp::test::dataPath("antex/igs20_gps_satellites_trim.atx") +
                          " --config " + PPP_REPO_DIR + "/config/live.yaml " + PPP_REPO_DIR +
                          "/test/rostest/live_ubx.yaml --estimator ekf_ins --imu " + u + "/imu_1730.csv" +
                          " --imu-format logged --imu-tag " + u + "/imu_1730.csv.tag --imu-grade consumer" +
                          " --imu-rotation 180,0,-90 --lever-arm 0,-0.05,0 " + start + " --name walk --out " + dir +
                          " > " + dir + "/log.txt 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(SolveImuAttitude, AStartInMotionNeedsTheWholeAttitude) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string dir = ppp::test::tempDir("solve_imu_attitude").string();
  // Levelling the readings up to the first solution (the walker moving): refused, nothing solved.
  solveWalk("--imu-heading -42.8", dir);
  EXPECT_NE(fileText(dir + "/log.txt").find("epochs: 536 read, 0 solved"), std::string::npos)
      << fileText(dir + "/log.txt");
  // The whole attitude (the in-motion alignment's roll and pitch at the start, its heading one second later).
  ASSERT_EQ(solveWalk("--imu-attitude -1.5,0.6,-42.8", dir), 0) << fileText(dir + "/log.txt");
  const std::string log = fileText(dir + "/log.txt");
  const auto at = log.find("epochs: 536 read, ");
  ASSERT_NE(at, std::string::npos) << log;
  EXPECT_GT(std::stoi(log.substr(at + 18)), 150) << log.substr(at, 60);  // 206 of 536 measured
  // The first attitude row: the given heading, roll and pitch (to the first epoch's update).
  std::istringstream rows(fileText(dir + "/walk_ekf_ins_attitude.csv"));
  std::string header, first;
  std::getline(rows, header);
  std::getline(rows, first);
  std::vector<std::string> f;
  std::stringstream ss(first);
  for (std::string v; std::getline(ss, v, ',');) f.push_back(v);
  ASSERT_GT(f.size(), 5u) << first;
  EXPECT_NEAR(std::stod(f[4]), -42.8, 5.0) << first;  // heading_deg
  // Two starts at once: a usage error.
  EXPECT_EQ(solveWalk("--imu-attitude 0,0,0 --imu-heading 10", dir), 2);
  EXPECT_NE(fileText(dir + "/log.txt").find("--imu-attitude and --imu-heading are two starts"), std::string::npos);
}

TEST(SolveImuAttitude, NoiseAdaptationSwitchReachesTheEstimator) {
  // --noise-adaptation off: the accelerometers' process noise is never scaled. On the walk
  // the phases find the consumer IMU's prediction inconsistent at many epochs, so the two
  // solutions differ (doc/studies/ins_walk.md, "The error after the weak geometry").
  PPP_REQUIRE_SHARED_DATA();
  const std::string on = ppp::test::tempDir("solve_noise_adaptation_on").string();
  const std::string off = ppp::test::tempDir("solve_noise_adaptation_off").string();
  ASSERT_EQ(solveWalk("--imu-attitude -1.5,0.6,-42.8", on), 0) << fileText(on + "/log.txt");
  ASSERT_EQ(solveWalk("--imu-attitude -1.5,0.6,-42.8 --noise-adaptation off", off), 0) << fileText(off + "/log.txt");
  const std::string a = fileText(on + "/walk_ekf_ins.csv"), b = fileText(off + "/walk_ekf_ins.csv");
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_NE(a, b);
  EXPECT_EQ(solveWalk("--imu-attitude -1.5,0.6,-42.8 --noise-adaptation sometimes", off), 2);
  EXPECT_NE(fileText(off + "/log.txt").find("--noise-adaptation needs on or off"), std::string::npos)
      << fileText(off + "/log.txt");
}

TEST(SolveImuAttitude, GapBridgeBoundIsParsed) {
  // --gap-bridge-max-s S: seconds in [0, 600] (InsEkfOptions::gap_bridge_max_s); else a usage error.
  PPP_REQUIRE_SHARED_DATA();
  const std::string dir = ppp::test::tempDir("solve_gap_bridge").string();
  ASSERT_EQ(solveWalk("--imu-attitude -1.5,0.6,-42.8 --gap-bridge-max-s 6", dir), 0) << fileText(dir + "/log.txt");
  EXPECT_FALSE(fileText(dir + "/walk_ekf_ins.csv").empty());
  EXPECT_EQ(solveWalk("--imu-attitude -1.5,0.6,-42.8 --gap-bridge-max-s -1", dir), 2);
  EXPECT_NE(fileText(dir + "/log.txt").find("--gap-bridge-max-s needs seconds in [0, 600]"), std::string::npos)
      << fileText(dir + "/log.txt");
}
