#include "ppp_bayes_tree/ros/node_imu_input.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/ros/imu_conversions.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp_ros {
namespace {

/// The grade of the ros.imu.grade key (checked when the options were read).
ppp::ImuGrade gradeOf(const std::string& name) {
  const std::optional<ppp::ImuGrade> grade = ppp::imuGradeFromName(name);
  if (!grade) throw std::invalid_argument("ros.imu.grade: unknown IMU grade \"" + name + "\"");
  return *grade;
}

ppp::ImuInputScreenOptions screenOptions(const RosImuOptions& o) {
  ppp::ImuInputScreenOptions s;
  s.max_gap_s = o.max_gap_s;
  s.max_gnss_offset_s = o.max_gnss_offset_s;
  if (o.accel_full_scale_mps2 > 0.0) s.accel_full_scale_mps2 = o.accel_full_scale_mps2;
  if (o.gyro_full_scale_radps > 0.0) s.gyro_full_scale_radps = o.gyro_full_scale_radps;
  return s;
}

std::string stampText(const sensor_msgs::Imu& m) {
  std::ostringstream s;
  s << "stamp " << m.header.stamp.sec << "." << std::setw(9) << std::setfill('0') << m.header.stamp.nsec;
  return s.str();
}

std::map<ppp::ImuInputProblem, std::size_t> screenCounts(const ppp::ImuInputScreen& screen) {
  std::map<ppp::ImuInputProblem, std::size_t> counts;
  for (const auto& [problem, count] : screen.problems()) counts[problem] = count.count;
  return counts;
}

}  // namespace

Eigen::Matrix3d rotationFromRpyDeg(const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d rpy_rad = rpy_deg * ppp::kDegToRad;
  return ppp::rotationNedBody(rpy_rad.x(), rpy_rad.y(), rpy_rad.z());
}

ImuExtrinsics parameterExtrinsics(const RosImuOptions& options) {
  ImuExtrinsics e;
  e.translation_m = options.translation_m;
  e.rotation_base_imu = rotationFromRpyDeg(options.rotation_rpy_deg);
  return e;
}

namespace {

/// R_base_body of the filter's body frame: base_link's x forward, y left, z up turned into
/// x forward, y right, z down (a half turn about x).
Eigen::Matrix3d baseFromBody() { return Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal(); }

}  // namespace

ImuExtrinsics filterBodyExtrinsics(const ImuExtrinsics& imu) {
  ImuExtrinsics body;
  body.translation_m = imu.translation_m;
  body.rotation_base_imu = baseFromBody();
  return body;
}

Eigen::Matrix3d bodyFromImu(const ImuExtrinsics& imu) { return baseFromBody().transpose() * imu.rotation_base_imu; }

ppp::InsEkfOptions insOptions(const RosNodeOptions& o, const ImuExtrinsics& e, ppp::InsEkfOptions ins) {
  using A = RosImuOptions::StartAttitude;
  const RosImuOptions& imu = o.imu;
  const ImuExtrinsics body = filterBodyExtrinsics(e);
  ins.noise = ppp::imuNoisePreset(gradeOf(imu.grade));
  ins.lever_arm_body_m = body.rotation_base_imu.transpose() * (o.antenna_lever_arm_m - body.translation_m);
  ins.initial_velocity_ned_mps = ppp::rotationNedEnu() * imu.initial_velocity_enu_mps;
  ins.heading_alignment.min_horizontal_speed_mps = imu.heading_speed_mps;
  ins.process_noise_adaptation.enabled = imu.process_noise_adaptation;
  ins.gap_bridge_max_s = imu.gap_bridge_max_s;
  ins.initial_rotation_ecef_body.reset();
  ins.initial_rotation_ned_body.reset();
  ins.initial_heading_rad.reset();
  switch (imu.initial_attitude) {
    case A::Given:
      ins.initial_rotation_ned_body =
          ppp::rotationNedEnu() * rotationFromRpyDeg(imu.initial_rpy_deg) * body.rotation_base_imu;
      break;
    case A::LevelAtRest: {  // base_link's x axis (the body's) from north, clockwise
      const double yaw_rad = imu.initial_rpy_deg.z() * ppp::kDegToRad;
      ins.initial_heading_rad = std::atan2(std::cos(yaw_rad), std::sin(yaw_rad));
      break;
    }
    case A::AlignInMotion: break;  // neither: the estimators align in motion
  }
  return ins;
}

std::string imuMessageProblemText(ImuMessageProblem problem) {
  switch (problem) {
    case ImuMessageProblem::FieldNotGiven: return "field not given";
    case ImuMessageProblem::ExtrinsicsMissing: return "IMU extrinsics missing";
  }
  return "unknown";
}

std::string imuProblemField(ppp::ImuInputProblem problem) {
  switch (problem) {
    case ppp::ImuInputProblem::NonFinite:
    case ppp::ImuInputProblem::Saturated: return "linear_acceleration / angular_velocity";
    case ppp::ImuInputProblem::InGravityUnits: return "linear_acceleration";
    case ppp::ImuInputProblem::TimeBackwards:
    case ppp::ImuInputProblem::DuplicateTime:
    case ppp::ImuInputProblem::Gap:
    case ppp::ImuInputProblem::FarFromGnssTime: return "header.stamp";
  }
  return "message";
}

NodeImuInput::NodeImuInput(const RosNodeOptions& options, WarningSink warn)
    : options_(options.imu), warn_(std::move(warn)), screen_(screenOptions(options.imu)) {}

