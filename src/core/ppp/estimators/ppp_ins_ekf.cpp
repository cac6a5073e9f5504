#include "ppp_bayes_tree/ppp/estimators/ppp_ins_ekf.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

#include "ppp_bayes_tree/ppp/estimators/ins_gap_bridge.h"
#include "ppp_bayes_tree/ppp/estimators/ins_in_motion_alignment.h"
#include "ppp_bayes_tree/ppp/estimators/ins_start_attitude.h"
#include "ppp_bayes_tree/navigation/imu_coverage.h"
#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/navigation/ins_mechanization.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

std::string InsEkfOptions::validate() const {
  if (!lever_arm_body_m.allFinite()) return "lever arm not finite";
  if (initial_velocity_ned_mps && !initial_velocity_ned_mps->allFinite()) return "initial NED velocity not finite";
  if (initial_rotation_ned_body && !initial_rotation_ned_body->allFinite()) return "initial NED attitude not finite";
  if (!(initial_attitude_sigma_rad > 0.0)) return "initial attitude sigma must be > 0";
  if (!(initial_velocity_sigma_mps > 0.0)) return "initial velocity sigma must be > 0";
  if (!(max_imu_interval_s > 0.0)) return "max IMU interval must be > 0";
  if (!(heading_alignment.min_horizontal_speed_mps > 0.0)) return "heading alignment speed must be > 0";
  if (!(heading_alignment.course_interval_s > 0.0)) return "heading alignment interval must be > 0";
  if (!(heading_alignment.velocity_sigma_mps > 0.0)) return "heading alignment velocity sigma must be > 0";
  if (!(heading_alignment.unaligned_heading_sigma_rad > 0.0)) return "unaligned heading sigma must be > 0";
  if (!(publish_tilt_sigma_rad > 0.0) || !(publish_heading_sigma_rad > 0.0)) return "publish sigmas must be > 0";
  if (auto problem = process_noise_adaptation.validate(); !problem.empty()) return problem;
  return doppler.validate();
}

PppInsEkf::PppInsEkf(const EstimatorOptions& options)
    : PppEkf(options), ins_(options.ins), track_(options.ins.heading_alignment) {}

namespace {

/// w_eb in the body axes: the gyro reading less the Earth's rate.
Eigen::Vector3d bodyRateOverEarth(const Eigen::Matrix3d& rotation_ecef_body, const Eigen::Vector3d& gyro_radps) {
  return gyro_radps - rotation_ecef_body.transpose() * Eigen::Vector3d(0.0, 0.0, kEarthRotationRate_radps);
}

}  // namespace

Eigen::Vector3d PppInsEkf::antennaVelocityAt(const NavState& nominal, const Eigen::Vector3d& lever_arm_body_m,
                                             const Eigen::Vector3d& gyro_radps, const Vector15d& error) {
  const Eigen::Matrix3d R = nominal.rotation_world_body * so3::expMap(error.segment<3>(InsErrorIndex::kAttitude));
  const Eigen::Vector3d w_eb = bodyRateOverEarth(R, gyro_radps - error.segment<3>(InsErrorIndex::kGyroBias));
  return nominal.velocity_world_mps + error.segment<3>(InsErrorIndex::kVelocity) + R * w_eb.cross(lever_arm_body_m);
}

