// rostest, integer ambiguity resolution in the nodes: the first 2 h of ESBC
// 2020-177 (240 epochs at 30 s; GPS fixes from about 43 min on with the IGS14
// satellite antennas) written as a RINEX file, made into a bag by the ppp_to_bag
// binary from the GRG SP3/CLK (integer-recovery clocks: every correction batch
// carries the wide-lane satellite biases of the clock header, PreciseCorrections
// ar_bias_source and satellites[].biases) and played at 100x to ppp_ekf_node (/ekf)
// and ppp_smoother_node (/smoother). The reference is one `ppp_solve --estimator
// both` on the same file with the same configuration (config/ppp.yaml +
// test/rostest/ar_esbc.yaml). Each node must equal it epoch by epoch: the same fix
// state (PppStatus fix_state, NavSatFix status STATUS_GBAS_FIX when fixed),
// positions within 1 mm, the same first fix; the smoother node's final smoothed
// path must equal ppp_solve's smoothed solution within 1 mm (the held integers
// carried back).
#include <sensor_msgs/NavSatStatus.h>

#include "esbc_stream_fixture.h"
#include "ppp_bayes_tree/io/rinex_obs_writer.h"
#include "rostest/live_support.h"

namespace {

using namespace ppp_ros::test;

constexpr std::size_t kEpochs = 240;  // 2 h at 30 s
constexpr double kPlaySpeed = 100.0;

/// One row of a ppp_solve solution CSV with a position.
struct SolvedEpoch {
  Eigen::Vector3d position_ecef_m;
  bool fixed = false;
};

/// ppp_solve's CSV: UTC stamp -> position and fix state ("status" ppp-fixed).
std::map<ros::Time, SolvedEpoch> readSolutionCsv(const std::filesystem::path& csv) {
  std::map<ros::Time, SolvedEpoch> out;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) names.push_back(f);
  }
  auto column = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    EXPECT_NE(it, names.end()) << "no column " << name << " in " << csv;
    return static_cast<std::size_t>(it - names.begin());
  };
  const std::size_t week = column("gps_week"), tow = column("tow_s"), x = column("x_m"), y = column("y_m"),
                    z = column("z_m"), status = column("status");
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string v; std::getline(ss, v, ',');) f.push_back(v);
    if (f.size() <= status || f[x].empty()) continue;
    const ppp::GnssTime t = ppp::GnssTime::fromGpsWeek(std::stoi(f[week]), std::stod(f[tow]));
    out[ppp_ros::utcStamp(t)] = {Eigen::Vector3d(std::stod(f[x]), std::stod(f[y]), std::stod(f[z])),
                                 f[status] == "ppp-fixed"};
  }
  return out;
}

/// The node's fixes and statuses against ppp_solve: the same epochs, positions within
/// 1 mm, the same fix state in PppStatus and NavSatFix; returns the fixed epochs.
std::size_t expectSameFixes(const std::string& what, NodeOutputs& out, const std::map<ros::Time, SolvedEpoch>& offline) {
  std::lock_guard<std::mutex> l(out.mutex);
  std::map<ros::Time, std::uint8_t> fix_state;
  for (const auto& s : out.statuses) fix_state[s.header.stamp] = s.fix_state;
  double worst_m = 0.0;
  std::size_t fixed = 0, state_mismatch = 0;
  for (const auto& f : out.fixes) {
    const auto it = offline.find(f.header.stamp);
    if (it == offline.end()) {
      ADD_FAILURE() << what << ": no ppp_solve epoch at " << f.header.stamp;
      continue;
    }
    worst_m = std::max(worst_m, (fixEcef(f) - it->second.position_ecef_m).norm());
    const bool node_fixed = fix_state[f.header.stamp] == ppp_bayes_tree::PppStatus::FIX_FIXED;
    state_mismatch += node_fixed != it->second.fixed ? 1 : 0;
    EXPECT_EQ(f.status.status, node_fixed ? sensor_msgs::NavSatStatus::STATUS_GBAS_FIX
                                          : sensor_msgs::NavSatStatus::STATUS_FIX) << what << " at " << f.header.stamp;
    fixed += node_fixed ? 1 : 0;
  }
  std::size_t offline_fixed = 0;
  for (const auto& [stamp, e] : offline) offline_fixed += e.fixed ? 1 : 0;
  std::printf("[ figures  ] %s: %zu node fixes (%zu fixed), %zu ppp_solve epochs (%zu fixed); largest difference "
              "%.3g mm; fix state differs at %zu epochs\n",
              what.c_str(), out.fixes.size(), fixed, offline.size(), offline_fixed, worst_m * 1e3, state_mismatch);
  EXPECT_EQ(out.fixes.size(), offline.size()) << what;
  EXPECT_LT(worst_m, 1e-3) << what;
  EXPECT_EQ(state_mismatch, 0u) << what;
  return fixed;
}

