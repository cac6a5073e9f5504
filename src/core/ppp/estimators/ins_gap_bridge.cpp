#include "ppp_bayes_tree/ppp/estimators/ins_gap_bridge.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

std::optional<GapBridgeRow> insGapBridgeRow(const BridgedArc& bridged, const SatelliteMeasurement& m,
                                            double held_bias_m, int position_index) {
  if (!bridged.gf_jump_m || !(bridged.wavelength1_m > 0.0)) return std::nullopt;
  GapBridgeRow row;
  // The first frequency's phase (L1 = IF - beta GF): its slip in its own cycles,
  // with the ionosphere's drift through the gap removed by the GF fit.
  const double beta = bridged.geometry_free_factor;
  row.residual_m = m.phaseResidualWithoutBias_m() - held_bias_m - beta * *bridged.gf_jump_m;
  row.position_jacobian = m.jacobian.segment<3>(position_index);
  row.clock = static_cast<int>(m.satellite.system);
  // The bias fitted the arc's phase at the last epoch: what is left is the phase
  // noise of both epochs (the bias's own sigma is mostly common to all arcs, in
  // the clocks and the position, and cancels in the difference).
  // The IF sigma scaled to one frequency's: IF = (1 + beta) L1 - beta L2.
  row.sigma_m = std::sqrt(2.0) * m.phase_sigma_m / std::hypot(1.0 + beta, beta);
  row.wavelength_m = bridged.wavelength1_m;
  // The repair's other candidates: another L1 slip moves this row by its difference;
  // each wide lane's prior cost from the Melbourne-Wubbena jump.
  if (bridged.repair && !bridged.repair->alternatives.empty()) {
    const SlipRepair& r = *bridged.repair;
    const auto wide_lane_cost = [&r](const SlipCandidate& c) {
      const double z = (static_cast<double>(c.dn1_cycles - c.dn2_cycles) - r.wide_lane_cycles) /
                       std::max(r.wide_lane_sigma_cycles, 1e-3);
      return z * z;
    };
    row.applied_prior_cost = wide_lane_cost(r.applied());
    for (const SlipCandidate& c : r.alternatives) {
      row.candidate_offsets_m.push_back(-static_cast<double>(c.dn1_cycles - r.dn1_cycles) * bridged.wavelength1_m);
      row.candidate_prior_costs.push_back(wide_lane_cost(c));
      row.candidate_wide_lane_offsets_cycles.push_back((c.dn1_cycles - c.dn2_cycles) -
                                                       (r.dn1_cycles - r.dn2_cycles));
    }
  }
  return row;
}

namespace {

/// The line of a kept arc, with its repair as the bridge chose it (`chosen`: another candidate).
std::string keptLine(const BridgedArc& b, const GapBridgeVerdict& v, const std::optional<SlipCandidate>& chosen) {
  std::string repair;
  if (b.repair) {
    SlipRepair r = *b.repair;
    if (chosen) r.choose(*chosen);
    repair = " after the slip repair " + r.text;
  }
  return b.satellite.toString() + " arc " + std::to_string(b.arc) + ": gap of " +
         format("%.0f s bridged, slip %.2f +- %.2f cycles", b.gap_s, v.slip_cycles, v.sigma_cycles) + repair;
}

}  // namespace

