#pragma once
// Gap bridge: INS-aided cycle-slip identification across a data gap. For the arcs
// back after a gap that the arc tracker bridged (arc_tracker.h,
// CycleSlipOptions::bridge_max_gap_s), each row is the ionosphere-free phase
// minus the model at the predicted state minus the arc's held bias [m]: without a
// slip only the predicted antenna position's error, the receiver clock (white
// noise, unknown after the gap) and the phase noise. A least squares of a
// position correction (prior: the predicted position's covariance, the INS
// through the gap) and one clock per system leaves each arc's residual; in
// narrow-lane cycles (an N1 = N2 slip, the one the Melbourne-Wubbena test leaves,
// moves the ionosphere-free bias by whole narrow-lane wavelengths) it is the slip.
// An arc goes on when its slip is within max_fraction_cycles of zero with a sigma
// of at most max_sigma_cycles; the worst arc failing is ended and the rest solved
// again. Reference: Du S., Gao Y. (2012), Inertial aided cycle slip detection and
// identification for integrated PPP GPS and INS, Sensors 12(11):14344-14362.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace ppp {

struct GapBridgeOptions {
  double max_fraction_cycles = 0.2;  // |slip| bound [narrow-lane cycles]
  double max_sigma_cycles = 0.15;    // sigma of the slip estimate bound [narrow-lane cycles]
  int min_extra_rows = 2;            // rows beyond the unknowns (position, clocks) to test at all
  /// Floor of the position prior's sigma per axis [m]: a margin against an optimistic
  /// INS covariance through the gap (a prior tighter than the true error turns the
  /// position error into apparent slips). With the covariance grown through a 30-s
  /// outage the simulated flights' arcs pass without it (test_ins_gap_bridge).
  /// 0: the prior as given.
  double min_position_sigma_m = 1.0;
};

struct GapBridgeRow {
  double residual_m = 0.0;           // phase - model(prediction) - held bias [m]
  Eigen::RowVector3d position_jacobian = Eigen::RowVector3d::Zero();  // d phase / d antenna position
  int clock = 0;                     // the row's clock (0, 1, ...: one per system)
  double sigma_m = 0.0;              // phase noise and bias sigma [m]
  double wavelength_m = 0.0;         // narrow-lane wavelength [m]
};

struct GapBridgeVerdict {
  bool keep = false;
  double slip_cycles = 0.0;   // the residual in narrow-lane cycles (NaN when not estimated)
  double sigma_cycles = 0.0;
  std::string reason;         // why the arc ends; empty when kept
};

/// One verdict per row (same order).
std::vector<GapBridgeVerdict> bridgeGap(const std::vector<GapBridgeRow>& rows, const Eigen::Matrix3d& position_cov_m2,
                                        const GapBridgeOptions& options = {});

}  // namespace ppp
