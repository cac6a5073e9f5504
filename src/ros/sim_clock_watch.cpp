#include "ppp_bayes_tree/ros/sim_clock_watch.h"

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp_ros {

SimClockWatch::SimClockWatch(ros::NodeHandle& nh, std::string node_name, double period_s)
    : node_name_(std::move(node_name)), start_(ros::WallTime::now()) {
  if (!ros::Time::isSimTime() || !ros::Time::now().isZero()) return;
  ROS_INFO_STREAM(node_name_ << ": /use_sim_time is true: waiting for /clock (nothing is processed before it; "
                             << "a warning every " << period_s << " s of wall time until it comes)");
  timer_ = nh.createWallTimer(ros::WallDuration(period_s), [this](const ros::WallTimerEvent&) { check(); });
}

std::string SimClockWatch::waitingText(const std::string& node_name, double waited_s) {
  return node_name + ": /use_sim_time is true and no /clock has arrived for " + ppp::format("%.0f", waited_s) +
         " s (wall): ROS time stands at 0, so nothing is processed or published (no status, no diagnostics). "
         "Start the bag player with --clock, or, for live input, clear a /use_sim_time left by an earlier replay "
         "(rosparam set /use_sim_time false) and restart the node";
}

void SimClockWatch::check() {
  if (!ros::Time::now().isZero()) {
    if (timer_.isValid()) {
      ROS_INFO_STREAM(node_name_ << ": /clock arrived after " << (ros::WallTime::now() - start_).toSec()
                                 << " s (wall); simulated time runs");
      timer_.stop();
    }
    return;
  }
  ROS_WARN_STREAM(waitingText(node_name_, (ros::WallTime::now() - start_).toSec()));
}

}  // namespace ppp_ros
