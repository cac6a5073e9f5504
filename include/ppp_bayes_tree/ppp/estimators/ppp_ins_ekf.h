#pragma once
// PppInsEkf: the tightly coupled GNSS/INS error-state extended Kalman filter, in
// the estimator family (registered as "ekf_ins"). It uses the same PPP
// measurement model, front end and update as the EKF (PppEkf, whose seam it
// fills), so the two are comparable epoch by epoch.
//
// State: the 15-state INS error [attitude, velocity, position, accel bias, gyro
// bias] of ins_error_state.h (truth = nominal moved by the error), then the
// receiver states of the layout other than the position (zenith wet delay,
// clocks, gradients), then one phase bias per arc. The nominal NavState (IMU
// origin, ECEF) and ImuBias are propagated through the IMU readings between
// GNSS epochs by ecefInsStep (EcefInsMechanization's step), the error covariance
// by the discrete error model; the other states move as in the EKF.
//
// At a GNSS epoch the measurement model is evaluated at the antenna,
// p_antenna = p + R_ecef_body Exp(dtheta) lever_arm_body_m (+ dp), and its
// position Jacobian J maps to the error state by the chain rule:
// position columns J, attitude columns -J R Exp(dtheta) [lever_arm]x.
// After each update the error is fed back (closed loop: NavState moved, bias
// corrected, covariance J_reset P J_reset^T) and is zero again.
//
// The propagation is committed at every epoch, solved or not: through a GNSS
// outage the filter carries the position (navState(), antennaPosition()); the
// epoch reports no solution (too few satellites). Readings that do not cover
// the interval (a gap longer than max_imu_interval_s) end the inertial solution:
// that epoch and every later one report NoImuReadings (no GNSS-only fallback).
// The start is the code least squares of the first epoch (as the EKF) with the
// given attitude (or a given heading and the levelling of the readings up to the
// first epoch, at rest) and velocity (InsEkfOptions).
// With neither attitude nor heading the heading is aligned in motion
// (ins_in_motion_alignment.h, shared with PppInsSmoother): roll and pitch from the
// latest static interval before the start (carried to it by the gyros), the
// heading unknown (a large sigma) until the filter's antenna track moves faster
// than a threshold: its course over ground becomes the heading of the body x axis
// (a platform moving along x), with sigma velocity sigma / speed.
// attitudeQuality() (and EstimatorEpochResult::attitude) says when the attitude is
// good enough to publish.
//
// PPP-AR is the EKF's (PppEkf::resolveAmbiguities, ambiguity_resolution.h: wide
// lane, narrow lane, partial fixing, validation and hold, the same gates): the
// resolver works on the float filter [INS error; receiver states; biases], its
// biases from coreDim() on, and conditions a copy of it on the held integers.
// The fixed copy's INS error is the correction of the nominal state the integers
// imply: the fixed solution is the antenna position of the nominal moved by it
// (receiverStateAt), and fixedNavState() is the nominal and bias corrected by it
// as the closed-loop reset does after an update (applyInsErrorCorrection). The
// float filter and its nominal are not changed (as in the EKF: the hold's
// release test compares the held integers with the float).
//
// After a GNSS outage the INS prediction carries the position
// (predictedAntennaPosition()); a new arc's bias starts, as in the EKF, at phase
// minus code with the a priori sigma of stochastic.phase_bias, and the update
// puts it at phase minus the range of the predicted position, weighted by that
// position's covariance: the INS-aided re-initialisation of the biases (Rabbou &
// El-Rabbany 2015, GPS Solutions 19:601-609). A gap of at most
// InsEkfOptions::gap_bridge_max_s does not end the arcs (gapBridgeMax_s): at
// the first epoch after, the arcs back are tested against the prediction
// (verifyBridgedArcs; ins_gap_bridge.h, shared with PppInsSmoother, and
// gap_bridge.h: INS-aided cycle-slip identification, Du & Gao 2012, Sensors
// 12(11):14344-14362); an arc without a slip keeps its bias
// and held integers, any other ends as after a longer gap and starts again as a
// new arc (BridgedArcChanges::restartArc). Among the candidates of a slip repair
// the arc tracker could not make unique the test chooses, and the pipeline applies
// the chosen slip (BridgedArcChanges::chooseRepairCandidate; doc/studies/ins_outages.md).
//
// Doppler (InsEkfOptions::doppler, on by default; usesDoppler()): at each epoch
// whose observations carry Doppler, the antenna velocity and receiver clock drift
// are solved from the range rates at the predicted antenna position
// (doppler_velocity.h: weighted least squares, outlier screen), and that velocity,
// with its covariance, updates the filter right after the propagation, before
// the code and phase (a loosely coupled velocity update: the clock drift stays
// in the least squares). Its model is the antenna's velocity in ECEF,
// v_antenna = v + R_ecef_body (w_eb x lever_arm), w_eb = w_ib - R^T w_ie with
// w_ib the bias-corrected gyro reading at the epoch (the lever arm's velocity
// term of Groves 2013, 2nd ed., ch. 14, in ECEF). The update is committed with the propagation (solved epoch or not);
// at the start it is made on the start's filter. An innovation whose normalised
// square exceeds DopplerVelocityOptions::innovation_chi2 is refused.
// dopplerUpdate() says what this epoch's update did.
//
// Adaptive process noise (InsEkfOptions::process_noise_adaptation, on by default;
// ins_process_noise_adaptation.h, shared with PppInsSmoother): before the update, the
// phase innovations of the arcs with a bias are tested against the antenna's error
// added since the last GNSS update (the transition and process noise accumulated by
// the propagation since, and the INS error covariance after that update); when they
// are inconsistent, the process noise of that propagation is scaled (added to the
// prediction's covariance times lambda - 1) so that their normalised square is its
// expectation. processNoiseAdaptation() says what this epoch's test found.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_bias.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/ppp/estimators/ins_ekf_options.h"
#include "ppp_bayes_tree/ppp/estimators/ins_in_motion_alignment.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"

