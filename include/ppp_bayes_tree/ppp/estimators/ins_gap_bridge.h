#pragma once
// The gap bridge of the GNSS/INS estimators (PppInsEkf, PppInsSmoother): at the first
// epoch after a data gap the arc tracker bridged (PppEstimator::gapBridgeMax_s), each
// arc back is tested against the INS prediction through the gap (gap_bridge.h:
// INS-aided cycle-slip identification, Du & Gao 2012). Its row is the first
// frequency's phase at the predicted state minus the arc's bias before the gap, with
// the ionosphere's drift through the gap removed by the geometry-free fit; the
// position prior is the antenna position's error covariance grown through the gap.
// An arc without a measurement, a bias or a geometry-free fit ends; one whose slip
// test passes goes on with its bias and held integers; any other ends. An arc whose
// slip repair has candidates (SlipRepair::alternatives) carries them into its row
// (the L1 offsets and their wide lanes' costs against the Melbourne-Wubbena jump):
// the test chooses one (BridgedArcVerdict::chosen), which the estimator has applied.
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_input.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_result.h"
#include "ppp_bayes_tree/ppp/model/gap_bridge.h"
#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"

namespace ppp {

/// What the gap bridge decided for one bridged arc.
struct BridgedArcVerdict {
  const BridgedArc* arc = nullptr;
  bool keep = false;
  /// Kept with another candidate of its slip repair than the one applied (SlipRepair::alternatives).
  std::optional<SlipCandidate> chosen;
  /// Kept, its wide lane possibly one slip off with every arc of its system
  /// (GapBridgeVerdict::common_shift_undecided): its wide-lane mean starts again.
  bool common_shift_undecided = false;
  std::string text;  ///< ended: the reason; kept: the line of EstimatorEpochResult::gap_bridge
};

/// The slip test's row of a bridged arc's measurement at the prediction, given the arc's
/// bias before the gap [m] and the receiver layout's position index; nullopt without a
/// geometry-free fit or a wavelength.
std::optional<GapBridgeRow> insGapBridgeRow(const BridgedArc& bridged, const SatelliteMeasurement& m,
                                            double held_bias_m, int position_index);

/// The verdicts on the bridged arcs: first those without a row (in order), then those
/// tested (in order). held_bias_m: the arc's bias before the gap, nullopt without one.
std::vector<BridgedArcVerdict> insGapBridgeVerdicts(const std::vector<BridgedArc>& bridged,
                                                    const std::vector<SatelliteMeasurement>& usable,
                                                    const std::function<std::optional<double>(ArcId)>& held_bias_m,
                                                    int position_index, const Eigen::Matrix3d& position_cov_m2,
                                                    const GapBridgeOptions& options);

/// Ends (end_arc, with the reason) or keeps (counted, its line) each arc, in order; a
/// kept arc with another candidate of its repair has it applied first (choose; ended
/// when that fails); a kept arc whose shift common to its system is undecided has its
/// wide-lane mean started again in `resolver` (AmbiguityResolver::restartWideLane).
void applyBridgedArcVerdicts(const std::vector<BridgedArcVerdict>& verdicts,
                             const std::function<void(const BridgedArc&, const std::string&)>& end_arc,
                             const std::function<bool(const BridgedArc&, const SlipCandidate&)>& choose,
                             AmbiguityResolver& resolver, EstimatorEpochResult& result);

/// The least variance per axis of the position covariance grown through a gap [m^2].
constexpr double kMinGapPositionVariance_m2 = 1e-6;
/// The antenna position's error covariance grown through a gap: `after` (the prediction's)
/// minus `before` (the last epoch's), symmetric, each eigenvalue at least kMinGapPositionVariance_m2.
Eigen::Matrix3d grownGapPositionCovariance(const Eigen::Matrix3d& after, const Eigen::Matrix3d& before);

}  // namespace ppp
