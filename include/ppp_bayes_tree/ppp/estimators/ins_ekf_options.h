#pragma once
// InsEkfOptions: what the GNSS/INS filter (PppInsEkf, ppp_ins_ekf.h) needs besides
// the GNSS options: the IMU's noise, the lever arm from the IMU to the antenna,
// the initial attitude and velocity, the a priori sigmas of the inertial states
// and the Doppler velocity update.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/ppp/estimators/ins_process_noise_adaptation.h"
#include "ppp_bayes_tree/ppp/model/doppler_velocity.h"
#include "ppp_bayes_tree/ppp/model/gap_bridge.h"

namespace ppp {

struct InsEkfOptions {
  /// The IMU's noise (a grade's preset, imu_noise.h); industrial MEMS unless set.
  ImuNoise noise = imuNoisePreset(ImuGrade::IndustrialMems);
  InsBiasModel bias_model;
  /// Antenna phase centre minus IMU origin, in the body frame [m].
  Eigen::Vector3d lever_arm_body_m = Eigen::Vector3d::Zero();
  /// The attitude at the start, R_ecef_body. Without it, with initial_heading_rad,
  /// roll and pitch come from levelling the readings up to the first epoch (at rest,
  /// ins_alignment.h). With neither, the heading is aligned in motion: roll and pitch
  /// from the latest static interval of the readings before the start, carried to
  /// the start by the gyros, the heading unknown (unaligned_heading_sigma_rad) until
  /// the course over ground of the filter's antenna track sets it (HeadingAlignment);
  /// with no static interval the filter does not start (no initial attitude).
  std::optional<Eigen::Matrix3d> initial_rotation_ecef_body;
  /// The attitude at the start in the local North-East-Down frame of the start
  /// position, R_ned_body (used when initial_rotation_ecef_body is not set; a
  /// node knows the local attitude before it knows the position).
  std::optional<Eigen::Matrix3d> initial_rotation_ned_body;
  /// Heading of the body x axis at the start, from north, clockwise [rad].
  std::optional<double> initial_heading_rad;
  /// The IMU's velocity at the start, ECEF [m/s] (zero: a start at rest).
  Eigen::Vector3d initial_velocity_ecef_mps = Eigen::Vector3d::Zero();
  /// The IMU's velocity at the start in the local NED frame [m/s]; when set it
  /// replaces initial_velocity_ecef_mps.
  std::optional<Eigen::Vector3d> initial_velocity_ned_mps;
  /// A priori sigmas of the attitude [rad] (each axis) and of the velocity [m/s].
  double initial_attitude_sigma_rad = 0.02;
  double initial_velocity_sigma_mps = 0.5;
  /// In-motion heading alignment (neither attitude nor heading given).
  struct HeadingAlignment {
    /// The course sets the heading once the horizontal speed reaches this [m/s].
    double min_horizontal_speed_mps = 0.5;
    /// The velocity is the antenna displacement over at least this interval [s].
    double course_interval_s = 1.0;
    /// Sigma of each horizontal component of that velocity [m/s]; the heading's
    /// sigma at alignment is this over the horizontal speed.
    double velocity_sigma_mps = 0.1;
    /// The heading's sigma before the alignment [rad].
    double unaligned_heading_sigma_rad = 1.0;
  } heading_alignment;
  /// The attitude is publishable (InsAttitudeQuality) when aligned and its tilt and
  /// heading sigmas are at most these [rad] (2 and 5 deg).
  double publish_tilt_sigma_rad = 0.0349;
  double publish_heading_sigma_rad = 0.0873;
  /// Readings further apart than this are a gap the INS cannot bridge [s].
  double max_imu_interval_s = 0.1;
  /// GNSS data gaps (time between two epochs) up to this long [s] do not end
  /// the arcs: at the first epoch after, each arc's slip is identified from the
  /// INS prediction (gap_bridge.h) and the arc goes on or ends; 0: every gap
  /// longer than the arc tracker's maximum ends the arcs. An arc whose slip tests
  /// fail after such a gap has its slip repaired first when the geometry-free
  /// identification is accepted (slip_repair.h, CycleSlipOptions::slip_repair).
  /// 90 s by default: an outage of 60 s leaves a data gap of 60 s plus the receiver's
  /// reacquisition; the repair, with the gap bridge choosing among its candidates,
  /// carries held integers over 30-s and 60-s outages without lock
  /// (doc/studies/ins_outages.md); 6 s was the default before the candidates, 61 s
  /// before a failing assignment cost ended the arc whose exclusion lowers it most
  /// (gap_bridge.h).
  double gap_bridge_max_s = 90.0;
  GapBridgeOptions gap_bridge;
  /// The Doppler velocity update (PppInsEkf): each epoch whose observations carry
  /// Doppler, the antenna velocity from them (doppler_velocity.h) updates the
  /// filter before the code and phase; on by default.
  DopplerVelocityOptions doppler;
  /// The process noise of a prediction inconsistent with the epoch's phases, scaled
  /// (ins_process_noise_adaptation.h); on by default, in both GNSS/INS estimators.
  ProcessNoiseAdaptationOptions process_noise_adaptation;

  /// Empty when valid; otherwise the first problem.
  std::string validate() const;
};

}  // namespace ppp