std::vector<BridgedArcVerdict> insGapBridgeVerdicts(const std::vector<BridgedArc>& bridged,
                                                    const std::vector<SatelliteMeasurement>& usable,
                                                    const std::function<std::optional<double>(ArcId)>& held_bias_m,
                                                    int position_index, const Eigen::Matrix3d& position_cov_m2,
                                                    const GapBridgeOptions& options) {
  // 1. One row per bridged arc with a measurement and a held bias; the others end.
  std::vector<BridgedArcVerdict> out;
  std::vector<GapBridgeRow> rows;
  std::vector<const BridgedArc*> row_arcs;
  std::vector<int> system_clock(kNumGnssSystems, -1);
  for (const BridgedArc& b : bridged) {
    const auto m = std::find_if(usable.begin(), usable.end(), [&](const SatelliteMeasurement& u) { return u.arc == b.arc; });
    std::optional<GapBridgeRow> row;
    const std::optional<double> bias_m = held_bias_m(b.arc);
    if (m != usable.end() && bias_m) row = insGapBridgeRow(b, *m, *bias_m, position_index);
    if (!row) {
      out.push_back({&b, false, std::nullopt, false, "no usable measurement, held bias or geometry-free fit at the prediction"});
      continue;
    }
    int& clock = system_clock[static_cast<std::size_t>(row->clock)];
    if (clock < 0) clock = *std::max_element(system_clock.begin(), system_clock.end()) + 1;
    row->clock = clock;
    rows.push_back(*row);
    row_arcs.push_back(&b);
  }
  // 2. A system's clock is free when no arc outside the bridge holds it (an arc that
  //    goes on without a gap, with its bias).
  std::vector<bool> clock_held(kNumGnssSystems, false);
  for (const SatelliteMeasurement& u : usable) {
    const bool in_bridge = std::any_of(bridged.begin(), bridged.end(), [&](const BridgedArc& b) { return b.arc == u.arc; });
    if (!in_bridge && held_bias_m(u.arc)) clock_held[static_cast<std::size_t>(u.satellite.system)] = true;
  }
  for (std::size_t i = 0; i < rows.size(); ++i)
    rows[i].clock_free = !clock_held[static_cast<std::size_t>(row_arcs[i]->satellite.system)];
  // 3. The slips; an arc goes on only without one.
  const std::vector<GapBridgeVerdict> verdicts = bridgeGap(rows, position_cov_m2, options);
  for (std::size_t i = 0; i < verdicts.size(); ++i) {
    const BridgedArc& b = *row_arcs[i];
    std::optional<SlipCandidate> chosen;
    if (verdicts[i].keep && b.repair && verdicts[i].candidate >= 0)
      chosen = b.repair->alternatives[static_cast<std::size_t>(verdicts[i].candidate)];
    out.push_back({&b, verdicts[i].keep, chosen, verdicts[i].common_shift_undecided,
                   verdicts[i].keep ? keptLine(b, verdicts[i], chosen) : verdicts[i].reason});
  }
  return out;
}

void applyBridgedArcVerdicts(const std::vector<BridgedArcVerdict>& verdicts,
                             const std::function<void(const BridgedArc&, const std::string&)>& end_arc,
                             const std::function<bool(const BridgedArc&, const SlipCandidate&)>& choose,
                             AmbiguityResolver& resolver, EstimatorEpochResult& result) {
  for (const BridgedArcVerdict& v : verdicts) {
    if (!v.keep) {
      end_arc(*v.arc, v.text);
      continue;
    }
    if (v.chosen && !choose(*v.arc, *v.chosen)) {
      end_arc(*v.arc, "the slip candidate the gap bridge chose (" + slipText(v.chosen->dn1_cycles, v.chosen->dn2_cycles) +
                          ") could not be applied");
      continue;
    }
    ++result.bridged_arcs_kept;
    if (v.arc->repair) ++result.repaired_arcs_kept;
    if (v.common_shift_undecided) resolver.restartWideLane(v.arc->arc);
    result.gap_bridge.push_back(v.common_shift_undecided ? v.text + "; a wide-lane slip common to the system undecided, "
                                                                    "wide-lane mean started again"
                                                         : v.text);
  }
}

Eigen::Matrix3d grownGapPositionCovariance(const Eigen::Matrix3d& after, const Eigen::Matrix3d& before) {
  Eigen::Matrix3d grown = after - before;
  grown = 0.5 * (grown + grown.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(grown);
  const Eigen::Vector3d values = eig.eigenvalues().cwiseMax(kMinGapPositionVariance_m2);
  return eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace ppp
