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

/// The wide-lane estimate and its sigma; false when too uncertain to round (the
/// outcome set: candidates may still be tried, candidatesAllowed).
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

/// Candidates may be tried: on, and the MW sigma within their bound.
bool candidatesAllowed(const SlipRepairOptions& o, const SlipRepair& out) {
  return o.max_candidate_wide_lane_sigma_cycles > 0.0 && o.max_candidates > 0 &&
         out.wide_lane_sigma_cycles <= o.max_candidate_wide_lane_sigma_cycles;
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

/// The L1 estimate given a wide-lane slip [cycles].
double l1Given(const SlipRepairInput& in, double jump_m, long nw) {
  return (jump_m - in.wavelength2_m * static_cast<double>(nw)) / (in.wavelength1_m - in.wavelength2_m);
}

/// How badly the slip with wide lane nw fits both jumps: its wide lane's distance from
/// the MW estimate and its L1 estimate's from the nearest integer, each in its sigmas,
/// squared and summed (chi-square with 2 degrees of freedom for the true slip). Needs
/// both sigmas in `out`.
double jointMisfit(const SlipRepair& out, long nw, double l1_fraction_cycles) {
  const double mw = (static_cast<double>(nw) - out.wide_lane_cycles) / out.wide_lane_sigma_cycles;
  const double l1 = l1_fraction_cycles / out.l1_sigma_cycles;
  return mw * mw + l1 * l1;
}

/// A wide lane may be the slip: its L1 passes the fraction bound, or it fits both
/// jumps plausibly (max_joint_misfit) and no worse than one that may (misfit_to_beat).
bool mayBeTheSlip(const SlipRepairOptions& o, double l1_fraction_cycles, double misfit, double misfit_to_beat) {
  return l1_fraction_cycles <= o.max_l1_fraction_cycles || (misfit <= misfit_to_beat && misfit <= o.max_joint_misfit);
}

/// The unique slip: of the wide-lane candidates (integers within
/// max_wide_lane_offset_cycles of the MW estimate) exactly one gives an L1 estimate
/// within the fraction bound, and its neighbours do not. False (with the outcome) otherwise.
bool firstFrequency(const SlipRepairInput& in, const SlipRepairOptions& o, double jump_m, double jump_sigma_m,
                    SlipRepair& out) {
  const double dl = in.wavelength1_m - in.wavelength2_m;
  out.l1_sigma_cycles = jump_sigma_m / std::abs(dl);
  const long centre = std::lround(out.wide_lane_cycles);
  int passing = 0;
  double nearest_fraction = 1.0;
  for (long nw = centre - 1; nw <= centre + 1; ++nw) {
    if (std::abs(out.wide_lane_cycles - static_cast<double>(nw)) > o.max_wide_lane_offset_cycles) continue;
    const double l1 = l1Given(in, jump_m, nw);
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
  // phase does not check the wide lane: Galileo E1/E5a), and fit both jumps worse than
  // it or implausibly (max_joint_misfit): a neighbour just over the fraction bound but
  // nearer the MW estimate may be the slip, the chosen one just under it one wide lane off.
  if (passing == 1) {
    const long nw = out.dn1_cycles - out.dn2_cycles;
    const double chosen_misfit = jointMisfit(out, nw, nearestInteger(out.l1_cycles).second);
    for (const long other : {nw - 1, nw + 1}) {
      const double l1 = l1Given(in, jump_m, other);
      const double fraction = nearestInteger(l1).second;
      const double misfit = jointMisfit(out, other, fraction);
      if (!mayBeTheSlip(o, fraction, misfit, chosen_misfit)) continue;
      out.outcome = SlipRepairOutcome::Ambiguous;
      out.text = fraction <= o.max_l1_fraction_cycles
                     ? format("wide lanes %ld and %ld both give an integer L1 (%.2f, %.2f cycles)", nw, other,
                              out.l1_cycles, l1)
                     : format("wide lane %ld fits the MW and geometry-free jumps better than %ld (misfit %.1f < %.1f) "
                              "though its L1 %.2f is %.2f cycles from an integer",
                              other, nw, misfit, chosen_misfit, l1, fraction);
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

/// One wide lane of the candidate search: its slip, L1 fraction and joint misfit.
struct ScoredSlip {
  SlipCandidate slip;
  double l1_fraction_cycles = 0.0;
  double misfit = 0.0;  // jointMisfit
};

/// Every wide lane within candidate_sigma_factor sigmas of the MW estimate (at least
/// max_wide_lane_offset_cycles) whose L1 passes, and every other that fits both jumps
/// plausibly (max_joint_misfit) and no worse than one that passes: a pair just over
/// the L1 fraction bound but nearer the MW estimate is not dropped for one just under
/// it but farther away (Galileo E1/E5a neighbours differ by only 0.05 L1 cycles in
/// their fractions). The nearest the estimate is applied, the others kept as
/// alternatives. False (with the outcome) without one or with too many.
bool candidates(const SlipRepairInput& in, const SlipRepairOptions& o, double jump_m, double jump_sigma_m,
                SlipRepair& out) {
  out.l1_sigma_cycles = jump_sigma_m / std::abs(in.wavelength1_m - in.wavelength2_m);
  if (!(out.l1_sigma_cycles <= o.max_l1_sigma_cycles)) {
    out.outcome = SlipRepairOutcome::L1TooUncertain;
    out.text = format("L1 too uncertain: sigma %.2f > %.2f cycles", out.l1_sigma_cycles, o.max_l1_sigma_cycles);
    return false;
  }
  const double half_width = std::max({o.max_wide_lane_offset_cycles, o.min_candidate_half_width_cycles,
                                      o.candidate_sigma_factor * out.wide_lane_sigma_cycles});
  std::vector<ScoredSlip> window;
  double worst_passing_misfit = -1.0;  // none passes the L1 test yet
  for (long nw = std::lround(std::ceil(out.wide_lane_cycles - half_width));
       static_cast<double>(nw) <= out.wide_lane_cycles + half_width; ++nw) {
    const double l1 = l1Given(in, jump_m, nw);
    const auto [n1, fraction] = nearestInteger(l1);
    window.push_back({{n1, n1 - nw, l1}, fraction, jointMisfit(out, nw, fraction)});
    if (fraction <= o.max_l1_fraction_cycles)
      worst_passing_misfit = std::max(worst_passing_misfit, window.back().misfit);
  }
  std::vector<std::pair<double, SlipCandidate>> passing;  // (|nw - MW|, candidate)
  for (const ScoredSlip& s : window)
    if (mayBeTheSlip(o, s.l1_fraction_cycles, s.misfit, worst_passing_misfit))
      passing.push_back(
          {std::abs(static_cast<double>(s.slip.dn1_cycles - s.slip.dn2_cycles) - out.wide_lane_cycles), s.slip});
  if (passing.empty() || static_cast<int>(passing.size()) > o.max_candidates) {
    out.outcome = passing.empty() ? SlipRepairOutcome::L1NotInteger : SlipRepairOutcome::TooManyCandidates;
    out.text = format("%zu wide lanes within %.2f cycles of %.2f +- %.2f give an integer L1 or fit as well "
                      "(at most %d)",
                      passing.size(), half_width, out.wide_lane_cycles, out.wide_lane_sigma_cycles, o.max_candidates);
    return false;
  }
  std::stable_sort(passing.begin(), passing.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  out.dn1_cycles = passing.front().second.dn1_cycles;
  out.dn2_cycles = passing.front().second.dn2_cycles;
  out.l1_cycles = passing.front().second.l1_cycles;
  out.alternatives.clear();
  for (std::size_t i = 1; i < passing.size(); ++i) out.alternatives.push_back(passing[i].second);
  return true;
}

std::string candidatesText(const SlipRepair& r) {
  if (r.alternatives.empty()) return {};
  std::string text = format("; %zu other candidate%s:", r.alternatives.size(), r.alternatives.size() == 1 ? "" : "s");
  for (std::size_t i = 0; i < r.alternatives.size(); ++i)
    text += (i == 0 ? " " : ", ") + slipText(r.alternatives[i].dn1_cycles, r.alternatives[i].dn2_cycles);
  return text;
}

void describe(SlipRepair& out) {
  out.outcome = out.dn1_cycles == 0 && out.dn2_cycles == 0 ? SlipRepairOutcome::NoSlip : SlipRepairOutcome::Repaired;
  out.text = slipText(out.dn1_cycles, out.dn2_cycles) +
             format(" (WL %.2f +- %.2f, L1 %.2f +- %.2f cycles)", out.wide_lane_cycles, out.wide_lane_sigma_cycles,
                    out.l1_cycles, out.l1_sigma_cycles) +
             candidatesText(out);
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
    case SlipRepairOutcome::TooManyCandidates: return "too many candidates";
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

std::string slipText(long dn1_cycles, long dn2_cycles) { return format("dN1 %+ld dN2 %+ld", dn1_cycles, dn2_cycles); }

void SlipRepair::choose(const SlipCandidate& chosen) {
  if (sameSlip(chosen, applied())) return;
  std::vector<SlipCandidate> others{applied()};
  for (const SlipCandidate& c : alternatives)
    if (!sameSlip(c, chosen)) others.push_back(c);
  const std::string before = slipText(dn1_cycles, dn2_cycles);
  dn1_cycles = chosen.dn1_cycles;
  dn2_cycles = chosen.dn2_cycles;
  l1_cycles = chosen.l1_cycles;
  alternatives = std::move(others);
  describe(*this);
  text += " (chosen by the gap bridge over " + before + ")";
}

SlipRepair repairSlip(const SlipRepairInput& input, const SlipRepairOptions& options) {
  SlipRepair out;
  // 1. The wide lane from the Melbourne-Wubbena jump (too uncertain to round: candidates).
  const bool wide_lane_rounds = wideLane(input, options, out);
  if (!wide_lane_rounds && !candidatesAllowed(options, out)) return out;
  const std::string wide_lane_refusal = out.text;
  // 2. The geometry-free jump over the ionosphere fit.
  double jump_m = 0.0, jump_sigma_m = 0.0;
  if (!geometryFreeJump(input, options, out, jump_m, jump_sigma_m)) return out;
  // 3. L1 given each wide-lane candidate: exactly one integer pair; else, where
  //    allowed, every pair that passes as candidates for the gap bridge.
  if (!(wide_lane_rounds && firstFrequency(input, options, jump_m, jump_sigma_m, out))) {
    if (out.outcome == SlipRepairOutcome::L1TooUncertain || !candidatesAllowed(options, out)) return out;
    const std::string unique_refusal = wide_lane_rounds ? out.text : wide_lane_refusal;
    if (!candidates(input, options, jump_m, jump_sigma_m, out)) {
      out.text = unique_refusal + "; " + out.text;
      return out;
    }
  }
  describe(out);
  return out;
}

}  // namespace ppp
