#pragma once
// The linearised IF code and phase measurement of one satellite at one epoch:
// what both estimators (EKF and smoother factors) consume from the single
// measurement model, so that they cannot drift apart.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"
#include "ppp_bayes_tree/ppp/model/receiver_state_layout.h"
#include "ppp_bayes_tree/ppp/model/rejection_reason.h"

namespace ppp {

/// Receiver state of one epoch, with named members; vector() / fromVector()
/// order them by the layout (receiver_state_layout.h): position, ZWD, one
/// receiver clock per processed system (GPS only: (x, y, z, zwd, clock)), and
/// the horizontal tropospheric gradients when the layout has them.
struct ReceiverState {
  ReceiverStateLayout layout;
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  double zwd_m = 0.0;
  /// Horizontal tropospheric gradients G_N, G_E [m] (troposphere_gradient.h);
  /// part of the vector only when layout.hasGradients(), else kept at 0.
  double gradient_north_m = 0.0;
  double gradient_east_m = 0.0;

  ReceiverState() { clocks_m_.fill(0.0); }
  explicit ReceiverState(const ReceiverStateLayout& state_layout) : layout(state_layout) { clocks_m_.fill(0.0); }

  /// Receiver clock bias times c [m] of a system (absorbs the system's IF code bias).
  double clock_m(GnssSystem system) const { return clocks_m_[static_cast<int>(system)]; }
  void setClock_m(GnssSystem system, double clock_m) { clocks_m_[static_cast<int>(system)] = clock_m; }
  /// The clock of the layout's first system (the reference system, GPS by default).
  double referenceClock_m() const { return clock_m(layout.clockSystem(layout.firstClock())); }

  Eigen::VectorXd vector() const {
    Eigen::VectorXd v(layout.dim());
    v.segment<ReceiverStateLayout::kPositionSize>(layout.position()) = position_ecef_m;
    v(layout.zwd()) = zwd_m;
    for (int i = layout.firstClock(); i < layout.firstClock() + layout.clockCount(); ++i)
      v(i) = clock_m(layout.clockSystem(i));
    if (layout.hasGradients()) {
      v(layout.gradientNorth()) = gradient_north_m;
      v(layout.gradientEast()) = gradient_east_m;
    }
    return v;
  }
  static ReceiverState fromVector(const Eigen::VectorXd& v, const ReceiverStateLayout& layout = {}) {
    ReceiverState s(layout);
    s.position_ecef_m = v.segment<ReceiverStateLayout::kPositionSize>(layout.position());
    s.zwd_m = v(layout.zwd());
    for (int i = layout.firstClock(); i < layout.firstClock() + layout.clockCount(); ++i)
      s.setClock_m(layout.clockSystem(i), v(i));
    if (layout.hasGradients()) {
      s.gradient_north_m = v(layout.gradientNorth());
      s.gradient_east_m = v(layout.gradientEast());
    }
    return s;
  }

 private:
  std::array<double, kNumGnssSystems> clocks_m_;
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
  /// d(predicted)/d(receiver state) in the state's layout: position, ZWD, 1
  /// in the satellite's own system clock column, and the gradient mapping times
  /// (cos az, sin az) in the gradient columns when the layout has them;
  /// identical for code and phase.
  Eigen::RowVectorXd jacobian;
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

/// A satellite left out of an epoch: the reason (counted), and the readable
/// detail with its values ("elevation 4.2 deg below cutoff 7.0 deg", "no orbit:
/// gap ...", "prefit code residual 35 m > 10 m").
struct RejectedSatellite {
  SatelliteId satellite;
  RejectionReason reason = RejectionReason::NonFiniteModel;
  std::string detail;
  /// The detail, or the reason's name when there is none.
  std::string text() const { return detail.empty() ? toString(reason) : detail; }
};

struct EpochMeasurements {
  GnssTime time;
  std::vector<SatelliteMeasurement> used;
  std::vector<RejectedSatellite> rejected;
};

}  // namespace ppp
