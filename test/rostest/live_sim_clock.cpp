// rostest, live input under sim time (launch/live.launch example c): with
// use_sim_time the ROS clock of a node is zero until its first /clock message, and a
// replayed bag's first messages can reach it before that (separate connections). The
// test publishes week-rollover-STR24.rtcm3 as rtcm_msgs/Message chunks (as
// live_rtcm_launch) to both nodes of live.launch (example b, live_str24.yaml,
// use_sim_time true): the first kBeforeClock chunks with no /clock at all, then a
// /clock message before each further chunk, advancing as rosbag play's does. Each
// node must hold the early chunks (its "live streams" diagnostic counts them: exactly
// kBeforeClock per node) and hand them on stamped with the first valid time, never
// zero, and its fixes must equal ppp_solve's (EKF; smoother filtered) epoch by epoch
// to 1 mm, the epochs of the held chunks included.
#include <rosgraph_msgs/Clock.h>


#include "rostest/live_support.h"

namespace {

constexpr std::size_t kBeforeClock = 300;  // about the first 50 epochs of the recording

}  // namespace

TEST(LiveSimClock, ChunksBeforeTheFirstClockAreHeldAndTheFixesEqualPppSolve) {
  PPP_REQUIRE_SHARED_DATA();
  using namespace ppp_ros::test;
  const std::string rtcm = str24Recording();
  PppSolveBoth offline;
  ASSERT_NO_FATAL_FAILURE(solveStr24Live("live_sim_clock", &offline));

  std::vector<StreamMessage> messages =
      rtcmChunkMessages(ppp::test::readFileBytes(rtcm), 2718);
  ASSERT_GT(messages.size(), 2 * kBeforeClock);

  ros::NodeHandle nh;
  LiveLaunchOutputs out;
  out.subscribe(nh);
  // The held count of each node's live streams diagnostic (the largest value seen).
  std::mutex held_mutex;
  std::map<std::string, std::size_t> held;  // diagnostic status name -> messages held
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 1000, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> l(held_mutex);
        for (const auto& s : m->status)
          for (const auto& kv : s.values)
            if (kv.key.find("messages held until the ROS clock was valid") != std::string::npos)
              held[s.name + " [" + s.hardware_id + "]"] =
                  std::max<std::size_t>(held[s.name + " [" + s.hardware_id + "]"], std::stoul(kv.value));
      });
  ros::Publisher clock = nh.advertise<rosgraph_msgs::Clock>("/clock", 100);
  ros::Publisher receiver = messages.front().message.advertise(nh, "/gnss/receiver", 100000);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
  while ((receiver.getNumSubscribers() < 2 || clock.getNumSubscribers() < 2) && ros::WallTime::now() < end)
    ros::WallDuration(0.05).sleep();
  ASSERT_GE(receiver.getNumSubscribers(), 2u);
  ros::WallDuration(0.5).sleep();  // connections settle
  for (std::size_t i = 0; i < kBeforeClock; ++i) {
    receiver.publish(messages[i].message);
    ros::WallDuration(0.003).sleep();
  }
  ros::WallDuration(1.0).sleep();  // the nodes have them, with no clock yet
  // Then a clock as rosbag play --clock gives one: a time, advancing with the data.
  ros::Time sim(1531612200, 0);  // 2018-07-14 23:50 UTC, the recording's start
  {
    rosgraph_msgs::Clock c;
    c.clock = sim;
    clock.publish(c);
    ros::WallDuration(0.5).sleep();  // the first clock reaches the nodes before the next chunk
  }
  for (std::size_t i = kBeforeClock; i < messages.size(); ++i) {
    rosgraph_msgs::Clock c;
    c.clock = sim;
    clock.publish(c);
    receiver.publish(messages[i].message);
    sim += ros::Duration(0.003);
    ros::WallDuration(0.003).sleep();
  }
  // The clock goes on after the data (the nodes' timers and diagnostics run on it).
  for (int i = 0; i < 300; ++i) {
    rosgraph_msgs::Clock c;
    c.clock = sim;
    clock.publish(c);
    sim += ros::Duration(0.1);
    ros::WallDuration(0.02).sleep();
  }
  waitForFixes(out.ekf, offline.ekf.size() - 1, 30.0);
  waitForFixes(out.smoother, offline.smoother_filtered.size() - 1, 30.0);
  out.expectEqualTo(offline, "rtcm_msgs/Message chunks under sim time, the first " + std::to_string(kBeforeClock) +
                                 " before any /clock");
  std::lock_guard<std::mutex> l(held_mutex);
  std::size_t nodes = 0;
  for (const auto& [name, n] : held) {
    std::printf("[ figures  ] %s: %zu messages held until the clock was valid\n", name.c_str(), n);
    EXPECT_EQ(n, kBeforeClock) << name;
    ++nodes;
  }
  EXPECT_EQ(nodes, 2u) << "the live streams diagnostic of both nodes";
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_sim_clock"); }
