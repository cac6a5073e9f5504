// rostest: a GNSS/INS node on a bag of the real u-blox walk (gnss_1730.ubx with its
// IMU imu_1730.csv + .tag, 134 s, ../shared/data/streams/ubx) against ppp_solve with the
// same settings. This test node makes the bag with `ppp_to_bag --ubx --imu --imu-tag`
// (UBX frames on gnss/receiver, the IMU on imu/data) and plays it at up to kSpeed x
// real time, each RXM-RAWX once the node has reported the epoch before it, and nothing
// after an epoch before the node has reported it (a loaded machine slows the replay,
// not the comparison; the odometry after an epoch is the state at the epoch).
// Parameter `estimator`:
//   - "ekf_ins" (ekf_ins_walk.test, ppp_ekf_node, the default): the start levelled at the
//     latest static interval and the heading aligned in motion (ppp_solve without
//     --imu-heading; ros.imu.initial_attitude align_in_motion);
//   - "smoother_ins" (smoother_ins_walk.test, ppp_smoother_node): the start attitude
//     given to both (ppp_solve --imu-attitude; ros.imu.initial_rpy_deg).
// Checks, epoch by epoch: the same epochs solved and one status per epoch; the node's
// ppp/fix equals ppp_solve's position (the filtered one for the smoother), and its
// ppp/odometry/filtered at each epoch's stamp (base_link at the IMU) ppp_solve's attitude
// file (velocity, roll, pitch, heading), within the tolerances. ppp_solve runs twice, the
// second time with the same mounting written -180,0,-90 (the rotation matrix changed at
// the rounding level): both estimators move by a fraction of a millimetre (smoother_ins
// since its cliques are factorized by QR, ppp_ins_smoother.h "Numerics"), so the node,
// whose IMU is stamped in nanoseconds and whose mounting is composed in base_link's axes,
// is compared with ppp_solve on the IMU files at every epoch.
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <sensor_msgs/Imu.h>

#include "ppp_bayes_tree/GnssStreamBytes.h"
#include "ppp_bayes_tree/ros/imu_conversions.h"
#include "ppp_bayes_tree/ros/node_config.h"
#include "ppp_bayes_tree/ros/node_imu_input.h"
#include "rostest/live_support.h"