Eigen::Matrix<double, 3, 15> PppInsEkf::antennaVelocityJacobian(const NavState& nominal,
                                                                const Eigen::Vector3d& lever_arm_body_m,
                                                                const Eigen::Vector3d& gyro_radps,
                                                                const Vector15d& error) {
  // d(R Exp(a) u)/da = -R Exp(a) [u]x Jr(a); d(w x l)/d(dbg) = [l]x (w_true = w - dbg).
  const Eigen::Vector3d a = error.segment<3>(InsErrorIndex::kAttitude);
  const Eigen::Matrix3d R = nominal.rotation_world_body * so3::expMap(a);
  const Eigen::Vector3d w_eb = bodyRateOverEarth(R, gyro_radps - error.segment<3>(InsErrorIndex::kGyroBias));
  Eigen::Matrix<double, 3, 15> J = Eigen::Matrix<double, 3, 15>::Zero();
  J.block<3, 3>(0, InsErrorIndex::kAttitude) = -R * so3::hat(w_eb.cross(lever_arm_body_m)) * so3::rightJacobian(a);
  J.block<3, 3>(0, InsErrorIndex::kVelocity) = Eigen::Matrix3d::Identity();
  J.block<3, 3>(0, InsErrorIndex::kGyroBias) = R * so3::hat(lever_arm_body_m);
  return J;
}

Eigen::Vector3d PppInsEkf::antennaPosition() const {
  return insAntennaPosition(nominal_, ins_.lever_arm_body_m, Vector15d::Zero());
}

// ---- The seam of PppEkf: the core is [INS error (15); receiver states but the position] ----

ReceiverState PppInsEkf::receiverStateAt(const Eigen::VectorXd& x) const {
  const int rest = layout_.dim() - ReceiverStateLayout::kPositionSize;
  Eigen::VectorXd v(layout_.dim());
  v.head<3>() = insAntennaPosition(nominal_, ins_.lever_arm_body_m, x.head<kInsErrorStateSize>());
  v.tail(rest) = x.segment(kInsErrorStateSize, rest);
  return ReceiverState::fromVector(v, layout_);
}

Eigen::MatrixXd PppInsEkf::receiverJacobianAt(const Eigen::VectorXd& x) const {
  const int rest = layout_.dim() - ReceiverStateLayout::kPositionSize;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(layout_.dim(), coreDim());
  M.topLeftCorner(3, kInsErrorStateSize) =
      insAntennaPositionJacobian(nominal_, ins_.lever_arm_body_m, x.head<kInsErrorStateSize>());
  M.bottomRightCorner(rest, rest).setIdentity();
  return M;
}

ReceiverCovariance PppInsEkf::receiverCovarianceAt(const Eigen::VectorXd& x, const Eigen::MatrixXd& P) const {
  const Eigen::MatrixXd M = receiverJacobianAt(x);
  return M * P.topLeftCorner(coreDim(), coreDim()) * M.transpose();
}

Eigen::RowVectorXd PppInsEkf::coreJacobian(const SatelliteMeasurement& m, const Eigen::VectorXd& x) const {
  return m.jacobian * receiverJacobianAt(x);
}

PppEkf::Filter PppInsEkf::initialFilter(const ReceiverState& state) const {
  // The receiver part as the EKF starts it; the INS error in place of the position.
  const Filter receiver = PppEkf::initialFilter(state);
  const int rest = layout_.dim() - ReceiverStateLayout::kPositionSize;
  Filter f;
  f.x = Eigen::VectorXd::Zero(coreDim());
  f.x.tail(rest) = receiver.x.tail(rest);
  f.P = Eigen::MatrixXd::Zero(coreDim(), coreDim());
  f.P.bottomRightCorner(rest, rest) = receiver.P.bottomRightCorner(rest, rest);
  const auto block = [&f](int first, double sigma) {
    f.P.block<3, 3>(first, first) = sigma * sigma * Eigen::Matrix3d::Identity();
  };
  block(InsErrorIndex::kAttitude, ins_.initial_attitude_sigma_rad);
  block(InsErrorIndex::kVelocity, ins_.initial_velocity_sigma_mps);
  block(InsErrorIndex::kPosition, std::sqrt(model_.position.initialVariance_m2()));
  block(InsErrorIndex::kAccelBias, ins_.noise.accel_bias_instability_mps2);
  block(InsErrorIndex::kGyroBias, ins_.noise.gyro_bias_instability_radps);
  return f;
}

