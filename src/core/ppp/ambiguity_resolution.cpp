#include "ppp_bayes_tree/ppp/ambiguity_resolution.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <Eigen/Cholesky>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

std::string AmbiguityResolutionOptions::validate() const {
  if (!(narrow_lane.ratio_threshold >= 1.0)) return "ratio_threshold must be >= 1";
  if (!(narrow_lane.min_success_rate >= 0.0 && narrow_lane.min_success_rate < 1.0))
    return "min_success_rate must be in [0, 1)";
  if (narrow_lane.min_fixed < 1) return "min_fixed must be >= 1";
  if (wide_lane.min_samples < 1) return "wide_lane_min_samples must be >= 1";
  if (!(wide_lane.max_fraction_cycles > 0.0 && wide_lane.max_fraction_cycles <= 0.5))
    return "wide_lane_max_fraction_cycles must be in (0, 0.5]";
  if (!(wide_lane.min_success_rate >= 0.0 && wide_lane.min_success_rate < 1.0))
    return "wide_lane_min_success_rate must be in [0, 1)";
  return "";
}

std::string toString(AmbiguityFloatReason reason) {
  switch (reason) {
    case AmbiguityFloatReason::None: return "fixed";
    case AmbiguityFloatReason::Disabled: return "ambiguity resolution off";
    case AmbiguityFloatReason::NoConsistentPhaseBiases: return "no consistent phase biases";
    case AmbiguityFloatReason::NoWideLaneReference: return "no wide-lane reference arc yet";
    case AmbiguityFloatReason::TooFewWideLanes: return "too few fixed wide lanes";
    case AmbiguityFloatReason::NarrowLane: return "narrow lane not fixed";
    case AmbiguityFloatReason::NumericalFailure: return "constrained covariance not positive definite";
  }
  return "unknown";
}

std::string AmbiguityFixSummary::text() const {
  char buf[160];
  const std::string ref = reference_satellite ? reference_satellite->toString() : "-";
  if (fixed()) {
    std::snprintf(buf, sizeof buf, "fixed %d/%d ratio %.1f (ref %s, WL %d/%d)", narrow_lanes_fixed,
                  narrow_lane_candidates, ratio, ref.c_str(), wide_lanes_fixed, wide_lane_candidates);
    return buf;
  }
  std::string s = "float: " + toString(float_reason);
  if (float_reason == AmbiguityFloatReason::NarrowLane) {
    std::snprintf(buf, sizeof buf, ": %s (ratio %.2f, %d candidates)", toString(ils_reason).c_str(), ratio,
                  narrow_lane_candidates);
    s += buf;
  }
  return s;
}

void AmbiguityResolver::addEpoch(const std::vector<DualFrequencyObservation>& observations,
                                 const std::vector<ArcId>& arcs, const BiasProvider* biases) {
  if (!options_.enabled || !biases) return;
  for (std::size_t i = 0; i < observations.size() && i < arcs.size(); ++i) {
    if (arcs[i] == 0) continue;
    if (wide_lane_.add(arcs[i], observations[i], biases) == WideLaneBiasIssue::None)
      last_observation_[arcs[i]] = observations[i];
  }
}

void AmbiguityResolver::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) {
    wide_lane_.removeArc(e.arc);
    last_observation_.erase(e.arc);
  }
}

std::optional<AmbiguityFixedState> applyIntegerConstraints(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                                           const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  const Eigen::MatrixXd PAt = P * A.transpose();
  const Eigen::MatrixXd S = A * PAt;
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return std::nullopt;
  AmbiguityFixedState out;
  out.x = x + PAt * llt.solve(y - A * x);
  out.P = P - PAt * llt.solve(PAt.transpose());
  out.P = 0.5 * (out.P + out.P.transpose());
  if (!out.x.allFinite() || !out.P.allFinite()) return std::nullopt;
  return out;
}

