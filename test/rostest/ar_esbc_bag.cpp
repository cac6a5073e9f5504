// rostest, integer ambiguity resolution in the nodes: the first 2 h of ESBC
// 2020-177 (240 epochs at 30 s; GPS fixes from about 43 min on with the IGS14
// satellite antennas) written as a RINEX file, made into a bag by the ppp_to_bag
// binary from the GRG SP3/CLK (integer-recovery clocks: every correction batch
// carries the wide-lane satellite biases of the clock header, PreciseCorrections
// ar_bias_source and satellites[].biases) and played at 150x to five nodes
// (ar_esbc_bag.test). The reference is one `ppp_solve --estimator both` on the same
// file with the same configuration (config/ppp.yaml + test/rostest/ar_esbc.yaml).
// - /ekf, /smoother: each equals ppp_solve epoch by epoch: the same fix state
//   (PppStatus fix_state, NavSatFix STATUS_GBAS_FIX when fixed), positions within
//   1 mm, the same first fix; the smoother node's final smoothed path equals
//   ppp_solve's smoothed solution within 1 mm (the held integers carried back).
// - /inject/{ekf,smoother}, wrong-fix injection: from 15 min after ppp_solve's first
//   fix on, the batches add half
//   a narrow-lane cycle (0.5 x 10.7 cm) to the L1 and L2 phase biases of the odd-PRN
//   GPS satellites, so that every held single difference between an odd and an even
//   PRN is off its integer by half a cycle (a phase-bias jump of the correction
//   service). Each node must release such integers, keep every fixed epoch within 10 cm
//   of the clean ppp_solve solution (the wrong-fix criterion) and be fixed at the end.
// - /nobias/ekf: the batches without their biases: float at every epoch, with the
//   reason in PppStatus.float_reason, the "ambiguity resolution" diagnostic at WARN
//   and one warning in the log.
#include <array>

#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/NavSatStatus.h>

#include "esbc_stream_fixture.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_writer.h"
#include "rostest/live_support.h"

namespace {

using namespace ppp_ros::test;

constexpr std::size_t kEpochs = 240;  // 2 h at 30 s
constexpr double kPlaySpeed = 150.0;
constexpr double kInjectAfterFirstFix_s = 15.0 * 60.0;  // the injection: 15 min after ppp_solve's first fix
// Half a narrow-lane cycle of the GPS ionosphere-free ambiguity: c / (f1 + f2) / 2 [m].
constexpr double kInjectedPhaseBias_m = 0.5 * 299792458.0 / (1575.42e6 + 1227.60e6);

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
  std::printf("[ figures  ] %s: first fix %.1f min after the first solution, %u fixed epochs, %u held integers "
              "released, last: %s, %u held, ratio %.1f\n", what.c_str(), last.time_to_first_fix_s / 60.0,
              last.epochs_fixed, last.ambiguity_releases, last.fix_state_text.c_str(), last.ambiguities_fixed, last.ratio);
  for (const auto& s : out.statuses) {
    if (s.fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED) {
      EXPECT_TRUE(s.float_reason.empty()) << s.float_reason;
      EXPECT_GT(s.ambiguities_fixed, 0u);
    } else if (s.fix_state == ppp_bayes_tree::PppStatus::FIX_FLOAT) {
      EXPECT_FALSE(s.float_reason.empty()) << what << " at " << s.header.stamp;
    }
  }
  // /diagnostics carries every node's tasks ("<node>: ambiguity resolution"): OK with phase information.
  std::size_t tasks = 0;
  for (const auto& [name, level] : out.worst_diagnostic)
    if (name.find("ambiguity resolution") != std::string::npos && name.find("nobias") == std::string::npos) {
      ++tasks;
      EXPECT_EQ(level, diagnostic_msgs::DiagnosticStatus::OK) << what << ": " << name;
    }
  EXPECT_EQ(tasks, 4u) << what;  // ekf, smoother, inject/ekf, inject/smoother
}


/// The three inputs of the test: the bag as it is, with the injection, without biases.
struct Inputs {
  ros::Publisher obs[3], corr[3];
  explicit Inputs(ros::NodeHandle& nh) {
    const char* prefix[3] = {"", "/inject", "/nobias"};
    for (int i = 0; i < 3; ++i) {
      obs[i] = nh.advertise<ppp_bayes_tree::GnssObservations>(std::string(prefix[i]) + "/gnss/observations", 5000);
      corr[i] = nh.advertise<ppp_bayes_tree::PreciseCorrections>(std::string(prefix[i]) + "/gnss/corrections", 500);
    }
  }
  /// Waits (wall time) until input i has `nodes[i]` connected subscribers on both topics.
  bool waitForConnections(const std::array<std::uint32_t, 3>& nodes, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      bool all = true;
      for (int i = 0; i < 3; ++i)
        all = all && obs[i].getNumSubscribers() >= nodes[i] && corr[i].getNumSubscribers() >= nodes[i];
      if (all) return true;
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }
};

