#include "ppp_bayes_tree/ppp/estimators/ppp_ins_smoother.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/navigation/imu_coverage.h"
#include "ppp_bayes_tree/navigation/imu_smoother_factor.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/navigation/ins_mechanization.h"
#include "ppp_bayes_tree/navigation/nav_state_value.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/ppp/estimators/antenna_position_factor.h"
#include "ppp_bayes_tree/ppp/estimators/ins_gap_bridge.h"
#include "ppp_bayes_tree/ppp/estimators/ins_start_attitude.h"
#include "ppp_bayes_tree/ppp/model/ppp_factors.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"

namespace ppp {

using smoother::Key;
using smoother::NoiseModel;

namespace {

/// The INS error model of the propagation of `nav` from `from` to `to` along the readings
/// (the last one at or before `from` first; each held from its time to the next one's):
/// the transition and process noise accumulated over the steps of the GNSS/INS EKF's
/// error model (ins_error_state.h), the nominal state stepped by the mechanization, as
/// the EKF propagates between epochs, with the noise's spectral densities `density`.
/// `accel_process_noise`, when given, receives in the same pass the process noise of the
/// accelerometers' white noise alone (accelerometerNoiseDensity) along that transition.
InsDiscreteModel propagatedErrorModel(NavState nav, const ImuBias& bias, const std::vector<ImuSample>& readings,
                                      const GnssTime& from, const GnssTime& to, const InsEkfOptions& ins,
                                      const Matrix12d& density, Matrix15d* accel_process_noise = nullptr) {
  InsDiscreteModel total;
  const Matrix12d accel_density = accelerometerNoiseDensity(density);
  if (accel_process_noise) accel_process_noise->setZero();
  GnssTime t = from;
  for (std::size_t k = 0; k < readings.size() && t < to; ++k) {
    const bool later = k + 1 < readings.size();
    if (later && readings[k + 1].time <= from) continue;  // a later reading holds at `from`
    const GnssTime end = later && readings[k + 1].time < to ? readings[k + 1].time : to;
    const double dt_s = end - t;
    if (dt_s <= 0.0) continue;
    const Eigen::Vector3d f_b = readings[k].specific_force_mps2 - bias.accel_mps2;
    const Eigen::Vector3d w_b = readings[k].angular_rate_radps - bias.gyro_radps;
    const Matrix15x12d g = insErrorStateG(nav);
    const InsDiscreteModel step = discretizeInsErrorModel(insErrorStateF(nav, f_b, w_b, ins.bias_model), g, density, dt_s);
    total.transition = (step.transition * total.transition).eval();
    total.process_noise = propagateInsCovariance(total.process_noise, step);
    if (accel_process_noise) {
      InsDiscreteModel accel_step = step;  // the transition with the accelerometers' noise alone
      accel_step.process_noise = discreteInsProcessNoise(step.transition, g, accel_density, dt_s);
      *accel_process_noise = propagateInsCovariance(*accel_process_noise, accel_step);
    }
    nav = ecefInsStep(nav, f_b, w_b, dt_s);
    t = end;
  }
  return total;
}

/// The INS error covariance of `nav` at `from` moved to `to` along the readings (propagatedErrorModel).
Matrix15d propagatedCovariance(const Matrix15d& covariance, const NavState& nav, const ImuBias& bias,
                               const std::vector<ImuSample>& readings, const GnssTime& from, const GnssTime& to,
                               const InsEkfOptions& ins) {
  return propagateInsCovariance(
      covariance,
      propagatedErrorModel(nav, bias, readings, from, to, ins, insNoiseSpectralDensity(ins.noise, ins.bias_model)));
}

/// The estimator options checked (PppInsSmoother::validateOptions; throws
/// std::invalid_argument), with the cliques factorized as the GNSS/INS smoother needs
/// (PppInsSmoother::kFactorization, ppp_ins_smoother.h "Numerics").
EstimatorOptions checkedWithInertialFactorization(EstimatorOptions options) {
  if (auto problem = PppInsSmoother::validateOptions(options); !problem.empty()) throw std::invalid_argument(problem);
  options.smoother.factorization = PppInsSmoother::kFactorization;
  return options;
}

}  // namespace

std::string PppInsSmoother::validateOptions(const EstimatorOptions& options) {
  if (options.smoother.factorization && *options.smoother.factorization != kFactorization)
    return "smoother_ins factorizes its cliques by QR only (Cholesky of its normal equations keeps 3-4 digits, "
           "ppp_ins_smoother.h \"Numerics\"): PppSmootherOptions::factorization Cholesky refused (leave it unset)";
  return options.ins.validate();
}

PppInsSmoother::PppInsSmoother(const EstimatorOptions& options)
    : PppSmoother(checkedWithInertialFactorization(options)),
      ins_(options.ins),
      track_(options.ins.heading_alignment) {
  in_motion_ = !ins_.initial_rotation_ecef_body && !ins_.initial_rotation_ned_body && !ins_.initial_heading_rad;
}

double PppInsSmoother::positionProcessSigma_m(double dt_s) const {
  if (in_motion_ && !last_nav_) return PppSmoother::positionProcessSigma_m(dt_s);
  return kFreePositionSigma_m;
}

std::optional<Eigen::Vector3d> PppInsSmoother::antennaPosition() const {
  if (!nav_) return std::nullopt;
  return AntennaPositionFactor::antennaOf(*nav_, ins_.lever_arm_body_m);
}

std::optional<InertialState> PppInsSmoother::inertialState() const {
  if (!nav_ || !nav_time_) return std::nullopt;
  InertialState s;
  s.time = *nav_time_;
  s.nav = *nav_;
  s.bias = bias_;
  s.antenna_ecef_m = *antennaPosition();
  s.error_covariance = errorCovariance();
  if (s.error_covariance) {
    constexpr int a = InsErrorIndex::kAttitude;
    const Eigen::Matrix3d ned_body = rotationEcefNed(nav_->position_world_m).transpose() * nav_->rotation_world_body;
    s.attitude_quality = insAttitudeQuality(alignment_, ned_body, s.error_covariance->block<3, 3>(a, a),
                                            ins_.publish_tilt_sigma_rad, ins_.publish_heading_sigma_rad);
  }
  return s;
}

std::optional<InsAttitudeQuality> PppInsSmoother::attitudeQuality() const {
  if (!in_motion_ || alignment_ == AlignmentState::Aligned) {
    const std::optional<InertialState> s = inertialState();
    return s ? s->attitude_quality : std::nullopt;
  }
  if (!epoch_attitude_) return std::nullopt;
  // Level only: the tilt of the start's sigma, the heading unknown.
  const Eigen::Matrix3d ned_body = rotationEcefNed(level_position_ecef_m_).transpose() * *epoch_attitude_;
  const double tilt_sigma_rad = ins_.initial_attitude_sigma_rad;
  const Eigen::Matrix3d covariance =
      attitudeCovarianceWithHeading(ned_body, tilt_sigma_rad * tilt_sigma_rad * Eigen::Matrix3d::Identity(),
                                    ins_.heading_alignment.unaligned_heading_sigma_rad);
  return insAttitudeQuality(alignment_, ned_body, covariance, ins_.publish_tilt_sigma_rad,
                            ins_.publish_heading_sigma_rad);
}

std::optional<Matrix15d> PppInsSmoother::errorCovariance() const {
  const std::optional<CovariantState>& c = newest_covariance_;
  if (!c || !nav_time_ || !lastTime() || !(c->time == *lastTime()) || *nav_time_ < c->time) return std::nullopt;
  if (*nav_time_ == c->time) return c->covariance;
  // Dead-reckoned from the newest state: its readings are still kept (keepReadingsFrom at a solve).
  if (readings_.empty() || c->time < readings_.front().time || readings_.back().time < *nav_time_ - ins_.max_imu_interval_s)
    return std::nullopt;
  return propagatedCovariance(c->covariance, c->nav, c->bias, readings_, c->time, *nav_time_, ins_);
}

void PppInsSmoother::keepNewestCovariance(std::uint32_t index) {
  // The marginal is of the tangent at the linearization point; the estimate is that point
  // moved by delta: the error about the estimate is Jr(delta_theta) times it (insErrorResetJacobian).
  const smoother::Matrix joint = isam2().jointMarginalCovariance({navKey(index), imuBiasKey(index)});
  Vector15d delta;
  delta << isam2().delta().at(navKey(index)), isam2().delta().at(imuBiasKey(index));
  const Matrix15d J = insErrorResetJacobian(delta);
  const Matrix15d P = J * Matrix15d(joint) * J.transpose();
  newest_covariance_ = CovariantState{*nav_time_, *nav_, bias_, 0.5 * (P + P.transpose())};
}

std::optional<double> PppInsSmoother::gapBridgeMax_s() const {
  if (!(ins_.gap_bridge_max_s > 0.0)) return std::nullopt;
  return ins_.gap_bridge_max_s;
}

Eigen::Matrix3d PppInsSmoother::gapPositionCovariance() const {
  const std::optional<CovariantState>& c = newest_covariance_;
  if (!c || !nav_ || !lastTime() || !(c->time == *lastTime())) {
    return grownGapPositionCovariance(Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero());
  }
  const Matrix15d after = propagatedCovariance(c->covariance, c->nav, c->bias, readings_, c->time, epoch_time_, ins_);
  return grownGapPositionCovariance(insAntennaPositionCovariance(*nav_, ins_.lever_arm_body_m, after),
                                    insAntennaPositionCovariance(c->nav, ins_.lever_arm_body_m, c->covariance));
}

void PppInsSmoother::verifyBridgedArcs(const std::vector<BridgedArc>& bridged,
                                       const std::vector<SatelliteMeasurement>& usable, EstimatorEpochResult& result) {
  const auto end = [&](const BridgedArc& b, const std::string& reason) { endBridgedArc(b, reason, result); };
  // Only the NavState predicted across the gap from the newest state tests the arcs.
  if (!pim_ || !last_nav_ || !nav_) {
    for (const BridgedArc& b : bridged) end(b, "no INS prediction across the gap");
    return;
  }
  const auto held_bias_m = [this](ArcId arc) -> std::optional<double> {
    const std::optional<ArcBiasPrior> prior = predictedBias(arc);
    if (!prior) return std::nullopt;
    return prior->bias_m;
  };
  applyBridgedArcVerdicts(insGapBridgeVerdicts(bridged, usable, held_bias_m, layout_.position(),
                                               gapPositionCovariance(), ins_.gap_bridge),
                          end, [&](const BridgedArc& b, const SlipCandidate& c) { return chooseRepairCandidate(b, c, result); },
                          resolver(), result);
}

std::optional<NavState> PppInsSmoother::smoothedNavState(std::uint32_t index) const {
  if (!isam2().exists(navKey(index))) return std::nullopt;
  return navStateFromStorage(isam2().calculateEstimate(navKey(index)));
}

void PppInsSmoother::receiveEpochInput(const EstimatorEpochInput& input) {
  epoch_time_ = input.time;
  epoch_problem_.reset();
  predicted_antenna_m_.reset();
  input_readings_.clear();
  if (!input.imu) return;
  input_readings_ = *input.imu;
  // Before the first solution of an in-motion start: the readings to level from.
  if (in_motion_ && !lastTime()) keepLevellingHistory(before_start_, input_readings_, input.time);
  readings_.insert(readings_.end(), input.imu->begin(), input.imu->end());
  dropUnusableReadings();
}

void PppInsSmoother::forgetGapOfAnOlderState() {
  if (broken_ && !(lastTime() && broken_->start == *lastTime())) broken_.reset();
}

void PppInsSmoother::dropUnusableReadings() {
  // From the newest state a broken interval stays broken (the readings come in time
  // order); before the start, and then, only a start uses readings: the last one at or
  // before its epoch (this one or a later one) and those after it.
  forgetGapOfAnOlderState();
  if (lastTime() && !broken_) return;
  const std::size_t before = readings_.size();
  keepReadingsFrom(epoch_time_);
  dropped_readings_ += before - readings_.size();
}

bool PppInsSmoother::startNav(const ReceiverState& start) {
  const InsStartAttitude attitude = insStartAttitude(ins_, input_readings_, start.position_ecef_m);
  if (!attitude.rotation_ecef_body) {
    epoch_problem_ = {NoSolutionReason::NoInitialAttitude, attitude.problem};
    return false;
  }
  if (!readingHeldAtStart()) return false;
  NavState nav;
  nav.rotation_world_body = *attitude.rotation_ecef_body;
  nav.velocity_world_mps = insStartVelocity_ecef_mps(ins_, start.position_ecef_m);
  nav.position_world_m = start.position_ecef_m - nav.rotation_world_body * ins_.lever_arm_body_m;
  nav_ = nav;
  nav_time_ = epoch_time_;
  bias_ = ImuBias{};
  alignment_ = AlignmentState::Aligned;
  return true;
}

bool PppInsSmoother::readingHeldAtStart() {
  const bool held = std::any_of(readings_.begin(), readings_.end(),
                                [this](const ImuSample& s) { return s.time - epoch_time_ <= 0.0; });
  if (!held)
    epoch_problem_ = {NoSolutionReason::NoImuReadings, "no IMU reading at or before the start " + epoch_time_.toString()};
  return held;
}

bool PppInsSmoother::startLevelOnly(const ReceiverState& start) {
  nav_.reset();
  nav_time_.reset();
  course_nav_.reset();
  level_attitude_.reset();
  epoch_attitude_.reset();
  track_.clear();
  alignment_ = AlignmentState::NotAligned;
  InMotionLevel level = levelInMotion(before_start_, start.position_ecef_m, epoch_time_, ins_.noise);
  if (!level.rotation_ecef_body) {
    epoch_problem_ = {NoSolutionReason::NoInitialAttitude, std::move(level.problem)};
    return false;
  }
  if (!readingHeldAtStart()) return false;
  epoch_attitude_ = level.rotation_ecef_body;
  level_position_ecef_m_ = start.position_ecef_m;
  start_accel_bias_mps2_ = level.accel_bias_mps2;
  start_gyro_bias_radps_ = level.gyro_bias_radps;
  start_gyro_bias_sigma_radps_ = level.gyro_bias_sigma_radps.value_or(ins_.noise.gyro_bias_instability_radps);
  alignment_ = AlignmentState::LevelOnly;
  return true;
}

void PppInsSmoother::predictBeforeNavState(double dt_s, ReceiverState& predicted) {
  // From the newest state: its levelled attitude, or the NavState the course set there.
  if (!level_attitude_ && !course_nav_) return;
  last_bias_ = ImuBias{};
  last_bias_.accel_mps2 = start_accel_bias_mps2_;
  last_bias_.gyro_radps = start_gyro_bias_radps_;
  if (!preintegrateTo(*lastTime() + dt_s)) return;
  NavState from;
  if (course_nav_) {
    from = *course_nav_;
  } else {
    from.rotation_world_body = *level_attitude_;
    from.position_world_m = predicted.position_ecef_m;
  }
  const NavState to = predictNavState(*pim_, from, last_bias_, ecefNavigationFrame(from.position_world_m));
  pim_.reset();  // no IMU factor from a state without a NavState: the NavState starts with priors
  if (!course_nav_) {
    epoch_attitude_ = to.rotation_world_body;
    return;
  }
  nav_ = to;
  nav_time_ = epoch_time_;
  bias_ = last_bias_;
  nav_from_course_ = true;
  predicted.position_ecef_m = AntennaPositionFactor::antennaOf(*nav_, ins_.lever_arm_body_m);
}

void PppInsSmoother::alignFromCourse(const GnssTime& time, const Eigen::Vector3d& antenna_ecef_m) {
  const std::optional<CourseHeading> course = track_.add(time, antenna_ecef_m);
  if (!course || !level_attitude_) return;
  NavState nav;
  nav.rotation_world_body = *level_attitude_;
  nav.position_world_m = antenna_ecef_m - nav.rotation_world_body * ins_.lever_arm_body_m;
  nav = alignedToCourse(nav, course->heading.heading_rad, antenna_ecef_m, ins_.lever_arm_body_m);
  nav.velocity_world_mps = course->velocity_ecef_mps;
  course_nav_ = nav;
  course_heading_sigma_rad_ = course->heading.heading_sigma_rad;
}

ReceiverState PppInsSmoother::predict(double dt_s, bool first, const std::optional<ReceiverState>& start) {
  ReceiverState predicted = PppSmoother::predict(dt_s, first, start);
  pim_.reset();
  last_nav_.reset();
  nav_from_course_ = false;
  if (start) {
    // A start keeps only the readings at and after the last one at or before it.
    keepReadingsFrom(epoch_time_);
    if (in_motion_)
      startLevelOnly(*start);
    else
      startNav(*start);
    return predicted;
  }
  const std::optional<std::uint32_t> last = newestStateIndex();
  if (!last) return predicted;
  if (!isam2().exists(navKey(*last))) {
    if (in_motion_) predictBeforeNavState(dt_s, predicted);
    return predicted;
  }
  last_nav_ = navStateFromStorage(isam2().calculateEstimate(navKey(*last)));
  last_bias_ = ImuBias::fromVector(isam2().calculateEstimate(imuBiasKey(*last)));
  if (!preintegrateTo(*lastTime() + dt_s)) return predicted;
  nav_ = predictNavState(*pim_, *last_nav_, last_bias_, ecefNavigationFrame(last_nav_->position_world_m));
  nav_time_ = epoch_time_;
  bias_ = last_bias_;
  predicted.position_ecef_m = AntennaPositionFactor::antennaOf(*nav_, ins_.lever_arm_body_m);
  predicted_antenna_m_ = predicted.position_ecef_m;
  return predicted;
}

bool PppInsSmoother::preintegrateTo(const GnssTime& time) {
  const GnssTime from = *lastTime();
  forgetGapOfAnOlderState();
  // A gap that a later reading ended is for good: said as it was first found (its readings dropped since).
  const ImuCoverage coverage = broken_ ? *broken_ : imuCoverage(readings_, from, time, ins_.max_imu_interval_s);
  if (coverage.problem == ImuCoverageProblem::Gap && !coverage.held_to_end) broken_ = coverage;
  if (!coverage.covered()) {
    epoch_problem_ = {NoSolutionReason::NoImuReadings,
                      "IMU readings do not cover the interval to " + time.toString() + ": " + coverage.text()};
    return false;
  }
  ImuPreintegration pim(ins_.noise, last_bias_);
  pim.integrateBetween(readings_, from, time);
  pim_ = pim;
  return true;
}

bool PppInsSmoother::solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) {
  if (epoch_problem_) return fail(result, EpochStatus::NoSolution, epoch_problem_->first, epoch_problem_->second);
  const bool level_only = in_motion_ && !nav_ && epoch_attitude_;
  if (!nav_ && !level_only)
    return fail(result, EpochStatus::NoSolution, NoSolutionReason::NoInitialAttitude, "no inertial state");
  adaptProcessNoise(in);
  if (!PppSmoother::solve(in, out, result)) return false;
  // The new state is in the graph: the readings before it are no longer needed.
  keepReadingsFrom(in.time);
  before_start_.clear();
  const std::uint32_t index = *newestStateIndex();
  if (!isam2().exists(navKey(index))) {  // level only: the course may give the heading
    level_attitude_ = epoch_attitude_;
    alignFromCourse(in.time, out.solution.state.position_ecef_m);
    return true;
  }
  commitSolvedNavState(index);
  return true;
}

