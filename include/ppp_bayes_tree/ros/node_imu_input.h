#pragma once
// NodeImuInput: the IMU input of the PPP node (ppp_node.h) when its estimator has
// inertial states (the registry's EstimatedState::GnssInertial: ekf_ins, smoother_ins).
// sensor_msgs/Imu messages on ros.imu.topic (REP-145: the IMU's own frame,
// specific force and angular rate) are checked for what the message itself says
// (a field marked "not given" by covariance[0] = -1), then screened by
// ppp::ImuInputScreen (non-finite, time going backwards, duplicates, gaps,
// saturation, accelerations in g, a time base far from the GNSS epochs); each
// problem is counted with its first example naming the topic, field and stamp.
// Readings arriving before the IMU extrinsics are known (ros.imu.extrinsics: tf
// and no transform yet) are not used and counted.
// The accepted readings wait in a buffer until a GNSS epoch takes those up to its
// time (EstimatorEpochInput::imu, as ppp_solve hands them on); the readings after
// the last epoch taken stay for the odometry at IMU rate (ins_odometry.h). The newest
// accepted reading and its arrival are what the held GNSS epochs wait on (progress(),
// imu_epoch_hold.h).
// Also here: the IMU extrinsics and the GNSS/INS filter's options from ros.imu.
#include <cstddef>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <sensor_msgs/Imu.h>

#include "ppp_bayes_tree/navigation/imu_input_screen.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"
#include "ppp_bayes_tree/ros/imu_epoch_hold.h"
#include "ppp_bayes_tree/ros/node_options.h"
#include "ppp_bayes_tree/ros/throttled_warnings.h"

namespace ppp_ros {

/// R = Rz(yaw) Ry(pitch) Rx(roll) from the parameters' [roll, pitch, yaw] in degrees: the
/// core's Euler composition (ppp::rotationNedBody, radians), here between any two frames.
Eigen::Matrix3d rotationFromRpyDeg(const Eigen::Vector3d& rpy_deg);

/// The IMU's pose in base_link: its origin [m] and its axes (R_base_imu).
struct ImuExtrinsics {
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation_base_imu = Eigen::Matrix3d::Identity();
};
/// The extrinsics of the ros.imu parameters (translation_m, rotation_rpy_deg).
ImuExtrinsics parameterExtrinsics(const RosImuOptions& options);

/// The GNSS/INS filter's body frame: at the IMU's origin, with base_link's axes turned
/// forward-right-down (x forward, y right, z down: the body frame of ppp_solve --imu after
/// --imu-rotation), whatever the IMU's mounting. The readings are turned into it before
/// the filter and the odometry see them, so that the filter's x axis is base_link's forward
/// axis (the heading aligned in motion is the course of base_link's x axis). Its pose in base_link.
ImuExtrinsics filterBodyExtrinsics(const ImuExtrinsics& imu);
/// R_body_imu: turns an IMU reading into the filter's body axes (filterBodyExtrinsics).
Eigen::Matrix3d bodyFromImu(const ImuExtrinsics& imu);

/// The GNSS/INS filter's options from ros.imu on top of `base`: the grade's
/// noise; the lever arm in the filter's body frame (antenna minus IMU origin, from
/// ros.frames.antenna_lever_arm_m and the extrinsics; filterBodyExtrinsics); the start
/// attitude (base_link in the map, ENU, turned into R_ned_body), with level_at_rest the
/// heading of base_link's x axis (roll and pitch levelled by the filter), with
/// align_in_motion neither (the estimators level at the latest static interval and take the
/// heading from the course over ground, from heading_speed_mps on); the start velocity
/// (ENU into NED).
ppp::InsEkfOptions insOptions(const RosNodeOptions& options, const ImuExtrinsics& extrinsics,
                              ppp::InsEkfOptions base = {});

/// The problems of the node's IMU input beyond the screen's.
enum class ImuMessageProblem {
  FieldNotGiven,       ///< linear_acceleration or angular_velocity marked not given (covariance[0] = -1)
  ExtrinsicsMissing,   ///< the IMU's pose in base_link is not known (no TF yet): not used
};
/// "field not given", "IMU extrinsics missing".
std::string imuMessageProblemText(ImuMessageProblem problem);

/// The IMU input's counts since the start (or the last reset).
struct ImuInputCounters {
  std::size_t received = 0;  ///< messages
  std::size_t used = 0;      ///< readings accepted (released by the screen)
  std::size_t rejected = 0;  ///< messages not used (the screen's refusals and the node's problems)
  std::size_t dropped_old = 0;  ///< accepted readings dropped from a full buffer (ros.imu.buffer_s)
};

class NodeImuInput {
 public:
  NodeImuInput(const RosNodeOptions& options, WarningSink warn);