namespace {

namespace fs = std::filesystem;
using ppp_ros::test::NodeOutputs;

constexpr double kSpeed = 4.0;               // replay speed at most (bag time / wall time)
constexpr double kEpochWait_s = 2.0;         // for the node's status of an epoch before going on
constexpr std::size_t kWalkEpochs = 536;     // RXM-RAWX epochs (shared/data README)
// Tolerances: the node and ppp_solve run the same code on the same data; what differs is
// the IMU's time stamps (nanoseconds in the messages) and the order of the rotations
// (the IMU's mounting composed in base_link's axes against ppp_solve's one matrix).
constexpr double kPositionTolerance_m = 1e-3;
constexpr double kVelocityTolerance_mps = 5e-4;   // the attitude file has 1e-4 m/s
constexpr double kAttitudeTolerance_deg = 1e-3;   // the attitude file has 1e-4 deg

/// The settings of the run: the estimator, ppp_solve's start options, the node.
struct Variant {
  std::string estimator = "ekf_ins";
  std::string node = "ppp_ekf_node";
  std::string solve_start;  // ekf_ins: aligned in motion (no option)
  std::string position_csv = "live_ekf_ins.csv";
};

Variant variantOf(const std::string& estimator) {
  if (estimator != "smoother_ins") return {};
  // The smoother's start: ekf_ins's levelling at the first solution and its heading aligned a second later.
  return {estimator, "ppp_smoother_node", " --imu-attitude -1.5,0.6,-42.8", "live_smoother_ins_filtered.csv"};
}

std::string walkFile(const std::string& name) { return ppp::test::dataPath("streams/ubx/" + name); }

/// ppp_solve's arguments: doc/studies/ins_walk.md "Command" (the IMU as the nodes get it).
std::string pppSolveArgs(const Variant& v) {
  const std::string repo = PPP_REPO_DIR;
  return "--ubx " + walkFile("gnss_1730.ubx") + " --nav " + walkFile("gnss_1730.ubx") + " --atx " +
         ppp::test::dataPath("antex/igs20_gps_satellites_trim.atx") + " --config " + repo + "/config/live.yaml " +
         repo + "/test/rostest/live_ubx.yaml --imu " + walkFile("imu_1730.csv") + " --imu-format logged --imu-tag " +
         walkFile("imu_1730.csv.tag") + " --imu-grade consumer --imu-rotation 180,0,-90 --lever-arm 0,-0.05,0" +
         v.solve_start;
}

/// One row of ppp_solve's attitude file: the GPST second of the day (0.1 s in the file),
/// roll, pitch, heading [deg] and the NED velocity [m/s].
struct AttitudeRow {
  double second_of_day = 0.0;
  Eigen::Matrix3d ned_body;  // from roll, pitch, heading
  Eigen::Vector3d velocity_ned_mps;
};

std::vector<AttitudeRow> readAttitudeFile(const fs::path& csv) {
  std::vector<AttitudeRow> rows;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header: time_gpst,status,roll_deg,pitch_deg,heading_deg,velocity_north_mps,...
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string v; std::getline(ss, v, ',');) f.push_back(v);
    if (f.size() < 8 || f[0].size() < 19 || f[2].empty()) continue;
    // Before its heading is aligned the node claims no orientation (doc/ros_interface.md): the
    // rows compared are the aligned ones.
    if (f.size() > 8 && f[8] != "aligned") continue;
    AttitudeRow r;
    r.second_of_day = std::stod(f[0].substr(11, 2)) * 3600.0 + std::stod(f[0].substr(14, 2)) * 60.0 +
                      std::stod(f[0].substr(17));
    r.ned_body = ppp::rotationNedBody(std::stod(f[2]) * ppp::kDegToRad, std::stod(f[3]) * ppp::kDegToRad,
                                      std::stod(f[4]) * ppp::kDegToRad);
    r.velocity_ned_mps = Eigen::Vector3d(std::stod(f[5]), std::stod(f[6]), std::stod(f[7]));
    rows.push_back(r);
  }
  return rows;
}

/// Odometry that claims an orientation: the INS's, at the IMU rate, once the heading is aligned
/// (before, the node publishes the GNSS position with an orientation covariance of 1e6).
bool claimsOrientation(const nav_msgs::Odometry& o) { return o.pose.covariance[21] < 1e5; }

double secondOfDay(const ros::Time& stamp) {
  const ppp::GpsWeekTime w = ppp_ros::fromUtcStamp(stamp).gpsWeek();
  return std::fmod(w.seconds_of_week, 86400.0);
}

/// ppp_solve's run: the solved positions (and every epoch's row), the attitude rows.
struct Offline {
  std::map<ros::Time, Eigen::Vector3d> positions;
  std::size_t rows = 0;
  std::vector<AttitudeRow> attitude;
};

/// Builds the bag and runs ppp_solve; returns the bag's path.
struct WalkTest {
  ros::NodeHandle nh;
  Variant variant;
  fs::path dir;
  std::string bag;
  Offline offline, perturbed;  // ppp_solve; the same with the mounting rotation changed at the rounding level
  NodeOutputs out;
  ros::Publisher ubx_pub, imu_pub;
  std::size_t frames = 0, readings = 0, rawx = 0;
  double replay_wall_s = 0.0;

  explicit WalkTest(Variant v) : variant(std::move(v)) {
    ubx_pub = nh.advertise<ppp_bayes_tree::GnssStreamBytes>("gnss/receiver", 20000);
    imu_pub = nh.advertise<sensor_msgs::Imu>("imu/data", 20000);
    out.subscribe(nh);
  }

