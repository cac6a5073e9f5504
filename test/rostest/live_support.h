#pragma once
// Helpers of the live-input rostests (live_*.cpp, issue 14): publish a real
// recording as foreign stream messages (exact type name and MD5, through
// topic_tools::ShapeShifter), run the ppp_solve binary on the same recording as
// the reference, and compare a node's fixes with it epoch by epoch.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ros/ublox_ros_messages.h"
#include "rostest/rostest_support.h"
#include "test_support.h"

namespace ppp_ros::test {

/// One message to publish: on which publisher, what.
struct StreamMessage {
  std::size_t publisher = 0;
  topic_tools::ShapeShifter message;
};

/// Advertises every (topic, message type) of `messages`' publishers, waits until each has
/// `subscribers` subscribers, then publishes them in order, `spacing_s` apart (wall time:
/// keeps the order across topics at the node, whose callbacks run one after the other).
inline void publishInOrder(ros::NodeHandle& nh, const std::vector<std::string>& topics,
                           std::vector<StreamMessage>& messages, double spacing_s, std::size_t subscribers = 1) {
  std::vector<ros::Publisher> pubs(topics.size());
  for (auto& m : messages)
    if (!pubs[m.publisher]) pubs[m.publisher] = m.message.advertise(nh, topics[m.publisher], 100000);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
  for (auto& p : pubs) {
    while (p && p.getNumSubscribers() < subscribers && ros::WallTime::now() < end) ros::WallDuration(0.05).sleep();
    ASSERT_TRUE(!p || p.getNumSubscribers() >= subscribers) << p.getTopic() << " has no subscriber";
  }
  ros::WallDuration(0.5).sleep();  // connections settle
  for (auto& m : messages) {
    pubs[m.publisher].publish(m.message);
    ros::WallDuration(spacing_s).sleep();
  }
}

/// Runs `ppp_solve <args> --estimator E --name live --out DIR` (exit 0, 3, or 1 with a CSV) and reads
/// DIR/live_E.csv (smoother: live_smoother_filtered.csv): UTC stamp -> ECEF position of the epochs with a solution
/// (`rows`: every epoch row, with a solution or not).
inline std::map<ros::Time, Eigen::Vector3d> pppSolve(const std::string& args, const std::string& tag,
                                                     const std::string& estimator, std::size_t* rows = nullptr) {
  const std::filesystem::path dir = ppp::test::tempDir(tag);
  const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_solve " + args + " --estimator " + estimator +
                          " --name live --out " + dir.string() + " > " + (dir / "ppp_solve.log").string() + " 2>&1";
  // The smoother's per-epoch (filtered) solutions are what its node publishes on ppp/fix.
  const std::string csv = estimator == "smoother" ? "live_smoother_filtered.csv" : "live_" + estimator + ".csv";
  const int rc = std::system(cmd.c_str());
  const int exit_code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  // 1 = nothing solved, with the CSV written: the caller checks the rows.
  EXPECT_TRUE(exit_code == 0 || exit_code == 3 || (exit_code == 1 && std::filesystem::exists(dir / csv)))
      << cmd << " exited " << exit_code << ":\n"
                                                << ppp::test::readFileBytes((dir / "ppp_solve.log").string());
  std::map<ros::Time, Eigen::Vector3d> out;
  if (rows) *rows = 0;
  std::ifstream in(dir / csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) names.push_back(f);
  }
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return i;
    ADD_FAILURE() << "no column " << name << " in " << (dir / csv);
    return std::size_t{0};
  };
  const std::size_t week = column("gps_week"), tow = column("tow_s"), x = column("x_m"), y = column("y_m"),
                    z = column("z_m");
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string v; std::getline(ss, v, ',');) f.push_back(v);
    if (rows) ++*rows;
    if (f.size() <= z || f[x].empty()) continue;  // no solution at this epoch
    const ppp::GnssTime t = ppp::GnssTime::fromGpsWeek(std::stoi(f[week]), std::stod(f[tow]));
    out[utcStamp(t)] = Eigen::Vector3d(std::stod(f[x]), std::stod(f[y]), std::stod(f[z]));
  }
  return out;
}

/// pppSolve with --estimator ekf.
inline std::map<ros::Time, Eigen::Vector3d> pppSolveEkf(const std::string& args, const std::string& tag,
                                                        std::size_t* rows = nullptr) {
  return pppSolve(args, tag, "ekf", rows);
}

/// The node's fixes against ppp_solve's: every fix has a ppp_solve epoch within 1 ms
/// of its stamp, and every ppp_solve epoch (but perhaps the last) a fix; largest 3D difference < 1 mm.
inline void expectEqualToPppSolve(const std::string& what, const std::vector<sensor_msgs::NavSatFix>& fixes,
                                  const std::map<ros::Time, Eigen::Vector3d>& offline) {
  ASSERT_FALSE(offline.empty()) << what << ": ppp_solve solved no epoch";
  double worst = 0.0;
  std::size_t matched = 0;
  for (const auto& f : fixes) {
    auto it = offline.lower_bound(f.header.stamp - ros::Duration(1e-3));
    ASSERT_TRUE(it != offline.end() && std::abs((it->first - f.header.stamp).toSec()) < 1e-3)
        << what << ": no ppp_solve epoch at " << f.header.stamp;
    worst = std::max(worst, (fixEcef(f) - it->second).norm());
    ++matched;
  }
  std::printf("[ figures  ] %s: %zu node fixes, %zu ppp_solve epochs; largest difference %.3g mm\n", what.c_str(),
              matched, offline.size(), worst * 1e3);
  // Every epoch, but perhaps the last: a live stream does not end, so an epoch whose
  // completeness the decoder cannot tell before the next one arrives may stay held.
  EXPECT_GE(matched + 1, offline.size()) << what;
  EXPECT_LT(worst, 1e-3) << what;
}

/// Waits (wall time) until `out` received `n` fixes and none for `quiet_s`, or the timeout.
inline void waitForFixes(NodeOutputs& out, std::size_t n, double timeout_s, double quiet_s = 3.0) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  std::size_t last = 0;
  ros::WallTime last_change = ros::WallTime::now();
  while (ros::WallTime::now() < end) {
    std::size_t now_n;
    {
      std::lock_guard<std::mutex> l(out.mutex);
      now_n = out.fixes.size();
    }
    if (now_n != last) {
      last = now_n;
      last_change = ros::WallTime::now();
    }
    if (now_n >= n && (ros::WallTime::now() - last_change).toSec() > quiet_s) return;
    ros::WallDuration(0.1).sleep();
  }
}

}  // namespace ppp_ros::test
