#pragma once
// The ROS node's outputs (ppp_node.h), built from an epoch's record: the PppStatus
// (with its fix-state fields), ppp/odometry/filtered, ppp/fix (NavSatFix), the TF
// map -> base_link (or map -> odom), ppp/path/filtered, the smoother's
// ppp/odometry/smoothed and ppp/path/smoothed and, with a fixed lag, the smoothed
// trajectory file. The messages are returned; the node publishes them, so this part
// runs without a ROS master. It keeps what the outputs need between epochs: the map
// datum, the attitude of each epoch (lever arm), the paths and the fix figures.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/NavSatFix.h>

#include "ppp_bayes_tree/PppStatus.h"
#include "ppp_bayes_tree/evaluation/lagged_trajectory_output.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_estimator.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ros/node_options.h"
#include "ppp_bayes_tree/ros/phase_bias_choice.h"
#include "ppp_bayes_tree/ros/throttled_warnings.h"

namespace ppp_ros {

/// Solution state of one epoch from the position sigmas (ENU) and thresholds.
std::uint8_t solutionState(bool solved, const Eigen::Vector3d& sigma_enu_m, const RosNodeOptions& options);
std::string solutionStateText(std::uint8_t state);
/// The epoch has a position (and its covariance) to publish.
bool solvedEpoch(const ppp::PppEpochRecord& rec);

/// A TF message parent -> child.
geometry_msgs::TransformStamped transformMsg(const std::string& parent, const std::string& child, const ros::Time& stamp,
                                             const Eigen::Vector3d& translation_m, const Eigen::Quaterniond& rotation);
/// The antenna's NavSatFix (REP-145): geodetic position, ENU covariance [m^2] at the antenna,
/// STATUS_GBAS_FIX for FIX_FIXED, else STATUS_FIX (doc/ros_ambiguity_resolution.md "Outputs").
sensor_msgs::NavSatFix navSatFix(const Eigen::Vector3d& position_ecef_m, const Eigen::Matrix3d& covariance_ecef_m2,
                                 std::uint8_t fix_state, const ros::Time& stamp, const std::string& antenna_frame);

/// A SetDatum request: the datum (ECEF [m]) and "datum set", or no datum and why it is
/// refused (valid: latitude in [-90, 90] deg, finite longitude, |height| < 1000 km).
struct DatumRequest {
  std::optional<Eigen::Vector3d> position_ecef_m;
  std::string message;
};
DatumRequest datumRequest(double latitude_deg, double longitude_deg, double height_m);
/// The datum of ros.datum (mode configured), ECEF [m]; nullopt with first_fix.
std::optional<Eigen::Vector3d> configuredDatum(const RosNodeOptions& options);

/// What the processing of one epoch adds to its status beyond the record.
struct EpochFigures {
  double update_time_s = 0.0;
  double correction_latency_s = 0.0;  // epoch time minus the newest correction batch (NaN: none)
  double corrections_stale_s = 0.0;   // NaN: not known
  std::uint8_t product_mode = ppp_bayes_tree::PppStatus::PRODUCTS_PRECISE;
  std::string product_mode_text;
  std::uint32_t variables_reeliminated = 0;
  std::vector<ppp::ArcId> active_arcs;
  std::vector<std::string> warnings;  // receiver antenna warnings
};

/// The attitude messages (ros.attitude.topic) and the epochs that had none.
struct AttitudeCounters {
  std::size_t received = 0, invalid = 0, epochs_without = 0;
};

/// The messages of one solved epoch.
struct SolutionMessages {
  nav_msgs::Odometry odometry;
  sensor_msgs::NavSatFix fix;
  std::optional<geometry_msgs::TransformStamped> tf;  // ros.frames.publish_tf
};

/// What the outputs count since the start (PppStatus counter fields of the outputs).
struct OutputCounters {
  std::uint32_t epochs_processed = 0;
  std::uint32_t epochs_not_published = 0;  // not after the last published one (in PppStatus::epochs_out_of_order)
  std::uint32_t corrections_late = 0;      // satellite-epochs without corrections in time
};

class NodeInputs;
/// The figures of one processed epoch: the inputs' (latency of the newest correction
/// batch, staleness, product mode), the estimator's (variables re-eliminated: the
/// EKF's whole state, the smoother's reported count; the active arcs), the
/// processor's receiver antenna `warnings` and the update time.
EpochFigures epochFigures(const NodeInputs& inputs, const ppp::PppEstimator& estimator, const ppp::ObsEpoch& epoch,
                          const ppp::PppEpochRecord& rec, double update_s, std::vector<std::string> warnings);

class NodeOutputs {
 public:
  NodeOutputs(const RosNodeOptions& options, WarningSink warn);

