#pragma once
// InsOdometry: the GNSS/INS filter's state carried at the IMU rate between GNSS
// epochs (the odometry of the PPP node, ros/ins_odometry.h, and of the real-time
// benchmark ppp_bench_ins_realtime). After each GNSS epoch the estimator's
// inertial state (inertial_state.h: the IMU's NavState in ECEF, the IMU bias and
// the 15-state INS error covariance; the EKF's, or the smoother's newest state
// with its marginal covariance) is taken; each later reading moves it by the INS
// mechanization (ecefInsStep, bias-corrected, each reading held from its time to
// the next one's as in the filter) and its covariance by the filter's error model.
// The readings that came before the epoch was processed (the epochs wait for
// corrections) are run through again without output, so the outputs never go
// back in time. A reading after a gap longer than the filter's
// max_imu_interval_s stops the odometry until the next epoch.
#include <deque>
#include <optional>

#include <Eigen/Core>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"

namespace ppp {

/// The IMU's state at one time with what the odometry needs.
struct InsState {
  GnssTime time;
  NavState nav;  // IMU origin and axes, ECEF
  ImuBias bias;
  Matrix15d covariance = Matrix15d::Zero();  // INS error (ins_error_state.h order)
  Eigen::Vector3d angular_rate_radps = Eigen::Vector3d::Zero();  // bias-corrected reading held, IMU axes
};

class InsOdometry {
 public:
  explicit InsOdometry(const InsEkfOptions& options) : options_(options) {}

  /// The filter's state after an epoch at `state.time` with `held` the last reading at or
  /// before it; runs through `later` (the readings after it already received) without output.
  void restart(const InsState& state, const std::optional<ImuSample>& held, const std::deque<ImuSample>& later);
  /// One new reading: the state at its time; nullopt without a state, for a reading not
  /// after the state, or after a gap (the odometry then stops until the next restart).
  std::optional<InsState> step(const ImuSample& reading);
  /// No more odometry (e.g. a fall-back to GNSS only), until a restart.
  void stop();
  const std::optional<InsState>& current() const { return state_; }

 private:
  bool advance(const ImuSample& reading);

  InsEkfOptions options_;
  std::optional<InsState> state_;
  std::optional<ImuSample> held_;
};

}  // namespace ppp