void PppInsSmoother::adaptProcessNoise(const EpochSolveInput& in) {
  // 1. The phase innovations of the arcs with a bias, at the NavState predicted from the newest state.
  noise_scale_ = ProcessNoiseScale{};
  const std::optional<CovariantState>& c = newest_covariance_;
  if (in.first || !pim_ || !last_nav_ || !nav_ || !c || !lastTime() || !(c->time == *lastTime())) return;
  std::vector<PhaseInnovationRow> rows;
  for (const ScreenedMeasurement& s : in.screened) {
    const std::optional<ArcBiasPrior> prior = s.active_arc ? predictedBias(s.m.arc) : std::nullopt;
    if (prior) rows.push_back(phaseInnovationRow(s.m, layout_, prior->bias_m));
  }
  // 2. Their test against the antenna's error added since the newest state; the scale.
  const ProcessNoiseAdaptationOptions& options = ins_.process_noise_adaptation;
  if (!noise_quantile_ || !(noise_quantile_->alpha() == options.false_alarm)) noise_quantile_.emplace(options.false_alarm);
  const Matrix12d density = insNoiseSpectralDensity(ins_.noise, ins_.bias_model);
  Matrix15d accel_noise;
  const InsDiscreteModel since =
      propagatedErrorModel(c->nav, c->bias, readings_, c->time, epoch_time_, ins_, density, &accel_noise);
  const Matrix15d relative = relativeInsErrorCovariance(since, c->covariance);
  noise_scale_ = processNoiseScale(rows, insAntennaPositionCovariance(*nav_, ins_.lever_arm_body_m, relative),
                                   insAntennaPositionCovariance(*nav_, ins_.lever_arm_body_m, accel_noise), options,
                                   *noise_quantile_);
  // 3. The accelerometers' white noise of the IMU factor times the scale: its preintegrated
  // covariance added lambda - 1 times.
  if (!noise_scale_.inflated()) return;
  ImuPreintegration accel(accelerometerNoise(ins_.noise), last_bias_);
  accel.integrateBetween(readings_, c->time, epoch_time_);
  pim_->addCovariance((noise_scale_.scale - 1.0) * accel.covariance());
}

