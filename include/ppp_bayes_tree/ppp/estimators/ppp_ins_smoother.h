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
// the last epoch. A gap of at most InsEkfOptions::gap_bridge_max_s does not end the arcs
// (gapBridgeMax_s): at the first epoch after, the arcs back are tested against the
// NavState predicted by the preintegrated readings across the gap, with the EKF's rule
// (verifyBridgedArcs, ins_gap_bridge.h); an arc that passes goes on with the same bias
// variable and its held integers' factors (with the slip-repair candidate the test
// chose), any other ends and starts again as a new arc with a new bias variable. Readings that do not cover the interval (a gap longer than
// max_imu_interval_s, or none at the last state) end the epoch with NoImuReadings.
// inertialState() carries the INS error covariance in the EKF's error state
// (ins_error_state.h: [dtheta; dv; dp; dba; dbg], the attitude error on the right, in
// the body frame, as the NavState tangent): after a solved epoch the joint marginal
// covariance of the newest NavState and bias from the Bayes tree, moved from the
// linearization point to the estimate; after an epoch without a solution that one
// propagated along the readings with the EKF's error model to the dead-reckoned state.
// The attitude quality is the EKF's (insAttitudeQuality) of that covariance.
// With neither attitude nor heading the heading is aligned in motion with the EKF's
// rule and options (ins_in_motion_alignment.h, InsEkfOptions::heading_alignment): at
// the start roll and pitch come from the latest static interval of the readings
// before it (carried to it by the gyros); the epochs are then solved as by the PPP
// smoother (receiver states with the position random walk, no NavState), the
// attitude carried through the readings by the preintegration, "level only", until
// the course over ground of the solved antenna positions gives a heading at a state
// k. The NavState starts at the next solved epoch: the attitude of k with the
// course's heading, the track's velocity and the levelling's accelerometer error,
// carried to that epoch by the readings, with priors of the options' tilt and
// velocity sigmas and the course's heading sigma; from there the alignment is
// "aligned". The result's attitude (EstimatorEpochResult::attitude) says so at each
// epoch; inertialState() is nullopt before the NavState.
// Adaptive process noise (InsEkfOptions::process_noise_adaptation, on by default;
// ins_process_noise_adaptation.h, shared with PppInsEkf): before the update, the phase
// innovations of the arcs with a bias at the predicted NavState are tested against the
// antenna's error added since the newest state (its INS error covariance and the error
// model's transition and process noise along the readings since); when they are
// inconsistent, the accelerometers' white noise in the IMU factor's covariance is
// scaled so that their normalised square is its expectation. processNoiseAdaptation() says what this epoch's test found.
// Numerics: the cliques are factorized by QR of the whitened Jacobian (kFactorization),
// never by Cholesky of the normal equations: options asking for Cholesky
// (PppSmootherOptions::factorization) are refused (validateOptions). The IMU factors make the states' relative motion stiff (the bias random walk of
// a consumer gyro over 0.25 s weighs 4e12 (rad/s)^-2) while the GNSS geometry leaves a
// direction of position and clocks weak (5-6 satellites: information 6e-5 m^-2 on the
// u-blox walk): the information matrix, scaled to a unit diagonal, has a condition
// number of 1e12-1e13 from the third state on. Cholesky of it keeps 3-4 digits: the
// update's step differed from the exact least-squares step by 0.2 rad or m/s and 8 cm,
// a rounding-level change of the input moved the solution by centimetres at once and,
// through the relinearizations of those wrong steps, by up to 1.8 km later. QR works on
// the Jacobian, whose condition number is the square root: the step agrees with the
// exact one to 1e-9 and the same change moves the walk's solution by micrometres
// (doc/studies/ins_walk.md, "Numerical conditioning").
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
#include "ppp_bayes_tree/ppp/estimators/ins_in_motion_alignment.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"

namespace ppp {

class PppInsSmoother : public PppSmoother {
 public:
  /// Sigma of the tie between the receiver state's position and the antenna [m].
  static constexpr double kAntennaTieSigma_m = 1e-4;
  /// Sigma of the position random walk between receiver states (uninformative: the
  /// IMU factor carries the motion) [m].
  static constexpr double kFreePositionSigma_m = 1e4;
  /// The factorization of the smoother's cliques (see "Numerics" above).
  static constexpr smoother::Factorization kFactorization = smoother::Factorization::QR;

  /// Empty when `options` suit the GNSS/INS smoother, else the first problem: a
  /// factorization other than kFactorization (PppSmootherOptions::factorization set to
  /// Cholesky), or InsEkfOptions::validate()'s.
  static std::string validateOptions(const EstimatorOptions& options);
  /// From the estimator options (the registry's factory, estimator_registry.h); throws
  /// std::invalid_argument with validateOptions()'s problem.
  explicit PppInsSmoother(const EstimatorOptions& options);