  void makeBag() {
    dir = ppp::test::tempDir("rostest_" + variant.estimator + "_walk");
    bag = (dir / "walk.bag").string();
    const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_to_bag --ubx " + walkFile("gnss_1730.ubx") + " --imu " +
                            walkFile("imu_1730.csv") + " --imu-tag " + walkFile("imu_1730.csv.tag") + " --out " + bag +
                            " > " + (dir / "ppp_to_bag.log").string() + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n" << ppp::test::readFileBytes((dir / "ppp_to_bag.log").string());
  }

  /// ppp_solve with the walk's mounting (`rotation` "180,0,-90"), or the same mounting as
  /// "-180,0,-90": a change of the rotation matrix at the rounding level (sin(-pi) = -sin(pi)).
  Offline solveOffline(const std::string& rotation, const std::string& tag) {
    std::string args = pppSolveArgs(variant);
    args.replace(args.find("--imu-rotation 180,0,-90"), 24, "--imu-rotation " + rotation);
    const fs::path solved = ppp_ros::test::runPppSolve(args, variant.estimator, variant.estimator + tag);
    Offline o;
    o.positions = ppp_ros::test::readPppSolveCsv(solved / variant.position_csv, &o.rows);
    o.attitude = readAttitudeFile(solved / ("live_" + variant.estimator + "_attitude.csv"));
    EXPECT_EQ(o.rows, kWalkEpochs);
    EXPECT_GT(o.positions.size(), 150u) << "ppp_solve solved too few epochs";
    if (!::testing::Test::HasFailure()) fs::remove_all(solved);
    return o;
  }

  /// Plays the bag in its order (frames and readings on their own topics).
  void replay() {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
    while (ros::WallTime::now() < end && (ubx_pub.getNumSubscribers() == 0 || imu_pub.getNumSubscribers() == 0))
      ros::WallDuration(0.05).sleep();
    ASSERT_GT(ubx_pub.getNumSubscribers(), 0u) << variant.node << " does not subscribe to gnss/receiver";
    ASSERT_GT(imu_pub.getNumSubscribers(), 0u) << variant.node << " does not subscribe to imu/data";
    ros::WallDuration(0.5).sleep();  // connections settle
    rosbag::Bag b(bag, rosbag::bagmode::Read);
    rosbag::View view(b);
    const ros::WallTime t0 = ros::WallTime::now();
    ros::WallTime start = t0;
    ros::Time first, last_reading;
    for (const rosbag::MessageInstance& m : view) {
      if (first.isZero()) first = m.getTime();
      const ros::WallDuration wait = start + ros::WallDuration((m.getTime() - first).toSec() / kSpeed) - ros::WallTime::now();
      if (wait > ros::WallDuration(0)) wait.sleep();
      if (auto i = m.instantiate<sensor_msgs::Imu>()) {
        imu_pub.publish(i);
        last_reading = i->header.stamp;
        ++readings;
      } else if (auto f = m.instantiate<ppp_bayes_tree::GnssStreamBytes>()) {
        if (isRawx(*f)) waitForReadingsBefore(last_reading);
        ubx_pub.publish(f);
        ++frames;
        if (isRawx(*f) && !waitForEpoch(++rawx, f->header.stamp))
          start = ros::WallTime::now() - ros::WallDuration((m.getTime() - first).toSec() / kSpeed);
      }
    }
    EXPECT_TRUE(out.waitForStatuses(kWalkEpochs - 1, 120.0)) << out.statusCount() << " statuses of " << kWalkEpochs;
    ros::WallDuration(1.0).sleep();
    replay_wall_s = (ros::WallTime::now() - t0).toSec();
    std::printf("[ figures  ] %s: %zu UBX frames (%zu RXM-RAWX), %zu IMU readings at up to %.0fx in %.1f s wall; "
                "%zu epochs not reported within %.0f s\n",
                variant.node.c_str(), frames, rawx, readings, kSpeed, replay_wall_s, epochs_not_reported_in_time,
                kEpochWait_s);
    EXPECT_LE(epochs_not_reported_in_time, 2u);  // the first two epochs go out with the third (measured)
    EXPECT_EQ(readings_not_seen_in_time, 0u) << "odometry of the readings before an epoch not seen in time";
  }