void PppInsSmoother::commitSolvedNavState(std::uint32_t index) {
  if (auto nav = smoothedNavState(index)) nav_ = nav;
  nav_time_ = lastTime();
  bias_ = ImuBias::fromVector(isam2().calculateEstimate(imuBiasKey(index)));
  keepNewestCovariance(index);
  alignment_ = AlignmentState::Aligned;
  course_nav_.reset();
  level_attitude_.reset();
  epoch_attitude_.reset();
}

void PppInsSmoother::keepReadingsFrom(const GnssTime& time) {
  // The last reading at or before `time` holds at `time`; keep it and the later ones.
  auto after = std::upper_bound(readings_.begin(), readings_.end(), time,
                                [](const GnssTime& t, const ImuSample& s) { return t < s.time; });
  if (after != readings_.begin()) --after;
  readings_.erase(readings_.begin(), after);
}

void PppInsSmoother::finishEpoch(EstimatorEpochResult& result) const {
  PppSmoother::finishEpoch(result);
  // An inertial problem is the epoch's reason, also when the screening stopped it first.
  if (epoch_problem_ && result.status != EpochStatus::Ok)
    fail(result, EpochStatus::NoSolution, epoch_problem_->first, epoch_problem_->second);
  result.attitude = attitudeQuality();
}