  std::string name() const override { return "smoother_ins"; }
  std::optional<double> gapBridgeMax_s() const override;
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
  /// What this epoch's test of the prediction against the phases found, and the scale
  /// of the IMU factor's noise it applied (ins_process_noise_adaptation.h).
  const ProcessNoiseScale& processNoiseAdaptation() const { return noise_scale_; }
  /// The attitude's alignment and sigmas at the last epoch; nullopt before the start.
  std::optional<InsAttitudeQuality> attitudeQuality() const;
  /// The INS error covariance of navState() (ins_error_state.h order); nullopt before a
  /// solved epoch, or when the readings since the newest state do not reach navTime().
  std::optional<Matrix15d> errorCovariance() const;
  /// The antenna position of navState(), ECEF [m].
  std::optional<Eigen::Vector3d> antennaPosition() const;
  /// PppEstimator::predictedAntennaPosition: the NavState of the newest state carried by
  /// the readings since, before the update; nullopt also before the NavState.
  std::optional<Eigen::Vector3d> predictedAntennaPosition() const override { return predicted_antenna_m_; }
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
  void verifyBridgedArcs(const std::vector<BridgedArc>& bridged, const std::vector<SatelliteMeasurement>& usable,
                         EstimatorEpochResult& result) override;
  ReceiverState predict(double dt_s, bool first, const std::optional<ReceiverState>& start) override;
  bool solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) override;
  void finishEpoch(EstimatorEpochResult& result) const override;

  /// Free (the IMU factor carries the motion) from a state with a NavState; before the
  /// NavState of an alignment in motion, the PPP smoother's.
  double positionProcessSigma_m(double dt_s) const override;
  void addInertialFactors(const EpochSolveInput& in, std::uint32_t index, smoother::NonlinearFactorGraph& factors,
                          smoother::Values& values, smoother::KeyVector& keys) const override;
  void addRestartInertialFactors(std::uint32_t index, smoother::NonlinearFactorGraph& factors,
                                 smoother::Values& values, smoother::KeyVector& newest) const override;

 private:
  bool startNav(const ReceiverState& start);
  /// Whether a reading holds at this epoch (the start's); the epoch's problem when not.
  bool readingHeldAtStart();
  /// The start of an alignment in motion: roll and pitch levelled, no NavState yet.
  bool startLevelOnly(const ReceiverState& start);
  /// Before the NavState of an alignment in motion: the attitude carried to this epoch,
  /// or, once the course gave the heading, the NavState's start at this epoch.
  void predictBeforeNavState(double dt_s, ReceiverState& predicted);
  /// After a solved epoch without a NavState: the course of the antenna track, once it
  /// gives a heading, sets the NavState of that epoch (course_nav_).
  void alignFromCourse(const GnssTime& time, const Eigen::Vector3d& antenna_ecef_m);
  /// The noise of the start's NavState prior: the options' sigmas, or after the
  /// course's heading, the heading's sigma about the down axis.
  smoother::NoiseModel::Ptr startNavNoise(const NavState& nav, bool from_course) const;
  void commitSolvedNavState(std::uint32_t index);
  bool preintegrateTo(const GnssTime& time);
  void addStartPriors(std::uint32_t index, const NavState& nav, const ImuBias& bias, bool from_course,
                      smoother::NonlinearFactorGraph& factors, smoother::Values& values) const;
  void keepReadingsFrom(const GnssTime& time);
  /// Drops (and counts) the readings no interval can use any more: before the start, and
  /// once the readings from the newest state have a gap no later reading closes, those
  /// before the last one at or before this epoch (a start holds that one).
  void dropUnusableReadings();
  /// The antenna position's error covariance grown through a gap: the newest state's
  /// propagated along the readings to this epoch minus its own (ins_gap_bridge.h).
  Eigen::Matrix3d gapPositionCovariance() const;
  /// The newest state's covariance from the Bayes tree (after a solved epoch).
  void keepNewestCovariance(std::uint32_t index);
  /// The adaptive process noise of this epoch's IMU factor (pim_), before the update.
  void adaptProcessNoise(const EpochSolveInput& in);
  /// broken_ is of the newest state only.
  void forgetGapOfAnOlderState();

  InsEkfOptions ins_;
  std::vector<ImuSample> input_readings_;  // this epoch's input
  std::vector<ImuSample> readings_;        // since the last state (the one held at its time first)
  GnssTime epoch_time_;
  std::optional<std::pair<NoSolutionReason, std::string>> epoch_problem_;
  std::optional<NavState> nav_;            // see navState()
  std::optional<GnssTime> nav_time_;       // see navTime()
  std::optional<Eigen::Vector3d> predicted_antenna_m_;  // see predictedAntennaPosition()
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
  ProcessNoiseScale noise_scale_;                          // this epoch's test (adaptProcessNoise)
  std::optional<ChiSquareUpperQuantile> noise_quantile_;  // its quantiles
  // The alignment in motion (neither attitude nor heading given).
  bool in_motion_ = false;
  AlignmentState alignment_ = AlignmentState::NotAligned;
  std::vector<ImuSample> before_start_;         // the readings before the start, to level from
  Eigen::Vector3d start_accel_bias_mps2_ = Eigen::Vector3d::Zero();  // from the levelling
  Eigen::Vector3d start_gyro_bias_radps_ = Eigen::Vector3d::Zero();   // from the levelling
  double start_gyro_bias_sigma_radps_ = 0.0;                          // its sigma (the grade's when not taken)
  std::optional<Eigen::Matrix3d> level_attitude_;  // R_ecef_body, heading unknown, at the newest state
  Eigen::Vector3d level_position_ecef_m_ = Eigen::Vector3d::Zero();  // the start's (its NED frame)
  std::optional<Eigen::Matrix3d> epoch_attitude_;  // level_attitude_ carried to this epoch
  CourseHeadingTrack track_;
  std::optional<NavState> course_nav_;          // the NavState from the course at the newest state
  double course_heading_sigma_rad_ = 0.0;
  bool nav_from_course_ = false;                // this epoch's nav_ starts from course_nav_
};

}  // namespace ppp