void NodeImuInput::reset() {
  screen_ = ppp::ImuInputScreen(screenOptions(options_));
  pending_.clear();
  last_taken_.reset();
  newest_arrival_s_.reset();
  checked_gnss_time_.reset();
  time_base_far_ = false;
  problems_.clear();
  counters_ = {};
}

void NodeImuInput::note(ImuMessageProblem problem, const sensor_msgs::Imu& message, const std::string& field,
                        const std::string& detail) {
  ++counters_.rejected;
  ppp::ImuProblemCount& c = problems_[problem];
  const std::string text = "topic " + options_.topic + ", field " + field + ", " + stampText(message) + ": " +
                           imuMessageProblemText(problem) + ": " + detail + " (not used, counted)";
  if (c.count++ == 0) c.first = text;
  warn_("imu:" + imuMessageProblemText(problem), "ppp: IMU " + text);
}

void NodeImuInput::reportScreenProblems(const std::map<ppp::ImuInputProblem, std::size_t>& before,
                                        const sensor_msgs::Imu& message) {
  for (const auto& [problem, count] : screen_.problems()) {
    const auto it = before.find(problem);
    const std::size_t added = count.count - (it == before.end() ? 0 : it->second);
    if (added == 0) continue;
    if (problem != ppp::ImuInputProblem::Gap) counters_.rejected += added;
    warn_("imu:" + ppp::imuInputProblemText(problem),
          "ppp: IMU topic " + options_.topic + ", field " + imuProblemField(problem) + ", " + stampText(message) + ": " +
              ppp::imuInputProblemText(problem) + (problem == ppp::ImuInputProblem::Gap ? " (kept" : " (not used") +
              ", counted; first: " + count.first + ")");
  }
}

std::vector<ppp::ImuSample> NodeImuInput::receive(const sensor_msgs::Imu& message,
                                                  const std::optional<ppp::GnssTime>& gnss_time,
                                                  const std::optional<Eigen::Matrix3d>& body_from_imu,
                                                  double arrival_s) {
  ++counters_.received;
  if (message.linear_acceleration_covariance[0] == -1.0) {
    note(ImuMessageProblem::FieldNotGiven, message, "linear_acceleration",
         "linear_acceleration_covariance[0] = -1 (REP-145: no reading)");
    return {};
  }
  if (message.angular_velocity_covariance[0] == -1.0) {
    note(ImuMessageProblem::FieldNotGiven, message, "angular_velocity",
         "angular_velocity_covariance[0] = -1 (REP-145: no reading)");
    return {};
  }
  if (!body_from_imu) {
    note(ImuMessageProblem::ExtrinsicsMissing, message, "header.frame_id",
         "no pose of \"" + message.header.frame_id + "\" in base_link (ros.imu.extrinsics: tf)");
    return {};
  }
  // The time base: the first reading after each new GNSS epoch is compared with it (a GNSS
  // outage leaves the readings alone); once one is far, every reading is, until one is near.
  std::optional<ppp::GnssTime> check;
  if (gnss_time && (time_base_far_ || !checked_gnss_time_ || *gnss_time - *checked_gnss_time_ != 0.0))
    check = gnss_time;
  const auto before = screenCounts(screen_);
  std::vector<ppp::ImuSample> released = screen_.push(fromImuMessage(message), check);
  if (check) {
    checked_gnss_time_ = check;
    const auto far = before.find(ppp::ImuInputProblem::FarFromGnssTime);
    time_base_far_ = screen_.count(ppp::ImuInputProblem::FarFromGnssTime) > (far == before.end() ? 0 : far->second);
  }
  reportScreenProblems(before, message);
  buffer(released, *body_from_imu);
  if (!released.empty()) newest_arrival_s_ = arrival_s;
  return released;
}

ImuProgress NodeImuInput::progress() const {
  ImuProgress p;
  if (!pending_.empty()) p.newest_reading = pending_.back().time;
  else if (last_taken_) p.newest_reading = last_taken_->time;
  if (p.newest_reading) p.newest_arrival_s = newest_arrival_s_;
  return p;
}

void NodeImuInput::buffer(std::vector<ppp::ImuSample>& readings, const Eigen::Matrix3d& body_from_imu) {
  counters_.used += readings.size();
  for (ppp::ImuSample& r : readings) {
    r.specific_force_mps2 = body_from_imu * r.specific_force_mps2;
    r.angular_rate_radps = body_from_imu * r.angular_rate_radps;
    pending_.push_back(r);
  }
  while (!pending_.empty() && pending_.back().time - pending_.front().time > options_.buffer_s) {
    pending_.pop_front();
    ++counters_.dropped_old;
  }
}

std::vector<ppp::ImuSample> NodeImuInput::takeUpTo(const ppp::GnssTime& time) {
  std::vector<ppp::ImuSample> out;
  while (!pending_.empty() && pending_.front().time - time <= 0.0) {
    out.push_back(pending_.front());
    pending_.pop_front();
  }
  if (!out.empty()) last_taken_ = out.back();
  return out;
}

std::string NodeImuInput::problemSummary() const {
  std::string s;
  const auto add = [&s](std::size_t n, const std::string& what, const std::string& first) {
    if (n == 0) return;
    s += (s.empty() ? "" : "; ") + std::to_string(n) + " " + what + " (first: " + first + ")";
  };
  for (const auto& [problem, c] : screen_.problems()) add(c.count, ppp::imuInputProblemText(problem), c.first);
  for (const auto& [problem, c] : problems_) add(c.count, imuMessageProblemText(problem), c.first);
  return s.empty() ? "none" : "topic " + options_.topic + ": " + s;
}

}  // namespace ppp_ros
