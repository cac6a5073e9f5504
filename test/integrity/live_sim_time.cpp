// rostest (live_sim_time.test): /use_sim_time is true and nothing publishes /clock, as
// after an earlier bag replay. Faulty phase (no clock): each node must warn on /rosout,
// on a wall-clock timer, that it waits for /clock, and publish no diagnostics (ROS time
// stands at 0). Clean phase (the test publishes /clock): each node says the clock
// arrived, and its diagnostics start.
#include <gtest/gtest.h>

#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <rosgraph_msgs/Log.h>

#include "rostest/live_support.h"

namespace {

struct Observed {
  std::mutex mutex;
  std::vector<rosgraph_msgs::Log> logs;
  std::set<std::string> diagnostic_names;  // status names seen on /diagnostics
  bool logged(const std::string& node, std::uint8_t level, const std::string& text) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& m : logs)
      if (m.name == node && m.level == level && m.msg.find(text) != std::string::npos) return true;
    return false;
  }
  bool diagnosed(const std::string& prefix) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& n : diagnostic_names)
      if (n.rfind(prefix, 0) == 0) return true;
    return false;
  }
};

bool waitUntil(const std::function<bool()>& done, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::WallTime::now() < end) {
    if (done()) return true;
    ros::WallDuration(0.1).sleep();
  }
  return done();
}

TEST(LiveSimTime, StaleUseSimTimeIsSaidUntilAClockComes) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::Time::isSimTime()) << "the .test sets /use_sim_time";
  Observed seen;
  ros::Subscriber rosout = nh.subscribe<rosgraph_msgs::Log>("/rosout", 1000, [&](const auto& m) {
    std::lock_guard<std::mutex> l(seen.mutex);
    seen.logs.push_back(*m);
  });
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 1000, [&](const auto& m) {
    std::lock_guard<std::mutex> l(seen.mutex);
    for (const auto& s : m->status) seen.diagnostic_names.insert(s.name);
  });
  const std::string wait_text = "/use_sim_time is true and no /clock has arrived";
  // Faulty: no clock. The warning comes every 10 s of wall time (the first after 10 s).
  for (const std::string node : {"/ppp_ekf_node", "/ppp_stream_node"}) {
    EXPECT_TRUE(waitUntil([&] { return seen.logged(node, rosgraph_msgs::Log::WARN, wait_text); }, 25.0))
        << node << " did not say that it waits for /clock";
  }
  EXPECT_FALSE(seen.diagnosed("ppp_ekf_node:")) << "diagnostics without a clock?";
  EXPECT_FALSE(seen.diagnosed("ppp_stream_node:")) << "diagnostics without a clock?";

  // Clean: a clock (as rosbag play --clock gives): the nodes say so and their diagnostics start.
  ros::Publisher clock = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  rosgraph_msgs::Clock c;
  c.clock = ros::Time(1000.0);
  const auto tick = [&] {
    c.clock += ros::Duration(0.1);
    clock.publish(c);
    return false;
  };
  ros::WallTimer ticker = nh.createWallTimer(ros::WallDuration(0.1), [&](const ros::WallTimerEvent&) { tick(); });
  for (const std::string node : {"/ppp_ekf_node", "/ppp_stream_node"}) {
    EXPECT_TRUE(waitUntil([&] { return seen.logged(node, rosgraph_msgs::Log::INFO, "/clock arrived"); }, 15.0))
        << node << " did not say that the clock arrived";
  }
  EXPECT_TRUE(waitUntil([&] { return seen.diagnosed("ppp_ekf_node:") && seen.diagnosed("ppp_stream_node:"); }, 15.0))
      << "no diagnostics after the clock came";
}

}  // namespace

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "integrity_live_sim_time"); }