/// Adds kInjectedPhaseBias_m to the phase biases of the odd-PRN GPS satellites.
ppp_bayes_tree::PreciseCorrections injected(ppp_bayes_tree::PreciseCorrections c) {
  for (auto& s : c.satellites) {
    const auto sat = ppp::SatelliteId::parse(s.satellite);
    if (!sat || sat->system != ppp::GnssSystem::GPS || sat->prn % 2 == 0) continue;
    for (auto& b : s.biases)
      if (!b.observable.empty() && b.observable[0] == 'L') b.bias_m += kInjectedPhaseBias_m;
  }
  return c;
}

/// Plays the bag at kPlaySpeed to the three inputs; returns the observation epochs.
std::size_t playToAll(const std::string& path, Inputs& in, const ros::Time& inject_from) {
  return playBagTo(
      path, kPlaySpeed,
      [&](const ppp_bayes_tree::GnssObservations& o) {
        for (auto& p : in.obs) p.publish(o);
      },
      [&](const ppp_bayes_tree::PreciseCorrections& c) {
        in.corr[0].publish(c);
        in.corr[1].publish(c.header.stamp >= inject_from ? injected(c) : c);
        ppp_bayes_tree::PreciseCorrections bare = c;
        bare.ar_bias_source.clear();
        bare.ar_bias_kind = ppp_bayes_tree::PreciseCorrections::AR_BIASES_NONE;
        for (auto& s : bare.satellites) s.biases.clear();
        in.corr[2].publish(bare);
      });
}

/// Wrong-fix injection: held integers released after the injection, no fixed epoch more
/// than 10 cm from the clean solution, fixed at the end.
void expectInjectionHandled(const std::string& what, NodeOutputs& out, const std::map<ros::Time, SolvedEpoch>& clean,
                            const ros::Time& inject_from) {
  std::lock_guard<std::mutex> l(out.mutex);
  ASSERT_FALSE(out.statuses.empty()) << what;
  std::map<ros::Time, bool> fixed_at;
  std::uint32_t releases_before = 0, releases_after = 0;
  std::optional<ros::Time> first_release;
  for (const auto& s : out.statuses) {
    fixed_at[s.header.stamp] = s.fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED;
    if (s.header.stamp < inject_from) {
      releases_before = s.ambiguity_releases;
      continue;
    }
    if (s.ambiguity_releases > releases_before && !first_release) first_release = s.header.stamp;
    releases_after = s.ambiguity_releases - releases_before;
  }
  double worst_fixed_m = 0.0, worst_float_m = 0.0;
  std::size_t fixed_after = 0, wrong = 0;
  for (const auto& f : out.fixes) {
    if (f.header.stamp < inject_from) continue;
    const auto it = clean.find(f.header.stamp);
    if (it == clean.end()) continue;
    const double d = (fixEcef(f) - it->second.position_ecef_m).norm();
    if (fixed_at[f.header.stamp]) {
      ++fixed_after;
      worst_fixed_m = std::max(worst_fixed_m, d);
      wrong += d > 0.10 ? 1 : 0;
    } else {
      worst_float_m = std::max(worst_float_m, d);
    }
  }
  std::printf("[ figures  ] %s, wrong-fix injection at %s: %u held integers released after it (the first "
              "%.1f min after); %zu fixed epochs after it, largest distance from the clean solution %.1f cm fixed "
              "(%zu > 10 cm), %.1f cm float\n",
              what.c_str(), (std::to_string(static_cast<int>((inject_from - clean.begin()->first).toSec() / 60.0)) +
                             " min").c_str(), releases_after,
              first_release ? (*first_release - inject_from).toSec() / 60.0 : -1.0, fixed_after, worst_fixed_m * 1e2,
              wrong, worst_float_m * 1e2);
  EXPECT_GT(releases_after, 0u) << what << ": no held integer released after the injection";
  EXPECT_EQ(wrong, 0u) << what;
  EXPECT_TRUE(out.statuses.back().fix_state == ppp_bayes_tree::PppStatus::FIX_FIXED) << what;
}