namespace ppp {

class PppInsEkf : public PppEkf {
 public:
  /// From the estimator options (the registry's factory, estimator_registry.h).
  explicit PppInsEkf(const EstimatorOptions& options);

  std::string name() const override { return "ekf_ins"; }
  std::optional<double> gapBridgeMax_s() const override;
  /// The nominal state, bias, antenna, attitude quality and INS error covariance; nullopt before the start.
  std::optional<InertialState> inertialState() const override;
  bool usesDoppler() const override { return ins_.doppler.enabled; }
  /// What the Doppler velocity update of the last epoch did.
  const DopplerUpdate& dopplerUpdate() const { return doppler_update_; }
  /// What this epoch's test of the prediction against the phases found, and the scale
  /// of the process noise it applied (ins_process_noise_adaptation.h).
  const ProcessNoiseScale& processNoiseAdaptation() const { return noise_scale_; }

  /// The nominal state of the IMU (ECEF) and the IMU bias (corrected after each update).
  const NavState& navState() const { return nominal_; }
  const ImuBias& imuBias() const { return bias_; }
  /// The antenna position of the nominal state, ECEF [m].
  Eigen::Vector3d antennaPosition() const;
  /// Time of the nominal state (the last epoch propagated to); nullopt before the start.
  std::optional<GnssTime> navTime() const { return lastTime(); }
  const InsEkfOptions& insOptions() const { return ins_; }
  /// The attitude's alignment state and sigmas (from the committed covariance).
  InsAttitudeQuality attitudeQuality() const;
  /// The nominal state (IMU, ECEF) and bias of this epoch's fixed solution: the
  /// float nominal moved by the fixed copy's INS error; nullopt when the epoch is
  /// not fixed (PPP-AR off, float, or no solution).
  const std::optional<NavState>& fixedNavState() const { return fixed_nominal_; }
  const std::optional<ImuBias>& fixedImuBias() const { return fixed_bias_; }
  std::optional<Eigen::Vector3d> predictedAntennaPosition() const override { return predicted_antenna_m_; }

  /// The antenna velocity (ECEF) at a nominal state moved by an INS error, with the
  /// gyro reading w_ib (bias-corrected by the nominal bias), and its Jacobian
  /// (3 x 15: velocity I, attitude -R [w_eb x l]x, gyro bias R [l]x; the Earth
  /// rate's attitude term, below 1e-5 m/s for a lever arm under 0.1 m, left out).
  static Eigen::Vector3d antennaVelocityAt(const NavState& nominal, const Eigen::Vector3d& lever_arm_body_m,
                                           const Eigen::Vector3d& gyro_radps, const Eigen::Matrix<double, 15, 1>& error);
  static Eigen::Matrix<double, 3, 15> antennaVelocityJacobian(const NavState& nominal,
                                                              const Eigen::Vector3d& lever_arm_body_m,
                                                              const Eigen::Vector3d& gyro_radps,
                                                              const Eigen::Matrix<double, 15, 1>& error);

