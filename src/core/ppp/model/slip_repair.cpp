#include "ppp_bayes_tree/ppp/model/slip_repair.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// The integer nearest x and the distance to it.
std::pair<long, double> nearestInteger(double x) {
  const double r = std::round(x);
  return {static_cast<long>(r), std::abs(x - r)};
}

/// The wide-lane estimate and its sigma; false (with the outcome) when too uncertain.
bool wideLane(const SlipRepairInput& in, const SlipRepairOptions& o, SlipRepair& out) {
  const double n = std::max(in.mw_samples, 1);
  out.wide_lane_cycles = in.mw_jump_cycles;
  out.wide_lane_sigma_cycles = in.mw_sigma_cycles * std::sqrt(1.0 + 1.0 / n);
  if (out.wide_lane_sigma_cycles <= o.max_wide_lane_sigma_cycles) return true;
  out.outcome = SlipRepairOutcome::WideLaneTooUncertain;
  out.text = format("wide lane too uncertain: %.2f +- %.2f cycles, sigma > %.2f", out.wide_lane_cycles,
                    out.wide_lane_sigma_cycles, o.max_wide_lane_sigma_cycles);
  return false;
}

/// The GF jump over the ionosphere fit and its sigma [m]; false (with the outcome) without a fit.
bool geometryFreeJump(const SlipRepairInput& in, const SlipRepairOptions& o, SlipRepair& out, double& jump_m,
                      double& sigma_m) {
  const double noise_floor_m = std::sqrt(2.0) * o.phase_sigma_m;  // GF = L1 - L2
  const auto fit = predictGeometryFreeFit(in.gf_before, in.time_after_s, o.gf_fit_order, noise_floor_m);
  if (!fit || static_cast<int>(in.gf_before.size()) < o.gf_fit_min_points) {
    out.outcome = SlipRepairOutcome::TooFewSamples;
    out.text = format("%zu geometry-free samples before the gap, fewer than %d", in.gf_before.size(),
                      std::max(o.gf_fit_min_points, o.gf_fit_order + 2));
    return false;
  }
  out.gf_prediction_m = fit->value_m;
  const double gap_s = std::max(in.time_after_s - in.gf_before.back().first, 0.0);
  jump_m = in.gf_after_m - fit->value_m;
  sigma_m = std::sqrt(noise_floor_m * noise_floor_m + fit->sigma_m * fit->sigma_m +
                      std::pow(o.ionosphere_sigma_mps * gap_s, 2));
  return true;
}

/// The wide-lane candidates (integers within max_wide_lane_offset_cycles of the
/// MW estimate) whose L1 estimate is within the fraction bound; exactly one is
/// accepted. False (with the outcome) otherwise.
bool firstFrequency(const SlipRepairInput& in, const SlipRepairOptions& o, double jump_m, double jump_sigma_m,
                    SlipRepair& out) {
  const double dl = in.wavelength1_m - in.wavelength2_m;
  out.l1_sigma_cycles = jump_sigma_m / std::abs(dl);
  const long centre = std::lround(out.wide_lane_cycles);
  int passing = 0;
  double nearest_fraction = 1.0;
  for (long nw = centre - 1; nw <= centre + 1; ++nw) {
    if (std::abs(out.wide_lane_cycles - static_cast<double>(nw)) > o.max_wide_lane_offset_cycles) continue;
    const double l1 = (jump_m - in.wavelength2_m * static_cast<double>(nw)) / dl;
    const auto [n1, fraction] = nearestInteger(l1);
    if (fraction < nearest_fraction || (passing == 0 && nw == centre)) out.l1_cycles = l1;
    nearest_fraction = std::min(nearest_fraction, fraction);
    if (fraction > o.max_l1_fraction_cycles) continue;
    ++passing;
    out.l1_cycles = l1;
    out.dn1_cycles = n1;
    out.dn2_cycles = n1 - nw;
  }
  if (!(out.l1_sigma_cycles <= o.max_l1_sigma_cycles)) {
    out.outcome = SlipRepairOutcome::L1TooUncertain;
    out.text = format("L1 too uncertain: %.2f +- %.2f cycles, sigma > %.2f", out.l1_cycles, out.l1_sigma_cycles,
                      o.max_l1_sigma_cycles);
    return false;
  }
  // The chosen wide lane's neighbours must fail the L1 test (else the geometry-free
  // phase does not check the wide lane: Galileo E1/E5a).
  if (passing == 1) {
    const long nw = out.dn1_cycles - out.dn2_cycles;
    for (const long other : {nw - 1, nw + 1}) {
      const double l1 = (jump_m - in.wavelength2_m * static_cast<double>(other)) / dl;
      if (nearestInteger(l1).second > o.max_l1_fraction_cycles) continue;
      out.outcome = SlipRepairOutcome::Ambiguous;
      out.text = format("wide lanes %ld and %ld both give an integer L1 (%.2f, %.2f cycles)", nw, other,
                        out.l1_cycles, l1);
      return false;
    }
    return true;
  }
  out.outcome = passing == 0 ? SlipRepairOutcome::L1NotInteger : SlipRepairOutcome::Ambiguous;
  out.text = passing == 0 ? format("L1 not an integer for any wide lane within %.1f cycles of %.2f: nearest %.2f "
                                   "+- %.2f cycles, fraction > %.2f",
                                   o.max_wide_lane_offset_cycles, out.wide_lane_cycles, out.l1_cycles,
                                   out.l1_sigma_cycles, o.max_l1_fraction_cycles)
                          : format("%d wide lanes within %.1f cycles of %.2f give an integer L1", passing,
                                   o.max_wide_lane_offset_cycles, out.wide_lane_cycles);
  return false;
}

}  // namespace

