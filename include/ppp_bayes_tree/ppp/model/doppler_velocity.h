#pragma once
// DopplerVelocity: the receiver antenna's velocity and clock drift of one epoch
// from its Doppler range rates (doppler_observation.h) by weighted least squares
// at a known approximate position, with an outlier screen.
//
// Unknowns: the antenna velocity (ECEF, 3) and one receiver clock drift [m/s]
// common to all systems (one oscillator; the inter-system biases do not drift).
// Weights: sigma(el) = sigma_zenith / sin(el), the elevation-dependent model of
// the code and phase (Misra & Enge 2006, ch. 6.2; Groves 2013, 9.4.2). The
// screen: while the largest normalised residual |r_i| / sqrt(Q_r,ii) (Baarda's
// w-test, Teunissen, "Testing theory", 2006) exceeds outlier_threshold and a
// satellite can be spared (more than min_satellites left), that satellite is
// rejected and the solve repeated; an outlier with none to spare: no solution. The covariance is (A^T W A)^-1 scaled by the
// a posteriori variance factor when that is above 1 (the sigmas too small).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/doppler_observation.h"

namespace ppp {

struct DopplerVelocityOptions {
  /// Use the Doppler (GNSS/INS filter: a velocity update each epoch).
  bool enabled = true;
  /// Sigma of one range rate at the zenith [m/s]. 0.05 m/s: on the hand-held
  /// u-blox walk (doc/studies/ins_walk.md) the a posteriori variance factor is 1.6
  /// at the median (0.44-2.6 between the quartiles), and the covariance is scaled
  /// by it when above 1.
  double sigma_zenith_mps = 0.05;
  /// Satellites below this elevation are not used [rad] (7 deg, as the PPP model).
  double elevation_cutoff_rad = 0.1222;
  /// Normalised-residual threshold of the outlier screen.
  double outlier_threshold = 4.0;
  /// Fewest satellites of a solution (4 unknowns + 1 to screen).
  int min_satellites = 5;
  /// The filter's velocity update is refused when its innovation's normalised
  /// square (chi-square, 3 dof) exceeds this: a guard against gross errors only
  /// (the outliers are the screen's). Not the 99.9 % quantile (16.27): the
  /// velocity covariance of a hand-held consumer IMU's filter is too small, and
  /// that test refused 106 of the walk's 354 epochs, when the filter was off.
  double innovation_chi2 = 100.0;

  /// Empty when valid; otherwise the first problem.
  std::string validate() const;
};

enum class DopplerVelocityStatus { Ok, TooFewSatellites, Singular, UnresolvedOutlier };
const char* dopplerVelocityStatusText(DopplerVelocityStatus status);

struct DopplerVelocitySolution {
  DopplerVelocityStatus status = DopplerVelocityStatus::TooFewSatellites;
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();
  double clock_drift_mps = 0.0;
  Eigen::Matrix3d velocity_covariance = Eigen::Matrix3d::Zero();  // [m^2/s^2]
  double variance_factor = 1.0;  // a posteriori, sum w r^2 / (n - 4)
  std::vector<SatelliteId> used;
  std::vector<SatelliteId> rejected;   // by the outlier screen
  int below_cutoff = 0;
  bool ok() const { return status == DopplerVelocityStatus::Ok; }
};

/// The velocity of an antenna at `receiver_ecef_m` from `observations`.
DopplerVelocitySolution solveDopplerVelocity(const std::vector<DopplerObservation>& observations,
                                             const Eigen::Vector3d& receiver_ecef_m,
                                             const DopplerVelocityOptions& options);

}  // namespace ppp