 protected:
  void receiveEpochInput(const EstimatorEpochInput& input) override;
  void verifyBridgedArcs(const std::vector<BridgedArc>& bridged, const std::vector<SatelliteMeasurement>& usable,
                         EstimatorEpochResult& result) override;
  ReceiverState predict(double dt_s, bool first, const std::optional<ReceiverState>& start) override;
  bool solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) override;
  void resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& result) override;
  void finishEpoch(EstimatorEpochResult& result) const override;

  int coreDim() const override { return layout_.dim() + kExtraStates; }
  int coreIndex(int receiver_index) const override { return receiver_index + kExtraStates; }
  ReceiverState receiverStateAt(const Eigen::VectorXd& x) const override;
  ReceiverCovariance receiverCovarianceAt(const Eigen::VectorXd& x, const Eigen::MatrixXd& P) const override;
  Eigen::RowVectorXd coreJacobian(const SatelliteMeasurement& m, const Eigen::VectorXd& x) const override;
  Filter initialFilter(const ReceiverState& state) const override;
  void predictFilter(Filter& f, double dt_s, bool first) const override;
  void closeLoop(Filter& f) override;
  void fixedSolutionFound(const AmbiguityFixedState& fixed) override;

 private:
  /// The INS error replaces the 3 position states of the receiver layout.
  static constexpr int kExtraStates = 15 - 3;

  /// d(receiver state)/d(core) at x (layout dim x coreDim()).
  Eigen::MatrixXd receiverJacobianAt(const Eigen::VectorXd& x) const;
  std::optional<Eigen::Matrix3d> initialAttitude(const Eigen::Vector3d& position_ecef_m);
  /// Roll and pitch from the latest static interval before the start, carried to it; heading unknown.
  std::optional<Eigen::Matrix3d> attitudeInMotion(const Eigen::Vector3d& position_ecef_m);
  /// The attitude covariance of `f` with the heading's variance set to sigma^2 and its
  /// correlations removed (tilt kept).
  void setHeadingCovariance(Filter& f, double heading_sigma_rad) const;
  /// The course of the antenna track as the heading, once fast enough.
  void alignHeadingFromTrack(Filter& f);
  /// The antenna position's error covariance grown through a gap (the prediction's
  /// minus that after the last GNSS update, grownGapPositionCovariance of ins_gap_bridge.h).
  Eigen::Matrix3d gapPositionCovariance() const;
  /// The antenna position's error covariance of `f` at the nominal state [m^2].
  Eigen::Matrix3d antennaCovariance(const Filter& f) const;
  /// R_ned_body of the nominal state.
  Eigen::Matrix3d rotationNedBody() const;
  bool startNominal(const ReceiverState& start);
  /// Whether the held reading and this epoch's cover [lastTime(), time] (imu_coverage.h); the
  /// epoch's problem when not.
  bool readingsCover(const GnssTime& time);
  /// The Doppler velocity update of `f` (its INS error not reset); true when applied.
  bool updateWithDoppler(Filter& f);
  /// The closed-loop reset of the INS error alone (no heading alignment).
  void resetInsError(Filter& f);
  bool propagateTo(const GnssTime& time);
  /// The adaptive process noise of this epoch's prediction (work_), before the update.
  void adaptProcessNoise(const EpochSolveInput& in);
  bool stepWith(double dt_s);

  InsEkfOptions ins_;
  NavState nominal_;
  ImuBias bias_;
  std::vector<ImuSample> pending_;          // the readings of this epoch's input
  std::vector<DopplerObservation> doppler_;  // this epoch's Doppler range rates
  DopplerUpdate doppler_update_;            // what this epoch's Doppler update did
  std::optional<ImuSample> held_;           // the reading held at the nominal's time
  GnssTime epoch_time_;                     // this epoch's time
  std::optional<std::pair<NoSolutionReason, std::string>> epoch_problem_;  // this epoch's inertial problem
  std::vector<ImuSample> before_start_;     // the readings before the first solution (in-motion start)
  bool heading_from_course_ = false;        // started without a heading, not yet aligned
  bool starting_ = false;                   // this epoch starts the filter (no state from before a gap)
  Eigen::Vector3d start_accel_bias_mps2_ = Eigen::Vector3d::Zero();  // from the levelling (in-motion start)
  Eigen::Vector3d start_gyro_bias_radps_ = Eigen::Vector3d::Zero();  // from the levelling (in-motion start)
  double start_gyro_bias_sigma_radps_ = 0.0;                         // its sigma (the grade's when not taken)
  AlignmentState alignment_ = AlignmentState::NotAligned;
  CourseHeadingTrack track_;                // antenna positions after the updates
  std::optional<NavState> fixed_nominal_;   // this epoch's fixed solution (PPP-AR)
  std::optional<ImuBias> fixed_bias_;
  std::optional<Eigen::Vector3d> predicted_antenna_m_;  // this epoch's prediction
  std::optional<Eigen::Matrix3d> updated_antenna_cov_m2_;  // antenna covariance after the last GNSS update
  // The adaptive process noise: the propagation since the last GNSS update (transition and
  // process noise), the INS error covariance after that update, this epoch's test.
  InsDiscreteModel since_update_;
  Matrix15d since_update_accel_noise_ = Matrix15d::Zero();  // the part of its noise from the accelerometers' white noise
  std::optional<Matrix15d> updated_error_cov_;
  ProcessNoiseScale noise_scale_;
  std::optional<ChiSquareUpperQuantile> noise_quantile_;
};

}  // namespace ppp