/// The last status: AR on with the clocks' wide-lane biases, the counters and the first fix as ppp_solve's.
void expectStatusFigures(const std::string& what, NodeOutputs& out, const std::map<ros::Time, SolvedEpoch>& offline) {
  std::lock_guard<std::mutex> l(out.mutex);
  ASSERT_FALSE(out.statuses.empty()) << what;
  const auto& last = out.statuses.back();
  EXPECT_TRUE(last.ambiguity_resolution_enabled) << what;
  EXPECT_NE(last.phase_bias_source.find("integer-recovery clocks"), std::string::npos) << last.phase_bias_source;
  std::optional<ros::Time> first_fix;
  std::size_t fixed = 0;
  for (const auto& [stamp, e] : offline)
    if (e.fixed) {
      if (!first_fix) first_fix = stamp;
      ++fixed;
    }
  ASSERT_TRUE(first_fix) << what << ": ppp_solve never fixed";
  EXPECT_EQ(last.epochs_fixed, fixed) << what;
  EXPECT_EQ(last.first_fix_stamp, *first_fix) << what;
  EXPECT_NEAR(last.time_to_first_fix_s, (*first_fix - offline.begin()->first).toSec(), 1e-6) << what;
  std::printf("[ figures  ] %s: first fix %.1f min after the first solution, %u fixed epochs, last: %s, %u held, "
              "ratio %.1f\n", what.c_str(), last.time_to_first_fix_s / 60.0, last.epochs_fixed,
              last.fix_state_text.c_str(), last.ambiguities_fixed, last.ratio);
  for (const auto& s : out.statuses) {
    if (s.fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED) {
      EXPECT_TRUE(s.float_reason.empty()) << s.float_reason;
      EXPECT_GT(s.ambiguities_fixed, 0u);
    } else if (s.fix_state == ppp_bayes_tree::PppStatus::FIX_FLOAT) {
      EXPECT_FALSE(s.float_reason.empty()) << what << " at " << s.header.stamp;
    }
  }
  // /diagnostics carries both nodes' tasks: "<node>: ambiguity resolution", OK (phase information present).
  std::size_t tasks = 0;
  for (const auto& [name, level] : out.worst_diagnostic)
    if (name.find("ambiguity resolution") != std::string::npos) {
      ++tasks;
      EXPECT_EQ(level, diagnostic_msgs::DiagnosticStatus::OK) << what << ": " << name;
    }
  EXPECT_EQ(tasks, 2u) << what;
}

}  // namespace

