#pragma once
// PppInsSmoother: tightly coupled GNSS/INS in the incremental smoother (iSAM2), the
// smoother sibling of the GNSS/INS EKF (PppInsEkf), registered as "smoother_ins".
// It is the PPP smoother (PppSmoother: receiver states with ZWD and clocks, one phase
// bias per arc, the same code and phase factors, postfit check, fixed lag, memory
// bound, restarts and PPP-AR with held integers) with, per state k, two more
// variables and their factors:
// - a NavState n_k (attitude R_ecef_body, velocity, position of the IMU origin in
//   ECEF; a manifold variable, nav_state_value.h) and an IMU bias i_k ([accel; gyro]);
// - between consecutive states the IMU factor of the readings in between, preintegrated
//   on the manifold (Forster, Carlone, Dellaert, Scaramuzza, "On-manifold
//   preintegration for real-time visual-inertial odometry", IEEE T-RO 33(1), 2017;
//   ImuSmootherFactor, with the Earth's rotation) and the bias random walk;
// - the receiver state's position tied to the antenna of n_k, p + R lever_arm, by a
//   stiff factor (AntennaPositionFactor, sigma kAntennaTieSigma_m), so that the code
//   and phase factors act on the pose through the lever arm; the position random walk
//   of the GNSS-only smoother is replaced by the IMU factor (its sigma is made
//   uninformative).
// Start: the code least squares position (as the PPP smoother), the attitude as the
// EKF (InsEkfOptions: given, or a given heading and the levelling of the readings up
// to the start), the velocity of the options; priors with the options' sigmas (the
// NavState position through the receiver state's prior). Through a GNSS outage (epochs
// without a solution) no state is added; the next solved epoch links to the last state
// by one IMU factor over the whole gap, and navState() is the dead-reckoned state of
// the last epoch. Readings that do not cover the interval (a gap longer than
// max_imu_interval_s, or none at the last state) end the epoch with NoImuReadings.
// inertialState() carries the INS error covariance in the EKF's error state
// (ins_error_state.h: [dtheta; dv; dp; dba; dbg], the attitude error on the right, in
// the body frame, as the NavState tangent): after a solved epoch the joint marginal
// covariance of the newest NavState and bias from the Bayes tree, moved from the
// linearization point to the estimate; after an epoch without a solution that one
// propagated along the readings with the EKF's error model to the dead-reckoned state.
// The attitude quality is the EKF's (insAttitudeQuality) of that covariance; the start
// attitude is given or levelled with a given heading, so the alignment is "aligned".
#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_coverage.h"
#include "ppp_bayes_tree/navigation/imu_preintegration.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"

namespace ppp {

class PppInsSmoother : public PppSmoother {
 public:
  /// Sigma of the tie between the receiver state's position and the antenna [m].
  static constexpr double kAntennaTieSigma_m = 1e-4;
  /// Sigma of the position random walk between receiver states (uninformative: the
  /// IMU factor carries the motion) [m].
  static constexpr double kFreePositionSigma_m = 1e4;

  /// From the estimator options (the registry's factory, estimator_registry.h).
  explicit PppInsSmoother(const EstimatorOptions& options);

  std::string name() const override { return "smoother_ins"; }
  /// navState() at navTime(), its bias, antenna, INS error covariance and attitude quality
  /// (see above); nullopt before the start.
  std::optional<InertialState> inertialState() const override;

  /// The state of the IMU at the last epoch: the filtered one after a solved epoch,
  /// the dead-reckoned one (IMU only, from the last state) after an epoch without a
  /// solution; nullopt before the start.
  const std::optional<NavState>& navState() const { return nav_; }
  /// The epoch navState() is at; nullopt before the start.
  const std::optional<GnssTime>& navTime() const { return nav_time_; }
  const ImuBias& imuBias() const { return bias_; }
  /// The INS error covariance of navState() (ins_error_state.h order); nullopt before a
  /// solved epoch, or when the readings since the newest state do not reach navTime().
  std::optional<Matrix15d> errorCovariance() const;
  /// The antenna position of navState(), ECEF [m].
  std::optional<Eigen::Vector3d> antennaPosition() const;
  /// The smoothed NavState of state `index` while it is in the graph.
  std::optional<NavState> smoothedNavState(std::uint32_t index) const;
  const InsEkfOptions& insOptions() const { return ins_; }
  /// The IMU readings kept (for the next IMU factor or a start), and how many were
  /// dropped as no longer usable (before the start, or after a gap from the newest state).
  std::size_t bufferedReadings() const { return readings_.size(); }
  std::size_t droppedReadings() const { return dropped_readings_; }

  static smoother::Key navKey(std::uint32_t index) { return smoother::symbolKey(kNavStateSymbol, index); }
  static smoother::Key imuBiasKey(std::uint32_t index) { return smoother::symbolKey(kImuBiasSymbol, index); }

 protected:
  void receiveEpochInput(const EstimatorEpochInput& input) override;
  ReceiverState predict(double dt_s, bool first, const std::optional<ReceiverState>& start) override;
  bool solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) override;
  void finishEpoch(EstimatorEpochResult& result) const override;

  double positionProcessSigma_m(double /*dt_s*/) const override { return kFreePositionSigma_m; }
  void addInertialFactors(const EpochSolveInput& in, std::uint32_t index, smoother::NonlinearFactorGraph& factors,
                          smoother::Values& values, smoother::KeyVector& keys) const override;
  void addRestartInertialFactors(std::uint32_t index, smoother::NonlinearFactorGraph& factors,
                                 smoother::Values& values, smoother::KeyVector& newest) const override;

 private:
  bool startNav(const ReceiverState& start);
  bool preintegrateTo(const GnssTime& time);
  void addStartPriors(std::uint32_t index, const NavState& nav, const ImuBias& bias,
                      smoother::NonlinearFactorGraph& factors, smoother::Values& values) const;
  void keepReadingsFrom(const GnssTime& time);
  /// Drops (and counts) the readings no interval can use any more: before the start, and
  /// once the readings from the newest state have a gap no later reading closes, those
  /// before the last one at or before this epoch (a start holds that one).
  void dropUnusableReadings();
  /// The newest state's covariance from the Bayes tree (after a solved epoch).
  void keepNewestCovariance(std::uint32_t index);
  /// broken_ is of the newest state only.
  void forgetGapOfAnOlderState();

  InsEkfOptions ins_;
  std::vector<ImuSample> input_readings_;  // this epoch's input
  std::vector<ImuSample> readings_;        // since the last state (the one held at its time first)
  GnssTime epoch_time_;
  std::optional<std::pair<NoSolutionReason, std::string>> epoch_problem_;
  std::optional<NavState> nav_;            // see navState()
  std::optional<GnssTime> nav_time_;       // see navTime()
  ImuBias bias_;
  std::optional<NavState> last_nav_;       // the newest state's estimate, read at this epoch's prediction
  ImuBias last_bias_;
  std::optional<ImuPreintegration> pim_;   // from the newest state to this epoch
  std::size_t dropped_readings_ = 0;       // see droppedReadings()
  std::optional<ImuCoverage> broken_;      // a gap from the newest state no later reading closes
  /// The newest state with its INS error covariance (keepNewestCovariance).
  struct CovariantState {
    GnssTime time;
    NavState nav;
    ImuBias bias;
    Matrix15d covariance = Matrix15d::Zero();
  };
  std::optional<CovariantState> newest_covariance_;
};

}  // namespace ppp
