#pragma once
// Slip repair: the geometry-free identification of an integer cycle slip of a
// dual-frequency arc across a data gap, so that the arc (and its held integers)
// goes on with its phase corrected. The wide-lane slip dNW = dN1 - dN2 is the
// Melbourne-Wubbena combination after the gap minus the arc's mean before it [wide-lane
// cycles]. The L1 slip follows from the geometry-free phase GF = L1 - L2 [m]
// after the gap minus its prediction from a polynomial fit over the arc's last
// epochs before the gap (the ionosphere's drift through the gap removed):
//   GF jump = lambda1 dN1 - lambda2 dN2 = (lambda1 - lambda2) dN1 + lambda2 dNW.
// One epoch's MW (code noise) is too coarse to round safely, so each integer dNW
// within max_wide_lane_offset_cycles of the MW estimate is tried: a wrong dNW moves
// the L1 estimate by lambda2 / (lambda1 - lambda2) (-4.53 cycles for GPS L1/L2,
// near half a cycle from an integer; -3.95 for Galileo E1/E5a, near an integer).
// The repair is unique when both sigmas (from the noise model) are within their
// bounds, exactly one candidate gives an L1 estimate within the fraction bound of
// an integer and its neighbours (dNW +- 1) do not, nor fit both jumps better (the
// joint misfit: MW offset and L1 fraction, each in its sigmas, squared and summed).
// Otherwise (Galileo E1/E5a, or a Melbourne-Wubbena jump too noisy to round, as under
// time-correlated multipath) every integer dNW within candidate_sigma_factor sigmas
// (at least 1.5 cycles) whose L1 passes is a candidate, and so is every other whose
// joint misfit is plausible (max_joint_misfit) and no larger than a passing one's (a
// dNW nearest the MW estimate whose L1 is just over the bound is not dropped for a
// farther one just under it): the one nearest the MW estimate is applied, the others
// are kept (SlipRepair::alternatives) for the estimator's gap bridge, which chooses by the
// first frequency's phase against the INS-predicted position (gap_bridge.h): GPS
// L1/L2 candidates 2 wide-lane cycles apart move L1 by 9 cycles (1.71 m), Galileo
// E1/E5a ones 1 cycle apart by 4 cycles (0.76 m), while the geometry-free phase
// moves by 9 and 3 mm. Not modelled: the phase wind-up's change through the gap
// (the same cycles on both frequencies: (lambda1 - lambda2) per cycle in the GF
// phase), which a turn during the gap adds to the GF jump.
// The repaired arc is still checked by the estimator's gap bridge (gap_bridge.h).
// References: Blewitt G. (1990) An automatic editing algorithm for GPS data, GRL
// 17(3):199-202; Banville S., Langley R.B. (2010) Instantaneous cycle-slip
// correction for real-time PPP applications, Navigation 57(4):325-334; Zhang X.,
// Li X. (2012) Instantaneous re-initialization in real-time kinematic PPP with
// cycle slip fixing, GPS Solutions 16:315-327.
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ppp {

struct SlipRepairOptions {
  /// Repairs are attempted only where the estimator bridges gaps
  /// (CycleSlipOptions::bridge_max_gap_s); false: never.
  bool enabled = true;
  double max_wide_lane_offset_cycles = 0.6;    // |dNW candidate - MW estimate| bound [wide-lane cycles]
  double max_wide_lane_sigma_cycles = 0.35;    // sigma of the dNW estimate bound [wide-lane cycles]
  double max_l1_fraction_cycles = 0.25;        // |dN1 - round(dN1)| bound [L1 cycles]
  double max_l1_sigma_cycles = 0.15;           // sigma of the dN1 estimate bound [L1 cycles]
  double gf_fit_window_s = 60.0;               // geometry-free samples before the gap in the fit [s]
  int gf_fit_min_points = 5;                   // fewer samples: no repair
  int gf_fit_order = 1;                        // 1 linear, 2 quadratic ionosphere fit
  double phase_sigma_m = 0.003;                // one frequency's phase noise [m] (floor of the fit's)
  double ionosphere_sigma_mps = 5.0e-5;        // the fit's unmodelled drift through the gap [m/s]
  /// Candidates for the gap bridge when the slip is not unique: wide lanes within
  /// candidate_sigma_factor sigmas of the MW estimate (at least
  /// min_candidate_half_width_cycles), tried while the MW sigma is at most this
  /// [wide-lane cycles]; 0: no candidates (a slip that is not unique is refused).
  double max_candidate_wide_lane_sigma_cycles = 1.0;
  double candidate_sigma_factor = 3.0;            // half-width of the search in MW sigmas
  double min_candidate_half_width_cycles = 1.5;   // least half-width of the search [wide-lane cycles]
  int max_candidates = 4;                         // more candidates passing the L1 test: refused
  /// A wide lane whose L1 fails the fraction bound is still a candidate (and a unique
  /// repair's neighbour makes it ambiguous) when its joint misfit (MW offset and L1
  /// fraction, each in its sigmas, squared and summed) is no larger than a passing
  /// one's and at most this: the chi-square quantile of 2 degrees of freedom at
  /// 99.9 % (13.82); 0: never.
  double max_joint_misfit = 13.82;
};

/// One integer slip (dN1, dN2) [cycles] and its L1 estimate [cycles].
struct SlipCandidate {
  long dn1_cycles = 0, dn2_cycles = 0;
  double l1_cycles = 0.0;
};
/// The same integer slip (the L1 estimates aside).
inline bool sameSlip(const SlipCandidate& a, const SlipCandidate& b) {
  return a.dn1_cycles == b.dn1_cycles && a.dn2_cycles == b.dn2_cycles;
}

/// The combinations of one arc across a gap.
struct SlipRepairInput {
  double mw_jump_cycles = 0.0;        // MW after the gap minus the arc's mean [wide-lane cycles]
  double mw_sigma_cycles = 0.0;       // sigma of one epoch's MW [wide-lane cycles]
  int mw_samples = 0;                 // epochs in the arc's mean
  double gf_after_m = 0.0;            // GF phase after the gap [m]
  /// The arc's GF samples before the gap: (time [s], GF [m]), time order, any origin.
  std::vector<std::pair<double, double>> gf_before;
  double time_after_s = 0.0;          // the epoch after the gap, same origin
  double wavelength1_m = 0.0, wavelength2_m = 0.0;
};

enum class SlipRepairOutcome {
  Repaired,             // a non-zero integer slip identified
  NoSlip,               // both estimates round to zero
  TooFewSamples,        // not enough GF samples before the gap for the fit
  WideLaneTooUncertain,
  L1TooUncertain,
  L1NotInteger,         // no wide-lane candidate gives an integer L1
  Ambiguous,            // more than one does, or a neighbour of the one that does (without candidates)
  TooManyCandidates,    // more than SlipRepairOptions::max_candidates pass the L1 test
};
const char* slipRepairOutcomeName(SlipRepairOutcome outcome);

struct SlipRepair {
  SlipRepairOutcome outcome = SlipRepairOutcome::TooFewSamples;
  long dn1_cycles = 0, dn2_cycles = 0;  // the slip (Repaired, NoSlip)
  double wide_lane_cycles = 0.0, wide_lane_sigma_cycles = 0.0;  // dNW estimate
  double l1_cycles = 0.0, l1_sigma_cycles = 0.0;                // dN1 estimate (given the chosen dNW)
  double gf_prediction_m = 0.0;  // the fit's GF at the epoch after the gap [m]
  /// The other slips the geometry-free phase allows (Repaired, NoSlip; nearest the MW
  /// estimate first): the estimator's gap bridge chooses among them and the applied one.
  std::vector<SlipCandidate> alternatives;
  /// Readable, e.g. "dN1 +3 dN2 -2 (WL 5.04 +- 0.27, L1 3.02 +- 0.08)" or
  /// "L1 not an integer for any wide lane within 1.0 cycles of 5.04: ...".
  std::string text;
  bool accepted() const { return outcome == SlipRepairOutcome::Repaired || outcome == SlipRepairOutcome::NoSlip; }
  /// The applied slip as a candidate.
  SlipCandidate applied() const { return {dn1_cycles, dn2_cycles, l1_cycles}; }
  /// Applies `chosen` (one of the alternatives, or the applied one) in place of the applied
  /// slip: the others become the alternatives, the text says it was chosen.
  void choose(const SlipCandidate& chosen);
};

/// "dN1 +3 dN2 -2".
std::string slipText(long dn1_cycles, long dn2_cycles);

/// A polynomial fit's value at t and its sigma [m].
struct GeometryFreePrediction {
  double value_m = 0.0;
  double sigma_m = 0.0;
};

/// Least squares of a polynomial of `order` (1 or 2) in time through `samples`,
/// extrapolated to t_s; its sigma from the residuals' scatter (at least
/// noise_floor_m per sample). nullopt with fewer than order + 2 samples.
std::optional<GeometryFreePrediction> predictGeometryFreeFit(const std::vector<std::pair<double, double>>& samples,
                                                             double t_s, int order, double noise_floor_m);

/// The slip of one arc across a gap (see the header comment).
SlipRepair repairSlip(const SlipRepairInput& input, const SlipRepairOptions& options);

}  // namespace ppp