void PppInsEkf::predictFilter(Filter& f, double dt_s, bool first) const {
  // The INS error moves with the readings (propagateTo); the rest as in the EKF.
  if (first) return;
  predictDelaysClocksBiases(f, dt_s);
}

void PppInsEkf::resetInsError(Filter& f) {
  const Vector15d error = f.x.head<kInsErrorStateSize>();
  applyInsErrorCorrection(error, &nominal_, &bias_);
  const Matrix15d J = insErrorResetJacobian(error);
  f.P.topRows(kInsErrorStateSize) = (J * f.P.topRows(kInsErrorStateSize)).eval();
  f.P.leftCols(kInsErrorStateSize) = (f.P.leftCols(kInsErrorStateSize) * J.transpose()).eval();
  f.x.head<kInsErrorStateSize>().setZero();
}

void PppInsEkf::closeLoop(Filter& f) {
  resetInsError(f);
  updated_error_cov_ = f.P.topLeftCorner<kInsErrorStateSize, kInsErrorStateSize>();
  since_update_ = InsDiscreteModel{};
  since_update_accel_noise_.setZero();
  before_start_.clear();  // started: the levelling readings are done with
  if (heading_from_course_) alignHeadingFromTrack(f);
  updated_antenna_cov_m2_ = antennaCovariance(f);  // the bridge's reference after a gap
}

Eigen::Matrix3d PppInsEkf::antennaCovariance(const Filter& f) const {
  return insAntennaPositionCovariance(nominal_, ins_.lever_arm_body_m, f.P.topLeftCorner<kInsErrorStateSize, kInsErrorStateSize>(),
                                      f.x.head<kInsErrorStateSize>());
}

// ---- The epoch: readings, start, propagation ----

void PppInsEkf::receiveEpochInput(const EstimatorEpochInput& input) {
  epoch_time_ = input.time;
  epoch_problem_.reset();
  fixed_nominal_.reset();
  fixed_bias_.reset();
  predicted_antenna_m_.reset();
  pending_.clear();
  if (input.imu) pending_ = *input.imu;
  doppler_.clear();
  if (input.doppler) doppler_ = *input.doppler;
  doppler_update_ = DopplerUpdate{};
  if (lastTime() || ins_.initial_rotation_ecef_body || ins_.initial_heading_rad) return;
  // Before the first solution of an in-motion start: the readings to level from.
  keepLevellingHistory(before_start_, pending_, input.time);
}

std::optional<Eigen::Matrix3d> PppInsEkf::initialAttitude(const Eigen::Vector3d& position_ecef_m) {
  heading_from_course_ = false;
  alignment_ = AlignmentState::Aligned;
  if (!ins_.initial_rotation_ecef_body && !ins_.initial_rotation_ned_body && !ins_.initial_heading_rad)
    return attitudeInMotion(position_ecef_m);
  InsStartAttitude start = insStartAttitude(ins_, pending_, position_ecef_m);
  if (!start.rotation_ecef_body) epoch_problem_ = {NoSolutionReason::NoInitialAttitude, std::move(start.problem)};
  return start.rotation_ecef_body;
}

std::optional<Eigen::Matrix3d> PppInsEkf::attitudeInMotion(const Eigen::Vector3d& position_ecef_m) {
  InMotionLevel level = levelInMotion(before_start_, position_ecef_m, epoch_time_, ins_.noise);
  if (!level.rotation_ecef_body) {
    epoch_problem_ = {NoSolutionReason::NoInitialAttitude, std::move(level.problem)};
    return std::nullopt;
  }
  heading_from_course_ = true;
  alignment_ = AlignmentState::LevelOnly;
  start_accel_bias_mps2_ = level.accel_bias_mps2;
  start_gyro_bias_radps_ = level.gyro_bias_radps;
  start_gyro_bias_sigma_radps_ = level.gyro_bias_sigma_radps.value_or(ins_.noise.gyro_bias_instability_radps);
  return level.rotation_ecef_body;
}

