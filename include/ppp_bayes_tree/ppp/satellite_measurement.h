#pragma once
// The linearised IF code and phase measurement of one satellite at one epoch:
// what both estimators (EKF and smoother factors) consume from the single
// measurement model, so that they cannot drift apart.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/dual_frequency_observation.h"

namespace ppp {

/// Receiver state of one epoch: X = (position, zenith wet delay, receiver clock).
struct ReceiverState {
  static constexpr int kDim = 5;  // x, y, z [m], ZWD [m], clock [m]
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  double zwd_m = 0.0;
  double clock_m = 0.0;  // receiver clock bias times c (absorbs the IF code bias)

  Eigen::Matrix<double, kDim, 1> vector() const {
    Eigen::Matrix<double, kDim, 1> v;
    v << position_ecef_m, zwd_m, clock_m;
    return v;
  }
  static ReceiverState fromVector(const Eigen::Matrix<double, kDim, 1>& v) {
    ReceiverState s;
    s.position_ecef_m = v.head<3>();
    s.zwd_m = v(3);
    s.clock_m = v(4);
    return s;
  }
};

struct SatelliteMeasurement {
  SatelliteId satellite;
  ArcId arc = 0;
  // Predicted IF observables at the linearisation point [m]. The phase
  // prediction excludes the arc's IF phase bias (bias enters with coefficient +1).
  double predicted_code_m = 0.0;
  double predicted_phase_m = 0.0;
  // Observed IF observables [m].
  double observed_code_m = 0.0;
  double observed_phase_m = 0.0;
  /// d(predicted)/d(x, y, z, zwd, clock); identical for code and phase.
  Eigen::Matrix<double, 1, ReceiverState::kDim> jacobian = Eigen::Matrix<double, 1, ReceiverState::kDim>::Zero();
  // Elevation-dependent standard deviations [m] of the IF observables.
  double code_sigma_m = 0.0;
  double phase_sigma_m = 0.0;
  double elevation_rad = 0.0;
  double azimuth_rad = 0.0;
  // Range geometry at the linearisation point, so that a smoother factor can
  // re-evaluate the geometric range exactly at another state of the same epoch
  // (ppp_factors.h): the satellite antenna phase centre at emission, rotated for
  // the Earth rotation during the flight (ECEF at reception), and the offset
  // marker -> receiver antenna phase centre (tides, loading, eccentricity, PCO).
  // nullopt when the producer gives no geometry (then factors stay linear).
  std::optional<Eigen::Vector3d> satellite_apc_ecef_m;
  Eigen::Vector3d receiver_apc_offset_ecef_m = Eigen::Vector3d::Zero();

  double codeResidual_m() const { return observed_code_m - predicted_code_m; }
  /// Phase residual before the bias: observed - predicted (the bias estimate is subtracted by the caller).
  double phaseResidualWithoutBias_m() const { return observed_phase_m - predicted_phase_m; }
};

/// A satellite left out of an epoch, with the reason ("elevation 4.2 deg below
/// cutoff 7 deg", "no orbit: gap ...", "prefit code residual 35 m > 10 m").
struct RejectedSatellite {
  SatelliteId satellite;
  std::string reason;
};

struct EpochMeasurements {
  GnssTime time;
  std::vector<SatelliteMeasurement> used;
  std::vector<RejectedSatellite> rejected;
};

}  // namespace ppp
