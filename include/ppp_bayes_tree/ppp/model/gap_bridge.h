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
// again. A row may carry candidates (a slip repair that the geometry-free phase
// could not make unique, slip_repair.h): each moves its residual by a known offset.
// Every assignment of candidates to those rows is tried: the least-squares cost with
// the position prior (a quadratic form in the offsets) plus each row's prior cost of
// its candidate (its wide lane against the Melbourne-Wubbena jump). The least is
// taken when it fits the noise (a chi-square test; else the row whose exclusion
// lowers the best cost the most ends: a row whose applied slip is wrong and has no
// candidates drags the others to candidates far from their MW jumps) and the next
// best costs clearly more (a difference and a ratio, as in integer ambiguity
// validation); else the rows where the two differ end.
// Assignments that differ by one integer slip common to every row of a clock are
// twins: the phases cannot tell them apart (that clock takes the shift), and when no
// arc outside the bridge holds that system's clock (GapBridgeRow::clock_free) nothing
// can, and nothing needs to: every bias of the system, and of any arc that starts
// later, carries the same shift, so the integer differences between satellites and
// the position are the same with either. The next best is then the least costly
// assignment that is not a twin of the best; a twin the wide lanes' costs do not
// tell apart is reported (common_shift_undecided). References: Du S., Gao Y.
// (2012), Inertial aided cycle slip detection and identification for integrated
// PPP GPS and INS, Sensors 12(11):14344-14362; Banville S., Langley R.B. (2013)
// Mitigating the impact of ionospheric cycle slips in GNSS observations, J Geod
// 87:179-193 (candidates of a slip tested by their fit, sec. 4).
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
  /// Rows with candidates: the assignment of least cost is taken when the next best
  /// costs at least this squared more
  /// [cost: squared sigmas] and min_candidate_ratio times as much; else the rows
  /// where the two differ end.
  double min_candidate_separation = 5.0;
  double min_candidate_ratio = 3.0;
  /// With candidates the best assignment's cost must be within the chi-square upper
  /// quantile of this false-alarm probability for its degrees of freedom (chi_square_quantile.h).
  double candidate_cost_false_alarm = 1e-3;
  /// More assignments than this: the rows with the most candidates end first. It
  /// also bounds the assignments ranked to find the row to end when the best cost does
  /// not fit (once per row: rows x assignments).
  double max_candidate_assignments = 100000.0;
};

struct GapBridgeRow {
  double residual_m = 0.0;           // phase - model(prediction) - held bias [m]
  Eigen::RowVector3d position_jacobian = Eigen::RowVector3d::Zero();  // d phase / d antenna position
  int clock = 0;                     // the row's clock (0, 1, ...: one per system)
  double sigma_m = 0.0;              // phase noise and bias sigma [m]
  double wavelength_m = 0.0;         // narrow-lane wavelength [m]
  /// Candidates: what each adds to residual_m in place of the slip applied [m] (empty: none).
  std::vector<double> candidate_offsets_m;
  /// With candidates: the prior cost [squared sigmas] of the slip applied and of each
  /// candidate (their wide lanes against the Melbourne-Wubbena jump); missing ones 0.
  double applied_prior_cost = 0.0;
  std::vector<double> candidate_prior_costs;
  /// With candidates: each candidate's wide lane minus the applied slip's [cycles]
  /// (with the L1 offsets, what makes a shift common to a clock's rows; missing ones 0).
  std::vector<long> candidate_wide_lane_offsets_cycles;
  /// No arc outside these rows holds this row's clock (every arc of its system with a
  /// bias is bridged here): a slip common to all of the clock's rows is the clock's.
  bool clock_free = false;
};

struct GapBridgeVerdict {
  bool keep = false;
  double slip_cycles = 0.0;   // the residual in narrow-lane cycles (NaN when not estimated)
  double sigma_cycles = 0.0;
  /// The candidate chosen (index into GapBridgeRow::candidate_offsets_m); -1: the slip applied.
  int candidate = -1;
  /// Kept with a twin (gap_bridge.h) that the wide lanes' prior costs could not tell
  /// apart: the integers between the clock's arcs hold, the wide lanes of its arcs may
  /// all be one slip off the Melbourne-Wubbena means before the gap (the caller's
  /// wide-lane means start again from this epoch).
  bool common_shift_undecided = false;
  std::string reason;         // why the arc ends; empty when kept
};

/// One verdict per row (same order).
std::vector<GapBridgeVerdict> bridgeGap(const std::vector<GapBridgeRow>& rows, const Eigen::Matrix3d& position_cov_m2,
                                        const GapBridgeOptions& options = {});

}  // namespace ppp