smoother::NoiseModel::Ptr PppInsSmoother::startNavNoise(const NavState& nav, bool from_course) const {
  // The position's prior is the receiver state's (tied to the antenna).
  Eigen::Matrix<double, 9, 1> sigmas;
  sigmas << Eigen::Vector3d::Constant(ins_.initial_attitude_sigma_rad),
      Eigen::Vector3d::Constant(ins_.initial_velocity_sigma_mps), Eigen::Vector3d::Constant(kFreePositionSigma_m);
  if (!from_course) return NoiseModel::sigmas(sigmas);
  // [attitude; velocity; position] (the NavState tangent): the course's heading sigma about down.
  Eigen::Matrix<double, 9, 9> covariance = sigmas.cwiseAbs2().asDiagonal();
  const Eigen::Matrix3d ned_body = rotationEcefNed(nav.position_world_m).transpose() * nav.rotation_world_body;
  covariance.topLeftCorner<3, 3>() =
      attitudeCovarianceWithHeading(ned_body, covariance.topLeftCorner<3, 3>(), course_heading_sigma_rad_);
  return NoiseModel::covariance(covariance);
}

void PppInsSmoother::addStartPriors(std::uint32_t index, const NavState& nav, const ImuBias& bias, bool from_course,
                                    smoother::NonlinearFactorGraph& factors, smoother::Values& values) const {
  insertNavState(values, navKey(index), nav);
  values.insert(imuBiasKey(index), bias.vector());
  factors.push_back(std::make_shared<NavStatePriorFactor>(navKey(index), nav, startNavNoise(nav, from_course)));
  Eigen::Matrix<double, 6, 1> bias_sigmas;
  // A start in motion (from the course) may have taken the gyros' bias from the levelling.
  bias_sigmas << Eigen::Vector3d::Constant(ins_.noise.accel_bias_instability_mps2),
      Eigen::Vector3d::Constant(from_course ? start_gyro_bias_sigma_radps_ : ins_.noise.gyro_bias_instability_radps);
  factors.push_back(
      std::make_shared<smoother::PriorFactor>(imuBiasKey(index), bias.vector(), NoiseModel::sigmas(bias_sigmas)));
}