Eigen::Matrix3d PppInsEkf::rotationNedBody() const {
  return rotationEcefNed(nominal_.position_world_m).transpose() * nominal_.rotation_world_body;
}

void PppInsEkf::setHeadingCovariance(Filter& f, double heading_sigma_rad) const {
  constexpr int a = InsErrorIndex::kAttitude;
  const Eigen::Matrix3d covariance =
      attitudeCovarianceWithHeading(rotationNedBody(), f.P.block<3, 3>(a, a), heading_sigma_rad);
  f.P.middleRows(a, 3).setZero();
  f.P.middleCols(a, 3).setZero();
  f.P.block<3, 3>(a, a) = covariance;
}

void PppInsEkf::alignHeadingFromTrack(Filter& f) {
  const Eigen::Vector3d antenna = antennaPosition();
  const std::optional<CourseHeading> course = track_.add(epoch_time_, antenna);
  if (!course) return;
  nominal_ = alignedToCourse(nominal_, course->heading.heading_rad, antenna, ins_.lever_arm_body_m);
  setHeadingCovariance(f, course->heading.heading_sigma_rad);
  heading_from_course_ = false;
  alignment_ = AlignmentState::Aligned;
}

std::optional<InertialState> PppInsEkf::inertialState() const {
  if (!lastTime()) return std::nullopt;
  InertialState s;
  s.time = *lastTime();
  s.nav = nominal_;
  s.bias = bias_;
  s.antenna_ecef_m = antennaPosition();
  s.attitude_quality = attitudeQuality();
  s.error_covariance = f_.P.topLeftCorner<kInsErrorStateSize, kInsErrorStateSize>();
  s.doppler = doppler_update_;
  return s;
}

InsAttitudeQuality PppInsEkf::attitudeQuality() const {
  if (!lastTime()) return InsAttitudeQuality{};
  constexpr int a = InsErrorIndex::kAttitude;
  return insAttitudeQuality(alignment_, rotationNedBody(), f_.P.block<3, 3>(a, a), ins_.publish_tilt_sigma_rad,
                            ins_.publish_heading_sigma_rad);
}

bool PppInsEkf::startNominal(const ReceiverState& start) {
  const std::optional<Eigen::Matrix3d> attitude = initialAttitude(start.position_ecef_m);
  if (!attitude) return false;
  held_.reset();
  for (const ImuSample& s : pending_)
    if (s.time - epoch_time_ <= 0.0) held_ = s;
  if (!held_) {
    epoch_problem_ = {NoSolutionReason::NoImuReadings,
                      "no IMU reading at or before the start " + epoch_time_.toString()};
    return false;
  }
  nominal_.rotation_world_body = *attitude;
  nominal_.velocity_world_mps = insStartVelocity_ecef_mps(ins_, start.position_ecef_m);
  nominal_.position_world_m = start.position_ecef_m - nominal_.rotation_world_body * ins_.lever_arm_body_m;
  bias_ = ImuBias{};
  if (heading_from_course_) {
    bias_.accel_mps2 = start_accel_bias_mps2_;
    bias_.gyro_radps = start_gyro_bias_radps_;
  }
  return true;
}

ReceiverState PppInsEkf::predict(double dt_s, bool first, const std::optional<ReceiverState>& start) {
  starting_ = start.has_value();
  if (start) {
    updated_error_cov_.reset();
    since_update_ = InsDiscreteModel{};
    since_update_accel_noise_.setZero();
    work_ = initialFilter(*start);
    if (!startNominal(*start)) {  // the epoch fails with the reason (solve, finishEpoch)
      pending_.clear();
      return *start;
    }
    track_.clear();
    if (heading_from_course_) {
      setHeadingCovariance(work_, ins_.heading_alignment.unaligned_heading_sigma_rad);
      constexpr int g = InsErrorIndex::kGyroBias;
      work_.P.block<3, 3>(g, g) = start_gyro_bias_sigma_radps_ * start_gyro_bias_sigma_radps_ * Eigen::Matrix3d::Identity();
    }
    updateWithDoppler(work_);  // committed with the start's update, if any
  } else if (!first) {
    if (propagateTo(*lastTime() + dt_s)) {
      predictFilter(f_, dt_s, false);
      if (updateWithDoppler(f_)) resetInsError(f_);  // committed with the propagation
    }
    work_ = f_;
  } else {
    work_ = f_;
  }
  pending_.clear();
  const ReceiverState predicted = receiverStateAt(work_.x);
  predicted_antenna_m_ = predicted.position_ecef_m;
  return predicted;
}

