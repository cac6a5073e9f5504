#pragma once
// Messages and a warning sink for the tests of the node's parts (test_node_*.cpp), built field by field.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <boost/make_shared.hpp>

#include "ppp_bayes_tree/GnssObservations.h"
#include "ppp_bayes_tree/PreciseCorrections.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/ros/throttled_warnings.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace node_test {

/// The warnings a part would log, in order.
struct Warnings {
  std::vector<std::pair<std::string, std::string>> logged;
  ppp_ros::WarningSink sink() {
    return [this](const std::string& c, const std::string& t) { logged.emplace_back(c, t); };
  }
  bool has(const std::string& category, const std::string& text_part) const {
    for (const auto& [c, t] : logged)
      if (c == category && t.find(text_part) != std::string::npos) return true;
    return false;
  }
};

/// A sink for warnings a test does not look at.
inline ppp_ros::WarningSink ignoreWarnings() {
  return [](const std::string&, const std::string&) {};
}

/// 2026-05-13 00:00:00 GPST (GPS week 2418, Wednesday).
inline ppp::GnssTime day() { return ppp::GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0}); }

/// An observation message at `t` with `satellites` (default) entries and header.seq `seq`.
inline ppp_bayes_tree::GnssObservations::ConstPtr observations(const ppp::GnssTime& t, std::uint32_t seq,
                                                               std::size_t satellites = 1) {
  auto msg = boost::make_shared<ppp_bayes_tree::GnssObservations>();
  const ppp_ros::MessageTime m = ppp_ros::toMessageTime(t);
  msg->header.seq = seq;
  msg->header.stamp = ppp_ros::utcStamp(t);
  msg->week = m.week;
  msg->seconds_of_week = m.seconds_of_week;
  msg->time_system = m.time_system;
  msg->receiver_clock_offset_s = std::numeric_limits<double>::quiet_NaN();
  msg->satellites.resize(satellites);
  return msg;
}

/// A correction batch at `t` with one satellite (G05: an orbit 26,560 km from the geocentre, a clock).
inline ppp_bayes_tree::PreciseCorrections corrections(const ppp::GnssTime& t, std::uint32_t seq,
                                                      const std::string& satellite = "G05") {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  ppp_bayes_tree::PreciseCorrections msg;
  const ppp_ros::MessageTime m = ppp_ros::toMessageTime(t);
  msg.header.seq = seq;
  msg.header.stamp = ppp_ros::utcStamp(t);
  msg.week = m.week;
  msg.seconds_of_week = m.seconds_of_week;
  msg.time_system = m.time_system;
  ppp_bayes_tree::SatelliteCorrection s;
  s.satellite = satellite;
  s.position_ecef_m.x = 26.56e6;
  s.velocity_ecef_mps.x = s.velocity_ecef_mps.y = s.velocity_ecef_mps.z = kNaN;
  s.clock_bias_s = 1e-4;
  s.clock_drift_s_per_s = s.position_sigma_m = s.velocity_sigma_mps = s.clock_bias_sigma_s =
      s.clock_drift_sigma_s_per_s = kNaN;
  msg.satellites.push_back(s);
  return msg;
}

}  // namespace node_test