std::optional<AmbiguityFixedState> AmbiguityResolver::resolve(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                                              int receiver_dim, const std::vector<ArcId>& bias_arcs,
                                                              const BiasProvider* biases,
                                                              AmbiguityFixSummary& summary,
                                                              const std::map<ArcId, double>* elevation_rad) const {
  summary = AmbiguityFixSummary{};
  if (!options_.enabled) return std::nullopt;
  if (!biases) {
    summary.float_reason = AmbiguityFloatReason::NoConsistentPhaseBiases;
    return std::nullopt;
  }
  auto highEnough = [&](ArcId arc) {
    if (!elevation_rad || options_.min_elevation_rad <= 0.0) return true;
    const auto e = elevation_rad->find(arc);
    return e != elevation_rad->end() && e->second >= options_.min_elevation_rad;
  };
  std::map<ArcId, int> slot;
  for (std::size_t i = 0; i < bias_arcs.size(); ++i)
    if (highEnough(bias_arcs[i])) slot[bias_arcs[i]] = receiver_dim + static_cast<int>(i);
  const WideLaneResolution wl = wide_lane_.resolve([&](ArcId arc) { return slot.count(arc) > 0; });
  if (!wl.reference_arc) {
    summary.float_reason = AmbiguityFloatReason::NoWideLaneReference;
    return std::nullopt;
  }
  summary.reference_satellite = wl.reference_satellite;
  summary.wide_lane_candidates = static_cast<int>(wl.arcs.size());
  summary.wide_lanes_fixed = wl.fixedCount();

  const auto ref_slot = slot.find(*wl.reference_arc);
  const auto ref_obs = last_observation_.find(*wl.reference_arc);
  if (ref_slot == slot.end() || ref_obs == last_observation_.end()) {
    summary.float_reason = AmbiguityFloatReason::NoWideLaneReference;
    return std::nullopt;
  }
  // IF combination of an arc's satellite phase OSBs [m]; nullopt when missing.
  auto ifPhaseBias = [&](const DualFrequencyObservation& o) -> std::optional<double> {
    const BiasAnswer b1 = biases->phaseBias(o.satellite, o.phase1, o.time);
    const BiasAnswer b2 = biases->phaseBias(o.satellite, o.phase2, o.time);
    if (!b1.value_m || !b2.value_m) return std::nullopt;
    return ionosphereFree(*b1.value_m, *b2.value_m, ionosphereFreeCoefficients(o.frequency1_hz, o.frequency2_hz));
  };
  const auto b_ref = ifPhaseBias(ref_obs->second);
  if (!b_ref) {
    summary.float_reason = AmbiguityFloatReason::NoWideLaneReference;
    return std::nullopt;
  }
  const int dim = static_cast<int>(x.size());
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<double> offsets;
  for (const WideLaneFix& f : wl.arcs) {
    if (!f.fixed) continue;
    const auto s = slot.find(f.arc);
    const auto o = last_observation_.find(f.arc);
    if (s == slot.end() || o == last_observation_.end()) continue;
    const auto b = ifPhaseBias(o->second);
    if (!b) continue;
    const double f1 = o->second.frequency1_hz, f2 = o->second.frequency2_hz;
    const double lambda_nl = narrowLaneWavelength_m(f1, f2);
    const double k_wl = ionosphereFreeAmbiguity_m(f1, f2, 0.0, 1.0);
    Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(dim);
    row(s->second) = 1.0 / lambda_nl;
    row(ref_slot->second) = -1.0 / lambda_nl;
    rows.push_back(row);
    offsets.push_back((*b - *b_ref + k_wl * static_cast<double>(f.integer_cycles)) / lambda_nl);
  }
  const int m = static_cast<int>(rows.size());
  summary.narrow_lane_candidates = m;
  if (m < options_.narrow_lane.min_fixed) {
    summary.float_reason = AmbiguityFloatReason::TooFewWideLanes;
    return std::nullopt;
  }
  Eigen::MatrixXd D(m, dim);
  Eigen::VectorXd o(m);
  for (int i = 0; i < m; ++i) D.row(i) = rows[static_cast<std::size_t>(i)], o(i) = offsets[static_cast<std::size_t>(i)];
  const Eigen::VectorXd n1_float = D * x - o;
  const Eigen::MatrixXd Q = D * P * D.transpose();
  const auto t0 = std::chrono::steady_clock::now();
  const IlsResult ils = solveIntegerLeastSquares(n1_float, Q, options_.narrow_lane);
  summary.search_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  summary.ratio = ils.ratio;
  summary.bootstrap_success_rate = ils.bootstrap_success_rate;
  summary.ils_reason = ils.float_reason;
  if (!ils.isFixed()) {
    summary.float_reason = AmbiguityFloatReason::NarrowLane;
    return std::nullopt;
  }
  const Eigen::MatrixXd A = ils.constraint_rows * D;
  const Eigen::VectorXd y = ils.constraint_values + ils.constraint_rows * o;
  auto fixed = applyIntegerConstraints(x, P, A, y);
  if (!fixed) {
    summary.float_reason = AmbiguityFloatReason::NumericalFailure;
    return std::nullopt;
  }
  fixed->constraint_rows = A;
  fixed->constraint_values = y;
  summary.narrow_lanes_fixed = ils.fixed;
  summary.float_reason = AmbiguityFloatReason::None;
  return fixed;
}

}  // namespace ppp