bool PppInsEkf::readingsCover(const GnssTime& time) {
  // The reading held at the nominal's time, then this epoch's after it.
  const GnssTime start = *lastTime();
  std::vector<ImuSample> readings;
  if (held_) readings.push_back(*held_);
  for (const ImuSample& s : pending_)
    if (s.time - start > 0.0) readings.push_back(s);
  const ImuCoverage coverage = imuCoverage(readings, start, time, ins_.max_imu_interval_s);
  if (coverage.covered()) return true;
  epoch_problem_ = {NoSolutionReason::NoImuReadings,
                    "IMU readings do not cover the interval to " + epoch_time_.toString() + ": " + coverage.text()};
  return false;
}

bool PppInsEkf::propagateTo(const GnssTime& time) {
  // Each reading is held from its time to the next one's; committed only when the
  // readings cover the whole interval (imu_coverage.h) and are finite.
  if (!readingsCover(time)) return false;
  const NavState nominal = nominal_;
  const Eigen::MatrixXd P = f_.P;
  const std::optional<ImuSample> held = held_;
  const InsDiscreteModel since_update = since_update_;
  const Matrix15d since_update_accel_noise = since_update_accel_noise_;
  GnssTime t = *lastTime();
  bool ok = true;
  for (const ImuSample& s : pending_) {
    const double dt_s = s.time - t;
    if (dt_s <= 0.0) continue;
    if (time - s.time < 0.0) break;
    if (!(ok = stepWith(dt_s))) break;
    held_ = s;
    t = s.time;
  }
  if (ok && time - t > 0.0) ok = stepWith(time - t);
  if (ok) {
    last_time_ = time;
    return true;
  }
  nominal_ = nominal;
  f_.P = P;
  held_ = held;
  since_update_ = since_update;
  since_update_accel_noise_ = since_update_accel_noise;
  return false;
}

bool PppInsEkf::stepWith(double dt_s) {
  // The held reading (readingsCover: there is one, held at most max_imu_interval_s).
  const Eigen::Vector3d f_b = held_->specific_force_mps2 - bias_.accel_mps2;
  const Eigen::Vector3d w_b = held_->angular_rate_radps - bias_.gyro_radps;
  if (!f_b.allFinite() || !w_b.allFinite()) {
    epoch_problem_ = {NoSolutionReason::NoImuReadings, "IMU readings do not cover the interval to " +
                                                           epoch_time_.toString() + ": reading at " +
                                                           held_->time.toString() + " not finite"};
    return false;
  }
  const Matrix15d F = insErrorStateF(nominal_, f_b, w_b, ins_.bias_model);
  const Matrix15x12d G = insErrorStateG(nominal_);
  const Matrix12d density = insNoiseSpectralDensity(ins_.noise, ins_.bias_model);
  const InsDiscreteModel model = discretizeInsErrorModel(F, G, density, dt_s);
  constexpr int n = kInsErrorStateSize;
  f_.P.topRows(n) = (model.transition * f_.P.topRows(n)).eval();
  f_.P.leftCols(n) = (f_.P.leftCols(n) * model.transition.transpose()).eval();
  f_.P.topLeftCorner(n, n) += model.process_noise;
  since_update_.transition = (model.transition * since_update_.transition).eval();
  since_update_.process_noise = propagateInsCovariance(since_update_.process_noise, model);
  if (ins_.process_noise_adaptation.enabled) {
    InsDiscreteModel white = model;  // the transition with the accelerometers' noise alone
    white.process_noise = discreteInsProcessNoise(model.transition, G, accelerometerNoiseDensity(density), dt_s);
    since_update_accel_noise_ = propagateInsCovariance(since_update_accel_noise_, white);
  }
  nominal_ = ecefInsStep(nominal_, f_b, w_b, dt_s);
  return true;
}