TEST(ArEsbcBag, EkfAndSmootherNodesFixAsPppSolve) {
  PPP_REQUIRE_SHARED_DATA();
  using ppp::test::esbcPath;
  const std::filesystem::path dir = ppp::test::tempDir("ar_esbc_bag");
  const std::string sp3 = esbcPath("GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz");
  const std::string clk = esbcPath("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz");

  // The first 2 h as a RINEX file: the one input of ppp_solve and ppp_to_bag.
  const std::string obs = (dir / "ESBC_2h.rnx").string();
  {
    auto reader = ppp::RinexObsReader::open(esbcPath("ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz"));
    std::ofstream file(obs);
    ppp::RinexObsWriter writer(file);
    writer.writeHeader(reader.header());
    ppp::ObsEpoch e;
    for (std::size_t k = 0; k < kEpochs && reader.next(e); ++k) writer.writeEpoch(e, reader.header());
    ASSERT_TRUE(file.good());
  }
  const std::string bag = (dir / "esbc_2h.bag").string();
  const std::string to_bag = std::string(PPP_BIN_DIR) + "/ppp_to_bag --obs " + obs + " --sp3 " + sp3 + " --clk " + clk +
                             " --out " + bag + " > " + (dir / "to_bag.log").string() + " 2>&1";
  ASSERT_EQ(std::system(to_bag.c_str()), 0) << ppp::test::readFileBytes((dir / "to_bag.log").string());
  const std::string to_bag_log = ppp::test::readFileBytes((dir / "to_bag.log").string());
  EXPECT_NE(to_bag_log.find("wide-lane biases of integer-recovery clocks"), std::string::npos) << to_bag_log;

  const std::string atx = ppp::test::dataPath("antex/igs14_2178_satellites.atx") + " " +
                          ppp::test::dataPath("antex/igs05_esbc_receiver_trim.atx");
  const std::filesystem::path solved =
      runPppSolve("--obs " + obs + " --sp3 " + sp3 + " --clk " + clk + " --atx " + atx + " --config " + PPP_REPO_DIR +
                      "/config/ppp.yaml " + PPP_REPO_DIR + "/test/rostest/ar_esbc.yaml",
                  "both", "ar_esbc_solve");
  const auto ekf = readSolutionCsv(solved / "live_ekf.csv");
  const auto smoother = readSolutionCsv(solved / "live_smoother_filtered.csv");
  const auto smoothed = readSolutionCsv(solved / "live_smoother_smoothed.csv");
  ASSERT_GT(ekf.size(), kEpochs - 5) << ppp::test::readFileBytes((solved / "ppp_solve.log").string());
  ASSERT_GT(smoother.size(), kEpochs - 5);

  ros::NodeHandle nh;
  ros::Publisher obs_pub = nh.advertise<ppp_bayes_tree::GnssObservations>("/gnss/observations", 5000);
  ros::Publisher corr_pub = nh.advertise<ppp_bayes_tree::PreciseCorrections>("/gnss/corrections", 500);
  NodeOutputs ekf_out, smoother_out;
  ekf_out.subscribe(nh, "/ekf/");
  smoother_out.subscribe(nh, "/smoother/");
  ASSERT_TRUE(waitForSubscriberCount("/gnss/observations", 2, 30.0));
  ASSERT_TRUE(waitForSubscriberCount("/gnss/corrections", 2, 30.0));
  ros::WallDuration(0.5).sleep();  // the TCPROS connections settle
  const std::size_t played = playBag(bag, obs_pub, corr_pub, kPlaySpeed);
  ASSERT_EQ(played, kEpochs);
  ASSERT_TRUE(ekf_out.waitForStatuses(played, 60.0)) << ekf_out.statusCount() << " of " << played;
  ASSERT_TRUE(smoother_out.waitForStatuses(played, 60.0)) << smoother_out.statusCount() << " of " << played;
  ros::WallDuration(2.5).sleep();  // one more smoothed path and diagnostics period

  EXPECT_GT(expectSameFixes("ppp_ekf_node", ekf_out, ekf), 50u);
  EXPECT_GT(expectSameFixes("ppp_smoother_node", smoother_out, smoother), 50u);
  expectStatusFigures("ppp_ekf_node", ekf_out, ekf);
  expectStatusFigures("ppp_smoother_node", smoother_out, smoother);

  // The smoothed path (map ENU about the datum = the first solution) against ppp_solve's smoothed solution.
  std::lock_guard<std::mutex> l(smoother_out.mutex);
  ASSERT_FALSE(smoother_out.fixes.empty());
  const Eigen::Vector3d datum = smoother.begin()->second.position_ecef_m;
  const ppp::Geodetic g = ppp::ecefToGeodetic(datum);
  const Eigen::Matrix3d r = ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  const auto& path = smoother_out.smoothed_path;
  ASSERT_EQ(path.poses.size(), smoothed.size());
  double worst_m = 0.0, largest_change_m = 0.0;
  for (const auto& pose : path.poses) {
    const auto it = smoothed.find(pose.header.stamp);
    ASSERT_NE(it, smoothed.end()) << pose.header.stamp;
    worst_m = std::max(worst_m, (position(pose.pose) - r * (it->second.position_ecef_m - datum)).norm());
    largest_change_m = std::max(largest_change_m, (it->second.position_ecef_m - smoother.at(it->first).position_ecef_m).norm());
  }
  std::printf("[ figures  ] ppp_smoother_node smoothed path: %zu poses, largest difference to ppp_solve's smoothed "
              "solution %.3g mm; smoothed - filtered up to %.1f cm\n", path.poses.size(), worst_m * 1e3,
              largest_change_m * 1e2);
  EXPECT_LT(worst_m, 1e-3);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_ar_esbc_bag");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