/// No phase information: float throughout, the reason in every status, WARN, one log warning.
void expectSaysNoPhaseInformation(NodeOutputs& out, const std::vector<std::string>& warnings) {
  std::lock_guard<std::mutex> l(out.mutex);
  ASSERT_FALSE(out.statuses.empty());
  for (const auto& s : out.statuses) {
    EXPECT_TRUE(s.ambiguity_resolution_enabled);
    EXPECT_NE(s.fix_state, ppp_bayes_tree::PppStatus::FIX_FIXED) << s.header.stamp;
    EXPECT_TRUE(s.phase_bias_source.empty()) << s.phase_bias_source;
    EXPECT_NE(s.float_reason.find("no consistent phase biases"), std::string::npos) << s.float_reason;
  }
  std::size_t tasks = 0;
  for (const auto& [name, level] : out.worst_diagnostic)
    if (name.find("nobias") != std::string::npos && name.find("ambiguity resolution") != std::string::npos) {
      ++tasks;
      EXPECT_EQ(level, diagnostic_msgs::DiagnosticStatus::WARN) << name;
    }
  EXPECT_EQ(tasks, 1u);
  EXPECT_EQ(warnings.size(), 1u) << "log warnings about the missing phase information";
  std::printf("[ figures  ] /nobias/ekf: %zu statuses, all float: \"%s\"; log: \"%s\"\n", out.statuses.size(),
              out.statuses.back().float_reason.c_str(), warnings.empty() ? "" : warnings.front().c_str());
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
  Inputs inputs(nh);
  NodeOutputs ekf_out, smoother_out, inject_ekf_out, inject_smoother_out, nobias_out;
  ekf_out.subscribe(nh, "/ekf/");
  smoother_out.subscribe(nh, "/smoother/");
  inject_ekf_out.subscribe(nh, "/inject/ekf/");
  inject_smoother_out.subscribe(nh, "/inject/smoother/");
  nobias_out.subscribe(nh, "/nobias/ekf/");
  std::mutex log_mutex;
  std::vector<std::string> nobias_warnings;  // the /nobias/ekf node's log warnings about the phase information
  ros::Subscriber rosout = nh.subscribe<rosgraph_msgs::Log>("/rosout", 1000, [&](const auto& m) {
    if (m->name.find("nobias") == std::string::npos || m->level != rosgraph_msgs::Log::WARN) return;
    if (m->msg.find("ambiguity resolution") == std::string::npos) return;
    std::lock_guard<std::mutex> l(log_mutex);
    nobias_warnings.push_back(m->msg);
  });
  // Every node connected to its inputs (publisher-side connections: nothing published is lost).
  ASSERT_TRUE(inputs.waitForConnections({2, 2, 1}, 30.0)) << "the nodes did not connect";
  ros::WallDuration(0.5).sleep();
  std::optional<ros::Time> first_fix;
  for (const auto& [stamp, e] : ekf)
    if (e.fixed && !first_fix) first_fix = stamp;
  ASSERT_TRUE(first_fix) << "ppp_solve never fixed";
  const ros::Time inject_from = *first_fix + ros::Duration(kInjectAfterFirstFix_s);
  ASSERT_LT(inject_from, ekf.rbegin()->first - ros::Duration(15.0 * 60.0)) << "too little data after the injection";
  const std::size_t played = playToAll(bag, inputs, inject_from);
  ASSERT_EQ(played, kEpochs);
  for (NodeOutputs* o : {&ekf_out, &smoother_out, &inject_ekf_out, &inject_smoother_out, &nobias_out})
    ASSERT_TRUE(o->waitForStatuses(played, 90.0)) << o->statusCount() << " of " << played;
  ros::WallDuration(2.5).sleep();  // one more smoothed path and diagnostics period

  EXPECT_GT(expectSameFixes("ppp_ekf_node", ekf_out, ekf), 50u);
  EXPECT_GT(expectSameFixes("ppp_smoother_node", smoother_out, smoother), 50u);
  expectStatusFigures("ppp_ekf_node", ekf_out, ekf);
  expectStatusFigures("ppp_smoother_node", smoother_out, smoother);
  expectInjectionHandled("/inject/ekf", inject_ekf_out, ekf, inject_from);
  expectInjectionHandled("/inject/smoother", inject_smoother_out, smoother, inject_from);
  {
    std::lock_guard<std::mutex> l(log_mutex);
    expectSaysNoPhaseInformation(nobias_out, nobias_warnings);
  }

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
