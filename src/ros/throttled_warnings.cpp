#include "ppp_bayes_tree/ros/throttled_warnings.h"

#include <ros/console.h>

namespace ppp_ros {

bool ThrottledWarnings::warn(const std::string& category, const std::string& text) {
  const ros::WallTime now = ros::WallTime::now();
  auto it = last_warning_.find(category);
  if (it != last_warning_.end() && (now - it->second).toSec() < kInterval_s) return false;
  last_warning_[category] = now;
  ROS_WARN_STREAM(text);
  return true;
}

}  // namespace ppp_ros