  /// The readings published before an epoch reach the node before it: once the INS odometry runs (heading aligned),
  /// until its odometry (one message per reading) reaches `last_reading`; before, 20 ms.
  void waitForReadingsBefore(const ros::Time& last_reading) {
    const auto reached = [&] {
      std::lock_guard<std::mutex> l(out.mutex);
      return !out.odometry.empty() && claimsOrientation(out.odometry.back()) &&
             out.odometry.back().header.stamp >= last_reading;
    };
    bool running = false;
    {
      std::lock_guard<std::mutex> l(out.mutex);
      running = !out.odometry.empty() && claimsOrientation(out.odometry.back());
    }
    if (!running) {
      ros::WallDuration(0.02).sleep();
      return;
    }
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(kEpochWait_s);
    while (!reached() && ros::WallTime::now() < end) ros::WallDuration(0.0005).sleep();
    if (!reached()) ++readings_not_seen_in_time;
  }
  std::size_t readings_not_seen_in_time = 0;

  static bool isRawx(const ppp_bayes_tree::GnssStreamBytes& f) {
    return f.data.size() > 4 && f.data[2] == 0x02 && f.data[3] == 0x15;
  }
  /// Waits until the node has reported the epoch of the `published`-th RXM-RAWX (at most
  /// kEpochWait_s), so that no later reading reaches it before: its odometry after the
  /// epoch is then the state at the epoch. False when it had to wait (the schedule then
  /// starts again from now).
  bool waitForEpoch(std::size_t published, const ros::Time& stamp) {
    if (out.statusCount() >= published) return true;
    if (!out.waitForStatuses(published, kEpochWait_s)) {
      ++epochs_not_reported_in_time;
      std::printf("[ figures  ] RXM-RAWX %zu (read at %.3f) not reported within %.0f s: %zu statuses\n", published,
                  stamp.toSec(), kEpochWait_s, out.statusCount());
    }
    return false;
  }
  std::size_t epochs_not_reported_in_time = 0;
};

WalkTest* g = nullptr;