bool PppInsEkf::updateWithDoppler(Filter& f) {
  // 1. The antenna velocity from the Doppler at the antenna position of `f`.
  if (!ins_.doppler.enabled || doppler_.empty() || !held_) return false;
  const Vector15d error = f.x.head<kInsErrorStateSize>();
  const DopplerVelocitySolution v =
      solveDopplerVelocity(doppler_, insAntennaPosition(nominal_, ins_.lever_arm_body_m, error), ins_.doppler);
  DopplerUpdate& u = doppler_update_;
  u.velocity_status = v.status;
  u.satellites = static_cast<int>(v.used.size());
  u.rejected = static_cast<int>(v.rejected.size());
  u.outcome = DopplerOutcome::NoVelocity;
  if (!v.ok()) return false;
  u.velocity_ecef_mps = v.velocity_ecef_mps;
  // 2. Its innovation against the filter's antenna velocity, tested.
  const Eigen::Vector3d gyro = held_->angular_rate_radps - bias_.gyro_radps;
  const int n = static_cast<int>(f.x.size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, n);
  H.leftCols(kInsErrorStateSize) = antennaVelocityJacobian(nominal_, ins_.lever_arm_body_m, gyro, error);
  const Eigen::Vector3d y = v.velocity_ecef_mps - antennaVelocityAt(nominal_, ins_.lever_arm_body_m, gyro, error);
  const Eigen::MatrixXd PHt = f.P * H.transpose();
  const Eigen::Matrix3d S = H * PHt + v.velocity_covariance;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(S);
  if (ldlt.info() != Eigen::Success) return false;
  u.innovation_chi2 = y.dot(ldlt.solve(y));
  if (!(u.innovation_chi2 <= ins_.doppler.innovation_chi2)) {
    u.outcome = DopplerOutcome::InnovationRefused;
    return false;
  }
  // 3. The update (Joseph form).
  const Eigen::MatrixXd K = ldlt.solve(PHt.transpose()).transpose();
  f.x += K * y;
  const Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(n, n) - K * H;
  f.P = I_KH * f.P * I_KH.transpose() + K * v.velocity_covariance * K.transpose();
  f.P = 0.5 * (f.P + f.P.transpose()).eval();
  u.outcome = DopplerOutcome::Applied;
  return true;
}

bool PppInsEkf::solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) {
  if (epoch_problem_) return fail(result, EpochStatus::NoSolution, epoch_problem_->first, epoch_problem_->second);
  adaptProcessNoise(in);
  return PppEkf::solve(in, out, result);
}

void PppInsEkf::adaptProcessNoise(const EpochSolveInput& in) {
  // 1. The phase innovations of the arcs with a bias, at the prediction.
  noise_scale_ = ProcessNoiseScale{};
  if (in.first || starting_ || !updated_error_cov_) return;
  std::vector<PhaseInnovationRow> rows;
  for (const ScreenedMeasurement& s : in.screened) {
    const int slot = s.active_arc ? findBias(work_, s.m.arc) : -1;
    if (slot >= 0) rows.push_back(phaseInnovationRow(s.m, layout_, work_.x(coreDim() + slot)));
  }
  // 2. Their test against the antenna's error added since the last update; the scale.
  const ProcessNoiseAdaptationOptions& options = ins_.process_noise_adaptation;
  if (!noise_quantile_ || !(noise_quantile_->alpha() == options.false_alarm)) noise_quantile_.emplace(options.false_alarm);
  const Matrix15d relative = relativeInsErrorCovariance(since_update_, *updated_error_cov_);
  noise_scale_ = processNoiseScale(rows, insAntennaPositionCovariance(nominal_, ins_.lever_arm_body_m, relative),
                                   insAntennaPositionCovariance(nominal_, ins_.lever_arm_body_m, since_update_accel_noise_),
                                   options, *noise_quantile_);
  // 3. The accelerometers' white noise since times the scale in the prediction.
  if (noise_scale_.inflated())
    work_.P.topLeftCorner<kInsErrorStateSize, kInsErrorStateSize>() +=
        (noise_scale_.scale - 1.0) * since_update_accel_noise_;
}