void PppInsSmoother::addInertialFactors(const EpochSolveInput& in, std::uint32_t index,
                                        smoother::NonlinearFactorGraph& factors, smoother::Values& values,
                                        smoother::KeyVector& keys) const {
  if (!nav_) return;  // level only (alignment in motion): no NavState yet
  if (in.first || !pim_ || !last_nav_) {
    addStartPriors(index, *nav_, bias_, nav_from_course_, factors, values);
  } else {
    insertNavState(values, navKey(index), *nav_);
    values.insert(imuBiasKey(index), last_bias_.vector());
    factors.push_back(std::make_shared<ImuSmootherFactor>(navKey(index - 1), imuBiasKey(index - 1), navKey(index),
                                                          *pim_, ecefNavigationFrame(last_nav_->position_world_m)));
    factors.push_back(std::make_shared<BiasRandomWalkFactor>(imuBiasKey(index - 1), imuBiasKey(index), ins_.noise,
                                                             in.dt_s));
  }
  factors.push_back(std::make_shared<AntennaPositionFactor>(stateKey(index), navKey(index), layout_.position(),
                                                            ins_.lever_arm_body_m, kAntennaTieSigma_m));
  keys.push_back(navKey(index));
  keys.push_back(imuBiasKey(index));
}

void PppInsSmoother::addRestartInertialFactors(std::uint32_t index, smoother::NonlinearFactorGraph& factors,
                                               smoother::Values& values, smoother::KeyVector& newest) const {
  // The newest state's inertial estimate read before the failed update, with the
  // start's sigmas; the tie to the restarted receiver state carries its position.
  if (!last_nav_) return;
  addStartPriors(index, *last_nav_, last_bias_, false, factors, values);
  factors.push_back(std::make_shared<AntennaPositionFactor>(stateKey(index), navKey(index), layout_.position(),
                                                            ins_.lever_arm_body_m, kAntennaTieSigma_m));
  newest.push_back(navKey(index));
  newest.push_back(imuBiasKey(index));
}

}  // namespace ppp