  // --- map datum and frames ---
  /// Sets the map datum; returns the static TF earth -> map.
  geometry_msgs::TransformStamped setDatum(const Eigen::Vector3d& position_ecef_m);
  bool hasDatum() const { return datum_ecef_m_.has_value(); }
  /// The datum (ECEF [m]; zero before one is set) and the rotation ENU <- ECEF at it.
  Eigen::Vector3d datumEcef() const { return datum_ecef_m_.value_or(Eigen::Vector3d::Zero()); }
  const Eigen::Matrix3d& enuFromEcef() const { return ecef_to_enu_; }
  /// The TF of a base_link pose in the map: map -> base_link, or map -> odom when another
  /// node publishes odom -> base_link (`odom_to_base`); nullopt without ros.frames.publish_tf.
  std::optional<geometry_msgs::TransformStamped> mapTransform(
      const ros::Time& stamp, const Eigen::Vector3d& position_m, const Eigen::Quaterniond& q_map_base,
      const std::optional<geometry_msgs::TransformStamped>& odom_to_base) const;
  /// The static TF base_link -> gnss_antenna (the lever arm, fixed in the body).
  geometry_msgs::TransformStamped leverArmTransform() const;

  // --- attitude (lever arm) ---
  /// REP-145: orientation_covariance[0] = -1 means no orientation: ignored (counted), as a
  /// non-unit quaternion or a zero stamp.
  void receiveAttitude(const sensor_msgs::Imu& msg);
  const AttitudeCounters& attitudeCounters() const { return attitude_counters_; }

  // --- status ---
  /// The status of the processed epoch at `time` (counted as processed; its satellites without
  /// corrections counted as late): the inputs' `counters` (NodeInputs::counters()) and the
  /// outputs' counters() with the record's satellites, sigmas, solution and fix state.
  /// Remembered as lastStatus(). A solved epoch needs the datum (setDatum) first.
  ppp_bayes_tree::PppStatus epochStatus(const ppp::GnssTime& time, const ppp::PppEpochRecord& rec, const ppp_bayes_tree::PppStatus& counters,
                                        const EpochFigures& figures, const PhaseBiasChoice& phase, bool ar_enabled);
  /// The status of an epoch without satellites (no solution; not counted as processed).
  ppp_bayes_tree::PppStatus emptyEpochStatus(const ppp::GnssTime& time, const ppp_bayes_tree::PppStatus& counters,
                                             double corrections_stale_s, const PhaseBiasChoice& phase, bool ar_enabled);
  const std::optional<ppp_bayes_tree::PppStatus>& lastStatus() const { return last_status_; }
  /// A processed epoch not after the last published one: not published, counted.
  void countNotPublished() { ++counters_.epochs_not_published; }
  const OutputCounters& counters() const { return counters_; }
  const std::optional<ppp::SmootherEpochDiagnostics>& lastSmoother() const { return last_smoother_; }

  // --- filtered outputs of a solved epoch (needs the datum) ---
  /// Odometry, NavSatFix and TF of the epoch (`odom_to_base`: odom -> base_link when another
  /// node publishes it: then the TF is map -> odom); the pose goes to the filtered path.
  SolutionMessages solution(const ppp::PppEpochRecord& rec, const ppp_bayes_tree::PppStatus& status,
                            const std::optional<geometry_msgs::TransformStamped>& odom_to_base);
  /// ppp/path/filtered stamped by its last pose (nullptr while empty).
  const nav_msgs::Path* filteredPath();

  // --- smoothed outputs (smoother node) ---
  /// The state at the lag boundary (or ros.smoothed.odometry_delay_s) after the epoch `newest`,
  /// each state once, in time order.
  std::optional<nav_msgs::Odometry> smoothedOdometry(const ppp::SmoothedTrajectoryProvider& smoother,
                                                     const ppp::GnssTime& newest);
  /// The whole trajectory re-read when epochs came since the last one (nullopt: nothing new).
  std::optional<nav_msgs::Path> smoothedPath(const ppp::SmoothedTrajectoryProvider& smoother);
  void markSmoothedStale() { smoothed_path_stale_ = true; }
  /// Fixed lag: the states leaving the window go to the output (file, recent path poses).
  void attachLaggedOutput(ppp::PppEstimator& estimator);
  /// Fixed lag: the rest of the window to the output (end, or before a reset).
  void finishLaggedOutput(ppp::PppEstimator& estimator);
  const ppp::LaggedTrajectoryOutput* laggedOutput() const { return lagged_output_.get(); }
  std::size_t smoothedPathPoses() const { return smoothed_path_poses_; }
  double smoothedPathRead_s() const { return smoothed_path_read_s_; }
  double smoothedPathReadMax_s() const { return smoothed_path_read_max_s_; }