void PppInsEkf::finishEpoch(EstimatorEpochResult& result) const {
  // An inertial problem is the epoch's reason, also when the screening stopped it first.
  if (epoch_problem_ && result.status != EpochStatus::Ok)
    fail(result, EpochStatus::NoSolution, epoch_problem_->first, epoch_problem_->second);
  if (lastTime()) result.attitude = attitudeQuality();
}

void PppInsEkf::resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& result) {
  // The EKF's PPP-AR over this filter's core (coreDim(), receiverStateAt);
  // fixedSolutionFound keeps the fixed nominal.
  fixed_nominal_.reset();
  fixed_bias_.reset();
  PppEkf::resolveAmbiguities(input, result);
}

void PppInsEkf::fixedSolutionFound(const AmbiguityFixedState& fixed) {
  // The closed-loop reset applied to a copy: the nominal moved by the fixed INS error.
  NavState nominal = nominal_;
  ImuBias bias = bias_;
  applyInsErrorCorrection(fixed.x.head<kInsErrorStateSize>(), &nominal, &bias);
  fixed_nominal_ = nominal;
  fixed_bias_ = bias;
}

std::optional<double> PppInsEkf::gapBridgeMax_s() const {
  if (!(ins_.gap_bridge_max_s > 0.0)) return std::nullopt;
  return ins_.gap_bridge_max_s;
}

Eigen::Matrix3d PppInsEkf::gapPositionCovariance() const {
  // The prediction's (work_: the filter propagated through the gap) minus the last
  // GNSS update's; none yet: the least variance (the bridge's floor then decides).
  if (!updated_antenna_cov_m2_) return grownGapPositionCovariance(Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero());
  return grownGapPositionCovariance(antennaCovariance(work_), *updated_antenna_cov_m2_);
}

void PppInsEkf::verifyBridgedArcs(const std::vector<BridgedArc>& bridged, const std::vector<SatelliteMeasurement>& usable,
                                  EstimatorEpochResult& result) {
  // A start (the first, or one attempted again after a refused start) has no state from
  // before the gap to predict across it: the arcs end.
  if (starting_) {
    for (const BridgedArc& b : bridged) endBridgedArc(b, "the filter starts at this epoch, no state before the gap", result);
    return;
  }
  // The arcs' biases of the prediction; the covariance of the antenna position's error
  // grown through the gap (the INS prediction's minus that after the last GNSS update:
  // the error then is in the biases).
  const auto held_bias_m = [this](ArcId arc) -> std::optional<double> {
    const int slot = findBias(work_, arc);
    if (slot < 0) return std::nullopt;
    return work_.x(coreDim() + slot);
  };
  const std::vector<BridgedArcVerdict> verdicts = insGapBridgeVerdicts(
      bridged, usable, held_bias_m, layout_.position(), gapPositionCovariance(), ins_.gap_bridge);
  applyBridgedArcVerdicts(
      verdicts, [&](const BridgedArc& b, const std::string& reason) { endBridgedArc(b, reason, result); },
      [&](const BridgedArc& b, const SlipCandidate& c) { return chooseRepairCandidate(b, c, result); }, resolver(),
      result);
}

}  // namespace ppp
