#pragma once
// The adaptive process noise of the GNSS/INS estimators (PppInsEkf, PppInsSmoother):
// the test of the inertial prediction against the epoch's carrier phases, and the
// scale of the prediction's process noise it implies (covariance matching: Mehra
// 1972, IEEE Trans. Autom. Control 17(5):693-698; for GNSS/INS, Mohamed & Schwarz
// 1999, Journal of Geodesy 73:193-203).
//
// Why. An IMU's noise preset gives its sensor noise, not the errors the mechanization
// makes where the error states have no place for them: scale factors and axis
// misalignments of a consumer IMU carried by hand, vibration, an attitude error that
// turns large accelerations into velocity. Then the prediction is confidently wrong:
// its phase innovations are many of their predicted sigmas, the postfit test rejects
// the phases of satellites that are right, and the update turns the phases it keeps
// into metre-sized steps along the geometry's weakest direction (the position against
// the white receiver clocks), which the code, weighted for its time correlation, pulls
// back only over tens of seconds (doc/studies/ins_walk.md, "The error after the weak
// geometry").
//
// The test. Each measurement whose arc has a bias gives a row: its phase at the
// prediction minus the bias. An arc's bias was fitted with the last solved state, so
// the row sees the error the prediction added since that state: the antenna's
// relative position error, of covariance D = (A - I) P (A - I)^T + Q, where P is the
// INS error covariance of that state and A, Q the transition and process noise of the
// propagation since (relativeInsErrorCovariance), mapped to the antenna. The receiver
// clocks (one per system in the rows) are free. T, the normalised innovation square,
// has rows - clocks degrees of freedom. The satellite whose leaving lowers T most is
// left out (one outlier, e.g. a slip the tracker missed, is the postfit test's, not a
// reason to trust the INS less). When T exceeds the chi-square quantile of its degrees
// of freedom at the false-alarm probability, the process noise is scaled by the
// lambda > 1 that brings T to its expectation (the degrees of freedom). What is scaled
// is the accelerometers' white noise, the velocity random walk: the errors above act on
// the specific force the mechanization integrates (a scale factor or misalignment times
// the acceleration, vibration, an attitude error turning the acceleration), and scaling
// the gyros' noise or the bias drivings instead lets the attitude and the biases take up
// what is velocity (on the walk the 15-s coasts grew from a median of 17 m to 25 m with
// the gyros' noise scaled too). Q_a -> lambda Q_a in the prediction's covariance (the
// EKF) or the IMU factor's (the smoother). A prediction consistent with the phases keeps
// its noise (lambda = 1).
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/ins_error_state.h"
#include "ppp_bayes_tree/ppp/model/receiver_state_layout.h"
#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"
#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"

namespace ppp {

struct ProcessNoiseAdaptationOptions {
  /// Scale the process noise of an inconsistent prediction; on by default.
  bool enabled = true;
  /// False-alarm probability of the prediction's test (0 < value < 0.5).
  double false_alarm = 1.0e-3;
  /// The largest scale of the process noise (>= 1).
  double max_scale = 1.0e6;

  /// Empty when valid; otherwise the first problem.
  std::string validate() const;
};

/// One phase innovation at the prediction.
struct PhaseInnovationRow {
  SatelliteId satellite;
  Eigen::Vector3d d_antenna_m = Eigen::Vector3d::Zero();  ///< d(phase)/d(antenna position ECEF)
  GnssSystem clock_system = GnssSystem::GPS;              ///< the receiver clock of the row
  double innovation_m = 0.0;                              ///< phase residual at the prediction - bias
  double variance_m2 = 0.0;                               ///< the phase's
};

/// The row of a measurement whose arc has a bias `bias_m` [m] (its value at the
/// prediction), from the layout's position columns of its Jacobian.
PhaseInnovationRow phaseInnovationRow(const SatelliteMeasurement& m, const ReceiverStateLayout& layout, double bias_m);

/// The spectral densities of the accelerometers' white noise alone (`density` of
/// insNoiseSpectralDensity with the other blocks zero): the part of the process noise
/// the adaptation scales.
Matrix12d accelerometerNoiseDensity(const Matrix12d& density);
/// The same for the preintegration (ImuPreintegration): `noise` with only its
/// accelerometer noise density.
ImuNoise accelerometerNoise(const ImuNoise& noise);

/// The covariance of the INS error added since a state of error covariance `covariance`
/// by a propagation of transition A and process noise Q (`since`): (A - I) P (A - I)^T + Q.
Matrix15d relativeInsErrorCovariance(const InsDiscreteModel& since, const Matrix15d& covariance);

/// What the test found and the scale it implies.
struct ProcessNoiseScale {
  double scale = 1.0;       ///< lambda: the process noise's factor (1: consistent, or not tested)
  double statistic = 0.0;   ///< T at lambda = 1, the satellite left out not in it
  double quantile = 0.0;    ///< the chi-square quantile T was tested against
  int dof = 0;              ///< T's degrees of freedom (0: not tested)
  std::optional<SatelliteId> left_out;
  bool inflated() const { return scale > 1.0; }
  std::string text() const;
};

/// The test and the scale, from the rows, the antenna's relative position covariance
/// (all process noise included) and the part of it from the accelerometers' white noise [m^2].
ProcessNoiseScale processNoiseScale(const std::vector<PhaseInnovationRow>& rows, const Eigen::Matrix3d& relative_cov_m2,
                                    const Eigen::Matrix3d& process_cov_m2, const ProcessNoiseAdaptationOptions& options,
                                    const ChiSquareUpperQuantile& quantile);

}  // namespace ppp