  /// One message. `gnss_time`: the newest GNSS epoch received (the time-base check: the
  /// first reading after each new epoch is compared with it, so that a GNSS outage leaves
  /// the readings alone; after a far one every reading is, until one is near again);
  /// `body_from_imu`: R_body_imu (bodyFromImu), nullopt while the IMU's pose in base_link is
  /// missing; `arrival_s`: ROS time of the message's arrival [s] (progress()). The accepted
  /// readings are turned into the filter's body axes. Returns the readings accepted by this
  /// message, in time order (none while the screen holds the first readings to decide the
  /// units, then those).
  std::vector<ppp::ImuSample> receive(const sensor_msgs::Imu& message, const std::optional<ppp::GnssTime>& gnss_time,
                                      const std::optional<Eigen::Matrix3d>& body_from_imu, double arrival_s);
  /// The buffered readings up to `time` (the epoch's EstimatorEpochInput::imu), in time
  /// order; they leave the buffer, the last one is kept as lastTaken().
  std::vector<ppp::ImuSample> takeUpTo(const ppp::GnssTime& time);
  /// The readings after the last epoch taken (time order).
  const std::deque<ppp::ImuSample>& pending() const { return pending_; }
  /// The last reading taken by an epoch (held from its time until the next one).
  const std::optional<ppp::ImuSample>& lastTaken() const { return last_taken_; }
  /// The newest accepted reading's time (the newest pending, else the last taken) and the
  /// arrival of the message that brought it; empty before the first and after reset().
  ImuProgress progress() const;
  /// Starts afresh (an estimator reset after a time jump): buffer, screen and counts.
  void reset();

  const ImuInputCounters& counters() const { return counters_; }
  const ppp::ImuInputScreen& screen() const { return screen_; }
  /// The node's own problems with their count and first example.
  const std::map<ImuMessageProblem, ppp::ImuProblemCount>& problems() const { return problems_; }
  /// Every problem seen, one line: "topic imu/data: 3 saturated (first: ...); ...".
  std::string problemSummary() const;
  const std::string& topic() const { return options_.topic; }

 private:
  void note(ImuMessageProblem problem, const sensor_msgs::Imu& message, const std::string& field,
            const std::string& detail);
  /// Warns about the screen's problems that this message added (named with the topic and field).
  void reportScreenProblems(const std::map<ppp::ImuInputProblem, std::size_t>& before, const sensor_msgs::Imu& message);
  void buffer(std::vector<ppp::ImuSample>& readings, const Eigen::Matrix3d& body_from_imu);

  RosImuOptions options_;
  WarningSink warn_;
  ppp::ImuInputScreen screen_;
  std::deque<ppp::ImuSample> pending_;
  std::optional<ppp::ImuSample> last_taken_;
  std::optional<double> newest_arrival_s_;  // ROS time [s] of the message of the newest accepted reading
  std::optional<ppp::GnssTime> checked_gnss_time_;  // the GNSS epoch the time base was last compared with
  bool time_base_far_ = false;                      // the last comparison found the stamps far from it
  std::map<ImuMessageProblem, ppp::ImuProblemCount> problems_;
  ImuInputCounters counters_;
};

/// The message field a screen problem concerns ("header.stamp", "linear_acceleration", ...).
std::string imuProblemField(ppp::ImuInputProblem problem);

}  // namespace ppp_ros