const char* slipRepairOutcomeName(SlipRepairOutcome outcome) {
  switch (outcome) {
    case SlipRepairOutcome::Repaired: return "repaired";
    case SlipRepairOutcome::NoSlip: return "no slip";
    case SlipRepairOutcome::TooFewSamples: return "too few geometry-free samples";
    case SlipRepairOutcome::WideLaneTooUncertain: return "wide lane too uncertain";
    case SlipRepairOutcome::Ambiguous: return "ambiguous";
    case SlipRepairOutcome::L1TooUncertain: return "L1 too uncertain";
    case SlipRepairOutcome::L1NotInteger: return "L1 not an integer";
  }
  return "unknown";
}

std::optional<GeometryFreePrediction> predictGeometryFreeFit(const std::vector<std::pair<double, double>>& samples,
                                                             double t_s, int order, double noise_floor_m) {
  const int p = std::clamp(order, 1, 2) + 1;
  const int n = static_cast<int>(samples.size());
  if (n < p + 1) return std::nullopt;
  // Times relative to the last sample, scaled to the fit's span (conditioning).
  const double t_ref = samples.back().first;
  const double scale = std::max(t_ref - samples.front().first, 1.0);
  Eigen::MatrixXd X(n, p);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    const double tau = (samples[static_cast<std::size_t>(i)].first - t_ref) / scale;
    for (int j = 0; j < p; ++j) X(i, j) = std::pow(tau, j);
    y(i) = samples[static_cast<std::size_t>(i)].second;
  }
  const Eigen::MatrixXd N = X.transpose() * X;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(N);
  if (ldlt.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd coeff = ldlt.solve(X.transpose() * y);
  const double rss = (y - X * coeff).squaredNorm();
  const double s = std::max(std::sqrt(rss / (n - p)), noise_floor_m);
  Eigen::VectorXd x0(p);
  const double tau0 = (t_s - t_ref) / scale;
  for (int j = 0; j < p; ++j) x0(j) = std::pow(tau0, j);
  GeometryFreePrediction out;
  out.value_m = x0.dot(coeff);
  out.sigma_m = s * std::sqrt(std::max(x0.dot(ldlt.solve(x0)), 0.0));
  if (!std::isfinite(out.value_m) || !std::isfinite(out.sigma_m)) return std::nullopt;
  return out;
}

SlipRepair repairSlip(const SlipRepairInput& input, const SlipRepairOptions& options) {
  SlipRepair out;
  // 1. The wide lane from the Melbourne-Wubbena jump.
  if (!wideLane(input, options, out)) return out;
  // 2. The geometry-free jump over the ionosphere fit.
  double jump_m = 0.0, jump_sigma_m = 0.0;
  if (!geometryFreeJump(input, options, out, jump_m, jump_sigma_m)) return out;
  // 3. L1 given each wide-lane candidate: exactly one integer pair.
  if (!firstFrequency(input, options, jump_m, jump_sigma_m, out)) return out;
  out.outcome = out.dn1_cycles == 0 && out.dn2_cycles == 0 ? SlipRepairOutcome::NoSlip : SlipRepairOutcome::Repaired;
  out.text = format("dN1 %+ld dN2 %+ld (WL %.2f +- %.2f, L1 %.2f +- %.2f cycles)", out.dn1_cycles, out.dn2_cycles,
                    out.wide_lane_cycles, out.wide_lane_sigma_cycles, out.l1_cycles, out.l1_sigma_cycles);
  return out;
}

}  // namespace ppp
