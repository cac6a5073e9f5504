#pragma once
// Helpers of the rostests: play a bag made by the test at a speed factor
// (header stamps give the data time), and collect what a PPP node publishes.
#include <gtest/gtest.h>

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/NavSatFix.h>

#include "ppp_bayes_tree/GnssObservations.h"
#include "ppp_bayes_tree/PppStatus.h"
#include "ppp_bayes_tree/PreciseCorrections.h"

namespace ppp_ros::test {

/// Publishes the bag's two topics at `speed` x real time (bag time spacing / speed).
inline std::size_t playBag(const std::string& path, ros::Publisher& obs, ros::Publisher& corr, double speed) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::size_t epochs = 0;
  ros::Time previous;
  const ros::WallTime start = ros::WallTime::now();
  ros::Time first;
  for (const rosbag::MessageInstance& m : view) {
    if (first.isZero()) first = m.getTime();
    // Wall time at which this message is due.
    const ros::WallTime due = start + ros::WallDuration((m.getTime() - first).toSec() / speed);
    const ros::WallDuration wait = due - ros::WallTime::now();
    if (wait > ros::WallDuration(0)) wait.sleep();
    if (auto o = m.instantiate<ppp_bayes_tree::GnssObservations>()) {
      obs.publish(o);
      ++epochs;
    } else if (auto c = m.instantiate<ppp_bayes_tree::PreciseCorrections>()) {
      corr.publish(c);
    }
  }
  return epochs;
}

/// Everything the node publishes, collected under a mutex.
struct NodeOutputs {
  std::mutex mutex;
  std::vector<nav_msgs::Odometry> odometry;
  std::vector<sensor_msgs::NavSatFix> fixes;
  std::vector<ppp_bayes_tree::PppStatus> statuses;
  std::map<std::string, std::uint8_t> worst_diagnostic;  // status name -> worst level seen
  ros::Subscriber subs[4];

  void subscribe(ros::NodeHandle& nh, const std::string& prefix = "") {
    subs[0] = nh.subscribe<nav_msgs::Odometry>(prefix + "ppp/odometry/filtered", 10000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      odometry.push_back(*m);
    });
    subs[1] = nh.subscribe<sensor_msgs::NavSatFix>(prefix + "ppp/fix", 10000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      fixes.push_back(*m);
    });
    subs[2] = nh.subscribe<ppp_bayes_tree::PppStatus>(prefix + "ppp/status", 10000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      statuses.push_back(*m);
    });
    subs[3] = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 1000, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      for (const auto& s : m->status) {
        auto& w = worst_diagnostic[s.name];
        w = std::max<std::uint8_t>(w, s.level);
      }
    });
  }
  std::size_t statusCount() {
    std::lock_guard<std::mutex> l(mutex);
    return statuses.size();
  }
  /// Waits (wall time) until `n` statuses arrived or the timeout.
  bool waitForStatuses(std::size_t n, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      if (statusCount() >= n) return true;
      ros::WallDuration(0.05).sleep();
    }
    return statusCount() >= n;
  }
  ppp_bayes_tree::PppStatus lastStatus() {
    std::lock_guard<std::mutex> l(mutex);
    return statuses.empty() ? ppp_bayes_tree::PppStatus() : statuses.back();
  }
};

/// Waits until the node subscribes to both inputs.
inline bool waitForSubscribers(ros::Publisher& a, ros::Publisher& b, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::WallTime::now() < end) {
    if (a.getNumSubscribers() > 0 && b.getNumSubscribers() > 0) return true;
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

}  // namespace ppp_ros::test