  // --- reset ---
  /// The estimator was reset: paths, attitudes, smoothed index and fix figures start afresh.
  void resetTrajectory();
  /// A new datum: the filtered path is cleared, the smoothed one re-read in the new map frame.
  void clearPathsForDatum();

  // --- fix figures since the start or the last reset ---
  std::uint32_t epochsFixed() const { return epochs_fixed_; }
  std::uint32_t ambiguityReleases() const { return ambiguity_releases_; }
  const std::optional<ppp::GnssTime>& firstFixed() const { return first_fixed_; }
  /// First fixed minus first solved epoch [s], NaN before a fix.
  double timeToFirstFix_s() const;

 private:
  struct Attitude {
    ros::Time stamp;
    Eigen::Quaterniond q_map_base = Eigen::Quaterniond::Identity();
    std::array<double, 9> covariance{};  // orientation covariance of the Imu message [rad^2]
  };
  /// base_link pose in the map frame for an antenna position (ENU) at `stamp`.
  struct BodyPose {
    Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_map_base = Eigen::Quaterniond::Identity();
    const Attitude* attitude = nullptr;  // the attitude applied, if any
    geometry_msgs::Pose toMsg() const;
  };
  void attachAttitude(const ros::Time& stamp);
  BodyPose bodyPose(const Eigen::Vector3d& antenna_enu_m, const ros::Time& stamp) const;
  nav_msgs::Odometry odometry(const ros::Time& stamp, const BodyPose& pose, const Eigen::Matrix3d& cov_enu_m2) const;
  /// The fix state fields of the status from the epoch's record.
  void setFixState(const ppp::PppEpochRecord& rec, bool solved, const PhaseBiasChoice& phase, bool ar_enabled,
                   ppp_bayes_tree::PppStatus& s);
  /// The status's counter fields: the inputs' and the outputs'.
  ppp_bayes_tree::PppStatus withCounters(const ppp_bayes_tree::PppStatus& input_counters) const;
  /// The satellites used and rejected; returns those without corrections (late products).
  std::uint16_t setSatellites(const ppp::PppEpochRecord& rec, ppp_bayes_tree::PppStatus& s) const;
  /// The sigmas, troposphere and clock of a solved epoch.
  Eigen::Vector3d setSolution(const ppp::PppEpochRecord& rec, ppp_bayes_tree::PppStatus& s) const;

  RosNodeOptions options_;
  WarningSink warn_;
  // datum of the map frame
  std::optional<Eigen::Vector3d> datum_ecef_m_;
  Eigen::Matrix3d ecef_to_enu_ = Eigen::Matrix3d::Identity();
  nav_msgs::Path path_;
  // attitude (lever arm): the newest message, and the one applied to each epoch (by stamp)
  std::optional<Attitude> attitude_;
  std::map<ros::Time, Attitude> attitude_of_epoch_;
  bool lever_arm_note_logged_ = false;
  AttitudeCounters attitude_counters_;
  OutputCounters counters_;
  std::optional<ppp_bayes_tree::PppStatus> last_status_;
  std::optional<ppp::SmootherEpochDiagnostics> last_smoother_;  // of the last processed epoch
  // smoother outputs
  std::optional<std::uint32_t> last_smoothed_index_;  // newest state published on ppp/odometry/smoothed
  bool smoothed_path_stale_ = false;                   // epochs processed since the last path re-read
  double smoothed_path_read_s_ = 0.0, smoothed_path_read_max_s_ = 0.0;
  std::size_t smoothed_path_poses_ = 0;
  // Fixed lag (bounded memory): the states past the lag go to this output
  // (ros.smoothed.trajectory_csv, and the newest path_max_poses for ppp/path/smoothed);
  // the smoother keeps only its window.
  std::unique_ptr<ppp::LaggedTrajectoryOutput> lagged_output_;
  // ambiguity resolution: the fix figures since the start or the last reset
  std::uint32_t epochs_fixed_ = 0, ambiguity_releases_ = 0;
  std::optional<ppp::GnssTime> first_solved_, first_fixed_;
};

}  // namespace ppp_ros