/// R_ned_body (body x forward, y right, z down) of an odometry pose of base_link (x forward,
/// y left, z up) in the map (ENU at the datum), at the pose's position.
Eigen::Matrix3d nedBodyOf(const geometry_msgs::Pose& p, const Eigen::Vector3d& datum_ecef_m,
                          const Eigen::Matrix3d& ecef_enu) {
  const Eigen::Quaterniond q(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  const Eigen::Vector3d position_ecef_m = datum_ecef_m + ecef_enu * ppp_ros::test::position(p);
  const Eigen::Matrix3d base_body = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  return ppp::rotationEcefNed(position_ecef_m).transpose() * ecef_enu * q.toRotationMatrix() * base_body;
}

TEST(InsWalk, TheNodeIsConfiguredAsPppSolve) {
  PPP_REQUIRE_SHARED_DATA();
  const ppp_ros::NodeConfig c = ppp_ros::loadNodeConfig(ros::NodeHandle("/" + g->variant.node), "");
  ASSERT_EQ(c.ros.estimator, g->variant.estimator);
  const ppp::InsEkfOptions ins = ppp_ros::insOptions(c.ros, ppp_ros::parameterExtrinsics(c.ros.imu));
  // The IMU's mounting and the lever arm: ppp_solve's --imu-rotation 180,0,-90 --lever-arm 0,-0.05,0.
  const Eigen::Matrix3d solve_body_imu = ppp::rotationNedBody(M_PI, 0.0, -M_PI / 2.0);
  EXPECT_LT((ppp_ros::bodyFromImu(ppp_ros::parameterExtrinsics(c.ros.imu)) - solve_body_imu).norm(), 1e-12);
  EXPECT_LT((ins.lever_arm_body_m - Eigen::Vector3d(0.0, -0.05, 0.0)).norm(), 1e-12);
  EXPECT_EQ(ins.noise.gyro_noise_density_radps_per_sqrthz,
            ppp::imuNoisePreset(ppp::ImuGrade::ConsumerMems).gyro_noise_density_radps_per_sqrthz);
  if (g->variant.estimator == "smoother_ins") {  // the start: ppp_solve --imu-attitude -1.5,0.6,-42.8
    ASSERT_TRUE(ins.initial_rotation_ned_body.has_value());
    const Eigen::Matrix3d solve = ppp::rotationNedBody(-1.5 * ppp::kDegToRad, 0.6 * ppp::kDegToRad, -42.8 * ppp::kDegToRad);
    EXPECT_LT((*ins.initial_rotation_ned_body - solve).norm(), 1e-12);
  } else {  // aligned in motion: neither an attitude nor a heading
    EXPECT_FALSE(ins.initial_rotation_ned_body || ins.initial_heading_rad);
  }
}

/// The largest differences of one solution from ppp_solve's: positions at the epochs both
/// solved, velocity and attitude at each attitude row (`compared` rows).
struct Differences {
  double position_m = 0.0, velocity_mps = 0.0, attitude_deg = 0.0;
  std::size_t positions = 0, compared = 0;
};

/// Velocity and attitude of an odometry message of the node as ppp_solve's attitude row gives them.
AttitudeRow rowOf(const nav_msgs::Odometry& o, const Eigen::Vector3d& datum_ecef_m, const Eigen::Matrix3d& ecef_enu) {
  const Eigen::Matrix3d ned_body = nedBodyOf(o.pose.pose, datum_ecef_m, ecef_enu);
  const Eigen::Matrix3d ned_base = ned_body * Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  AttitudeRow r;
  r.second_of_day = secondOfDay(o.header.stamp);
  r.velocity_ned_mps = ned_base * Eigen::Vector3d(o.twist.twist.linear.x, o.twist.twist.linear.y, o.twist.twist.linear.z);
  r.ned_body = ned_body;
  return r;
}

double attitudeDifference_deg(const AttitudeRow& a, const AttitudeRow& b) {
  return Eigen::AngleAxisd(a.ned_body.transpose() * b.ned_body).angle() / ppp::kDegToRad;
}

/// `positions` and `rows` (by the decisecond of their time) against ppp_solve's run.
Differences differences(const std::map<ros::Time, Eigen::Vector3d>& positions, const std::vector<AttitudeRow>& rows,
                        const Offline& offline) {
  Differences d;
  for (const auto& [stamp, p] : positions) {
    const auto it = offline.positions.find(stamp);
    if (it == offline.positions.end()) continue;
    d.position_m = std::max(d.position_m, (p - it->second).norm());
    ++d.positions;
  }
  std::map<long, const AttitudeRow*> by_decisecond;
  for (const AttitudeRow& r : rows) by_decisecond[std::lround(r.second_of_day * 10.0)] = &r;
  for (const AttitudeRow& row : offline.attitude) {
    const auto it = by_decisecond.find(std::lround(row.second_of_day * 10.0));
    if (it == by_decisecond.end()) continue;
    d.velocity_mps = std::max(d.velocity_mps, (it->second->velocity_ned_mps - row.velocity_ned_mps).cwiseAbs().maxCoeff());
    d.attitude_deg = std::max(d.attitude_deg, attitudeDifference_deg(*it->second, row));
    ++d.compared;
  }
  return d;
}

/// The node's fixes (ECEF by stamp) and its odometry at the epochs as attitude rows.
void nodeSolutions(const std::vector<sensor_msgs::NavSatFix>& fixes, const std::vector<nav_msgs::Odometry>& odometry,
                   const std::vector<ppp_bayes_tree::PppStatus>& statuses, std::map<ros::Time, Eigen::Vector3d>* positions,
                   std::vector<AttitudeRow>* rows) {
  for (const auto& f : fixes) (*positions)[f.header.stamp] = ppp_ros::test::fixEcef(f);
  const ppp_ros::NodeConfig c = ppp_ros::loadNodeConfig(ros::NodeHandle("/" + g->variant.node), "");
  const Eigen::Vector3d datum_ecef_m = ppp::geodeticToEcef(
      {c.ros.datum_latitude_deg * ppp::kDegToRad, c.ros.datum_longitude_deg * ppp::kDegToRad, c.ros.datum_height_m});
  const Eigen::Matrix3d ecef_enu = ppp::rotationEcefNed(datum_ecef_m) * ppp::rotationNedEnu();
  std::set<ros::Time> epochs;
  for (const auto& s : statuses) epochs.insert(s.header.stamp);
  for (const auto& o : odometry)
    if (epochs.count(o.header.stamp) && claimsOrientation(o)) rows->push_back(rowOf(o, datum_ecef_m, ecef_enu));
}

TEST(InsWalk, FixesAndOdometryEqualPppSolveEpochByEpoch) {
  PPP_REQUIRE_SHARED_DATA();
  ASSERT_NO_FATAL_FAILURE(g->makeBag());
  g->offline = g->solveOffline("180,0,-90", "");
  g->perturbed = g->solveOffline("-180,0,-90", "_perturbed");
  ASSERT_FALSE(::testing::Test::HasFailure());
  ASSERT_NO_FATAL_FAILURE(g->replay());
  std::vector<sensor_msgs::NavSatFix> fixes;
  std::vector<nav_msgs::Odometry> odometry;
  std::vector<ppp_bayes_tree::PppStatus> statuses;
  {
    std::lock_guard<std::mutex> l(g->out.mutex);
    fixes = g->out.fixes;
    odometry = g->out.odometry;
    statuses = g->out.statuses;
  }
  // One status per epoch (the last perhaps held: a live stream does not end), nothing lost.
  EXPECT_GE(statuses.size() + 1, kWalkEpochs);
  EXPECT_LE(statuses.size(), kWalkEpochs);
  ASSERT_FALSE(statuses.empty());
  EXPECT_EQ(statuses.back().estimator, g->variant.estimator);
  EXPECT_EQ(statuses.back().imu_readings_rejected, 0u);
  // The same epochs solved: every fix has a ppp_solve solution and every solution (but perhaps the last) a fix.
  std::map<ros::Time, Eigen::Vector3d> positions;
  std::vector<AttitudeRow> rows;
  nodeSolutions(fixes, odometry, statuses, &positions, &rows);
  const Differences node = differences(positions, rows, g->offline);
  const Differences spread = differences(g->perturbed.positions, g->perturbed.attitude, g->offline);
  std::printf("[ figures  ] %s: %zu fixes of %zu ppp_solve solutions; largest difference: position %.3g mm, "
              "velocity %.3g m/s, attitude %.3g deg over %zu of %zu attitude rows. ppp_solve with the mounting "
              "rotation changed at the rounding level: position %.3g mm, velocity %.3g m/s, attitude %.3g deg\n",
              g->variant.estimator.c_str(), node.positions, g->offline.positions.size(), node.position_m * 1e3,
              node.velocity_mps, node.attitude_deg, node.compared, g->offline.attitude.size(), spread.position_m * 1e3,
              spread.velocity_mps, spread.attitude_deg);
  // Both estimators are well conditioned on the walk: ppp_solve's rounding-level change moves
  // them by a fraction of a millimetre, and the node is as close to ppp_solve.
  EXPECT_EQ(node.positions, positions.size()) << "fixes at epochs ppp_solve did not solve";
  EXPECT_GE(node.positions + 1, g->offline.positions.size());
  EXPECT_GE(node.compared + 1, g->offline.attitude.size());
  EXPECT_LT(spread.position_m, kPositionTolerance_m);
  EXPECT_LT(node.position_m, kPositionTolerance_m);
  EXPECT_LT(node.velocity_mps, kVelocityTolerance_mps);
  EXPECT_LT(node.attitude_deg, kAttitudeTolerance_deg);
  if (!::testing::Test::HasFailure()) fs::remove_all(g->dir);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_ins_walk");
  const std::optional<std::string> estimator = ppp_ros::test::insEstimatorParam();
  if (!estimator) return 1;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  WalkTest t(variantOf(*estimator));
  g = &t;
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
