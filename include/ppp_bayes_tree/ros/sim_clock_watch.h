#pragma once
// SimClockWatch: says why a node is silent when /use_sim_time is true and no /clock
// arrives (a /use_sim_time left true by an earlier bag replay, a player not started).
// With simulated time and no clock, ROS time stays 0: ROS timers never fire, so the
// node publishes no status and no diagnostics. The watch runs on a WALL-clock timer:
// it says so at start (INFO) and warns every `period_s` of wall time until the first
// /clock arrives (then it says so once and stops). Without use_sim_time it does nothing.
#include <string>

#include <ros/ros.h>

namespace ppp_ros {

class SimClockWatch {
 public:
  /// `node_name` prefixes the messages; starts the wall timer on `nh`'s callback queue.
  SimClockWatch(ros::NodeHandle& nh, std::string node_name, double period_s = 10.0);
  /// The warning text after `waited_s` of wall time without a clock.
  static std::string waitingText(const std::string& node_name, double waited_s);

 private:
  void check();
  std::string node_name_;
  ros::WallTime start_;
  ros::WallTimer timer_;
};

}  // namespace ppp_ros
