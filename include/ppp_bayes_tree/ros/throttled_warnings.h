#pragma once
// The node's warnings: each category logged the first time, then at most every
// 10 s (wall clock); what it warns about is counted elsewhere always. The node's
// parts (node_inputs.h, node_outputs.h) take a WarningSink, so that a test can
// read what they would log.
#include <functional>
#include <map>
#include <string>

#include <ros/time.h>

namespace ppp_ros {

/// (category, text): the category is the throttling key, the text the log line.
using WarningSink = std::function<void(const std::string& category, const std::string& text)>;

class ThrottledWarnings {
 public:
  static constexpr double kInterval_s = 10.0;
  /// True when `text` was logged (ROS_WARN), false when its category is within its interval.
  bool warn(const std::string& category, const std::string& text);
  WarningSink sink() {
    return [this](const std::string& category, const std::string& text) { warn(category, text); };
  }

 private:
  std::map<std::string, ros::WallTime> last_warning_;
};

}  // namespace ppp_ros
