#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <cmath>
#include <cstdio>

#include <Eigen/Cholesky>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

std::string AmbiguityResolutionOptions::validate() const {
  if (!(narrow_lane.ratio_threshold >= 1.0)) return "ratio_threshold must be >= 1";
  if (!(narrow_lane.min_success_rate >= 0.0 && narrow_lane.min_success_rate < 1.0))
    return "min_success_rate must be in [0, 1)";
  if (!(narrow_lane.success_rate_variance_factor >= 1.0))
    return "success_rate_variance_factor must be >= 1";
  if (narrow_lane.min_fixed < 1) return "min_fixed must be >= 1";
  if (wide_lane.min_samples < 1) return "wide_lane_min_samples must be >= 1";
  if (!(std::isfinite(wide_lane.correlation_time_s) && wide_lane.correlation_time_s >= 0.0))
    return "wide_lane_correlation_time_s must be a finite value >= 0";
  if (hold.small_subset_max_size < 0) return "small_subset_max_size must be >= 0";
  if (!(wide_lane.max_fraction_cycles > 0.0 && wide_lane.max_fraction_cycles <= 0.5))
    return "wide_lane_max_fraction_cycles must be in (0, 0.5]";
  if (!(wide_lane.min_success_rate >= 0.0 && wide_lane.min_success_rate < 1.0))
    return "wide_lane_min_success_rate must be in [0, 1)";
  if (hold.consistency_epochs < 1) return "consistency_epochs must be >= 1";
  if (!(hold.max_float_spread_cycles > 0.0)) return "max_float_spread_cycles must be > 0";
  if (!(hold.max_float_drift_sigmas >= 0.0)) return "max_float_drift_sigmas must be >= 0";
  if (hold.validation_epochs < 1) return "validation_epochs must be >= 1";
  if (hold.fast_validation_epochs < 1) return "fast_validation_epochs must be >= 1";
  if (!(hold.fast_validation_success_rate >= 0.0 && hold.fast_validation_success_rate <= 1.0))
    return "fast_validation_success_rate must be in [0, 1]";
  if (!(hold.release_cycles > 0.0 && hold.release_cycles <= 1.0)) return "release_cycles must be in (0, 1]";
  if (!(hold.release_sigma > 0.0)) return "release_sigma must be > 0";
  if (!(hold.max_fraction_cycles > 0.0 && hold.max_fraction_cycles <= 0.5))
    return "narrow_lane_max_fraction_cycles must be in (0, 0.5]";
  if (!(hold.max_sigma_cycles > 0.0)) return "narrow_lane_max_sigma_cycles must be > 0";
  return "";
}

std::string toString(AmbiguityResolutionMode mode) {
  switch (mode) {
    case AmbiguityResolutionMode::Off: return "false";
    case AmbiguityResolutionMode::On: return "true";
    case AmbiguityResolutionMode::Auto: return "auto";
  }
  return "unknown";
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
    case AmbiguityFloatReason::Validating: return "integers not yet validated across epochs";
    case AmbiguityFloatReason::FloatsDrifting:
      return "narrow-lane floats still drift (spread over the window too large and more than their covariance "
             "explains)";
    case AmbiguityFloatReason::FloatsOffInteger:
      return "narrow-lane floats too far from an integer or too uncertain (candidate gate)";
    case AmbiguityFloatReason::IntegerFarFromFloat:
      return "an integer the search returned lies too far from its float (candidate gate)";
  }
  return "unknown";
}

std::string toString(AmbiguityReleaseReason reason) {
  switch (reason) {
    case AmbiguityReleaseReason::FloatDeparted: return "float departed from the held integer";
    case AmbiguityReleaseReason::WideLaneChanged: return "wide lane rounds to another integer";
    case AmbiguityReleaseReason::ArcEnded: return "arc or reference arc ended";
  }
  return "unknown";
}

std::string AmbiguityFixSummary::text() const {
  char buf[200];
  std::string ref;
  for (const SystemAmbiguitySummary& sys : systems) ref += (ref.empty() ? "" : " ") + sys.reference_satellite.toString();
  if (ref.empty()) ref = reference_satellite ? reference_satellite->toString() : "-";
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
  } else if (float_reason == AmbiguityFloatReason::IntegerFarFromFloat) {
    std::snprintf(buf, sizeof buf, " (ratio %.2f, %d candidates)", ratio, narrow_lane_candidates);
    s += buf;
  }
  return s;
}

void AmbiguityResolver::addEpoch(const std::vector<DualFrequencyObservation>& observations,
                                 const std::vector<ArcId>& arcs, const BiasProvider* biases) {
  if (!options_.enabled || !biases) return;
  for (std::size_t i = 0; i < observations.size() && i < arcs.size(); ++i) {
    // GLONASS (FDMA) arcs stay float: no wide lane, so no reference, candidate or hold.
    if (arcs[i] == 0 || !integerAmbiguitySystem(observations[i].satellite.system)) continue;
    if (wide_lane_.add(arcs[i], observations[i], biases) == WideLaneBiasIssue::None)
      last_observation_[arcs[i]] = observations[i];
  }
}

void AmbiguityResolver::arcsEnded(const std::vector<EndedArc>& ended) {
  for (const auto& e : ended) {
    wide_lane_.removeArc(e.arc);
    last_observation_.erase(e.arc);
    auto touches = [&](const PairKey& k) { return k.arc == e.arc || k.reference_arc == e.arc; };
    // The held single differences through the ended arc, as (other arc - ended arc).
    struct Through {
      ArcId arc;
      long wide_lane_cycles, narrow_lane_cycles;
    };
    std::vector<Through> through;
    for (auto it = held_.begin(); it != held_.end();) {
      if (!touches(it->first)) {
        ++it;
        continue;
      }
      if (it->first.reference_arc == e.arc)
        through.push_back({it->first.arc, it->first.wide_lane_cycles, it->second});
      else
        through.push_back({it->first.reference_arc, -it->first.wide_lane_cycles, -it->second});
      it = held_.erase(it);
    }
    // Their differences stay integers (the held pairs form a forest, so none is held yet).
    if (options_.hold.rereference_on_arc_end)
      for (std::size_t i = 1; i < through.size(); ++i)
        held_[PairKey{through[i].arc, through[0].arc, through[i].wide_lane_cycles - through[0].wide_lane_cycles}] =
            through[i].narrow_lane_cycles - through[0].narrow_lane_cycles;
    for (auto it = pending_.begin(); it != pending_.end();) it = touches(it->first) ? pending_.erase(it) : std::next(it);
    for (auto it = float_history_.begin(); it != float_history_.end();)
      it = touches(it->first) ? float_history_.erase(it) : std::next(it);
  }
}

void AmbiguityResolver::releaseAll() {
  releases_total_ += static_cast<long>(held_.size());
  held_.clear();
  pending_.clear();
  float_history_.clear();
}

void AmbiguityResolver::holdInteger(ArcId arc, ArcId reference_arc, long wide_lane_cycles, long narrow_lane_cycles) {
  const PairKey key{arc, reference_arc, wide_lane_cycles};
  pending_.erase(key);
  held_[key] = narrow_lane_cycles;
}

namespace {

/// Exact conditioning of (x, P) on A x = y with ONE factorisation of
/// S = A P A^T, which also gives u = S^-1 (A x - y) and, on request, diag(S^-1):
/// the leave-one-out test of each constraint against the others needs only
/// these (with K = S^-1, the float of row i conditioned on the other rows lies
/// u_i / K_ii from its value y_i, with sigma K_ii^-1/2: the w-test identity of
/// the conditional mean and variance of a Gaussian).
struct Conditioning {
  AmbiguityFixedState state;
  Eigen::VectorXd u;           // S^-1 (A x - y)
  Eigen::VectorXd s_inv_diag;  // diag(S^-1), when asked for
};

std::optional<Conditioning> conditionOn(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, const Eigen::MatrixXd& A,
                                        const Eigen::VectorXd& y, bool leave_one_out) {
  const Eigen::MatrixXd PAt = P * A.transpose();
  const Eigen::LLT<Eigen::MatrixXd> llt(A * PAt);
  if (llt.info() != Eigen::Success) return std::nullopt;
  Conditioning c;
  const Eigen::VectorXd r = A * x - y;
  c.u = llt.solve(r);
  c.state.x = x - PAt * c.u;
  c.state.P = P - PAt * llt.solve(PAt.transpose());
  c.state.P = 0.5 * (c.state.P + c.state.P.transpose());
  c.state.constraint_residual_statistic = r.dot(c.u);
  if (leave_one_out) c.s_inv_diag = llt.solve(Eigen::MatrixXd::Identity(A.rows(), A.rows())).diagonal();
  if (!c.state.x.allFinite() || !c.state.P.allFinite()) return std::nullopt;
  return c;
}

}  // namespace

std::optional<AmbiguityFixedState> applyIntegerConstraints(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                                           const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  auto c = conditionOn(x, P, A, y, false);
  if (!c) return std::nullopt;
  return std::move(c->state);
}

std::optional<GnssSystem> AmbiguityResolver::systemOf(ArcId arc) const {
  const auto m = wide_lane_.arcs().find(arc);
  if (m == wide_lane_.arcs().end()) return std::nullopt;
  return m->second.satellite.system;
}

namespace {

/// The systems of the `slot` arcs with a wide-lane mean, in enum order (GPS first).
template <typename SystemOf>
std::vector<GnssSystem> systemsOfArcs(const std::map<ArcId, int>& slot, const SystemOf& system_of) {
  std::vector<GnssSystem> systems;
  for (const auto& [arc, index] : slot)
    if (const std::optional<GnssSystem> sys = system_of(arc))
      if (std::find(systems.begin(), systems.end(), *sys) == systems.end()) systems.push_back(*sys);
  std::sort(systems.begin(), systems.end());
  return systems;
}

/// An arc high enough to be fixed: no elevations given, no minimum, or its
/// elevation at least min_elevation_rad.
bool highEnoughToFix(ArcId arc, const std::map<ArcId, double>* elevation_rad, double min_elevation_rad) {
  if (!elevation_rad || min_elevation_rad <= 0.0) return true;
  const auto e = elevation_rad->find(arc);
  return e != elevation_rad->end() && e->second >= min_elevation_rad;
}

/// Each system's reference and wide-lane counts into the summary.
void recordWideLanes(const std::vector<WideLaneResolution>& per_system, AmbiguityFixSummary& summary) {
  for (const WideLaneResolution& wl : per_system) {
    SystemAmbiguitySummary sys;
    sys.system = wl.reference_satellite.system;
    sys.reference_satellite = wl.reference_satellite;
    sys.wide_lane_candidates = static_cast<int>(wl.arcs.size());
    sys.wide_lanes_fixed = wl.fixedCount();
    summary.systems.push_back(sys);
    summary.wide_lane_candidates += sys.wide_lane_candidates;
    summary.wide_lanes_fixed += sys.wide_lanes_fixed;
    if (!summary.reference_satellite) summary.reference_satellite = wl.reference_satellite;
  }
}

}  // namespace

std::vector<WideLaneResolution> AmbiguityResolver::wideLanesPerSystem(const std::map<ArcId, int>& slot) const {
  std::vector<WideLaneResolution> out;
  for (const GnssSystem system : systemsOfArcs(slot, [&](ArcId a) { return systemOf(a); })) {
    WideLaneResolution wl =
        wide_lane_.resolve([&](ArcId arc) { return slot.count(arc) > 0 && systemOf(arc) == system; });
    if (wl.reference_arc) out.push_back(std::move(wl));
  }
  return out;
}

std::vector<WideLaneResolution> AmbiguityResolver::wideLanesPerSystemKeepingReferences(
    const std::map<ArcId, int>& slot) {
  std::vector<WideLaneResolution> out;
  std::map<GnssSystem, ArcId> kept_references;
  for (const GnssSystem system : systemsOfArcs(slot, [&](ArcId a) { return systemOf(a); })) {
    const auto eligible = [&](ArcId arc) { return slot.count(arc) > 0 && systemOf(arc) == system; };
    // The reference is kept while it stays eligible, so that the float history
    // and the validation of its single differences go on. It gives way to the
    // best-determined arc when that fixes more wide lanes (a reference whose own
    // wide-lane bias is off leaves its pairs unfixed).
    WideLaneResolution wl = wide_lane_.resolve(eligible);
    const auto previous = reference_arcs_.find(system);
    if (previous != reference_arcs_.end() && eligible(previous->second) && wl.reference_arc &&
        *wl.reference_arc != previous->second) {
      WideLaneResolution kept = wide_lane_.resolveAgainst(previous->second, eligible);
      if (kept.reference_arc && kept.fixedCount() >= wl.fixedCount()) wl = std::move(kept);
    }
    if (!wl.reference_arc) continue;
    kept_references[system] = *wl.reference_arc;
    out.push_back(std::move(wl));
  }
  reference_arcs_ = std::move(kept_references);
  return out;
}

std::vector<AmbiguityResolver::PairRow> AmbiguityResolver::wideLaneFixedRows(
    const std::vector<WideLaneResolution>& per_system, int dim, const std::map<ArcId, int>& slot,
    const BiasProvider* biases) const {
  std::vector<PairRow> rows;
  for (const WideLaneResolution& wl : per_system)
    for (const WideLaneFix& f : wl.arcs) {
      if (!f.fixed) continue;
      if (auto row = rowOf(PairKey{f.arc, *wl.reference_arc, f.integer_cycles}, dim, slot, biases))
        rows.push_back(std::move(*row));
    }
  return rows;
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
  std::map<ArcId, int> slot;
  for (std::size_t i = 0; i < bias_arcs.size(); ++i)
    if (highEnoughToFix(bias_arcs[i], elevation_rad, options_.min_elevation_rad))
      slot[bias_arcs[i]] = receiver_dim + static_cast<int>(i);
  const std::vector<WideLaneResolution> per_system = wideLanesPerSystem(slot);
  recordWideLanes(per_system, summary);
  const int dim = static_cast<int>(x.size());
  const std::vector<PairRow> rows = wideLaneFixedRows(per_system, dim, slot, biases);
  if (per_system.empty()) {
    summary.float_reason = AmbiguityFloatReason::NoWideLaneReference;
    return std::nullopt;
  }
  const int m = static_cast<int>(rows.size());
  summary.narrow_lane_candidates = m;
  if (m < options_.narrow_lane.min_fixed) {
    summary.float_reason = AmbiguityFloatReason::TooFewWideLanes;
    return std::nullopt;
  }
  Eigen::MatrixXd D(m, dim);
  Eigen::VectorXd o(m);
  for (int i = 0; i < m; ++i) D.row(i) = rows[static_cast<std::size_t>(i)].d, o(i) = rows[static_cast<std::size_t>(i)].offset;
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

namespace {

/// Union-find over arcs: pairs joined by held integers are connected, and a
/// new single difference between two connected arcs would be a linear
/// combination of held ones (not independent).
struct ArcComponents {
  std::map<ArcId, ArcId> parent;
  ArcId find(ArcId a) {
    auto it = parent.find(a);
    if (it == parent.end()) return parent[a] = a;
    if (it->second == a) return a;
    return it->second = find(it->second);
  }
  bool join(ArcId a, ArcId b) {
    const ArcId ra = find(a), rb = find(b);
    if (ra == rb) return false;
    parent[ra] = rb;
    return true;
  }
};

}  // namespace

std::optional<AmbiguityResolver::PairRow> AmbiguityResolver::rowOf(const PairKey& key, int dim,
                                                                   const std::map<ArcId, int>& slot,
                                                                   const BiasProvider* biases) const {
  const auto s = slot.find(key.arc), sr = slot.find(key.reference_arc);
  const auto o = last_observation_.find(key.arc), orf = last_observation_.find(key.reference_arc);
  if (s == slot.end() || sr == slot.end() || o == last_observation_.end() || orf == last_observation_.end())
    return std::nullopt;
  auto ifPhaseBias = [&](const DualFrequencyObservation& obs) -> std::optional<double> {
    const BiasAnswer b1 = biases->phaseBias(obs.satellite, obs.phase1, obs.time);
    const BiasAnswer b2 = biases->phaseBias(obs.satellite, obs.phase2, obs.time);
    if (!b1.value_m || !b2.value_m) return std::nullopt;
    return ionosphereFree(*b1.value_m, *b2.value_m, ionosphereFreeCoefficients(obs.frequency1_hz, obs.frequency2_hz));
  };
  const auto b = ifPhaseBias(o->second), b_ref = ifPhaseBias(orf->second);
  if (!b || !b_ref) return std::nullopt;
  const double f1 = o->second.frequency1_hz, f2 = o->second.frequency2_hz;
  const double lambda_nl = narrowLaneWavelength_m(f1, f2);
  const double k_wl = ionosphereFreeAmbiguity_m(f1, f2, 0.0, 1.0);
  PairRow r;
  r.key = key;
  r.satellite = o->second.satellite;
  r.reference_satellite = orf->second.satellite;
  r.d = Eigen::RowVectorXd::Zero(dim);
  r.d(s->second) = 1.0 / lambda_nl;
  r.d(sr->second) = -1.0 / lambda_nl;
  r.offset = (*b - *b_ref + k_wl * static_cast<double>(key.wide_lane_cycles)) / lambda_nl;
  return r;
}

/// The state carried between the steps of resolveAndHold.
struct AmbiguityResolver::HoldEpoch {
  HoldEpoch(const Eigen::VectorXd& x_float, const Eigen::MatrixXd& P_float, const BiasProvider* bias_provider,
            AmbiguityFixSummary& fix_summary)
      : x(x_float), P(P_float), dim(static_cast<int>(x_float.size())), biases(bias_provider), summary(fix_summary) {}

  const Eigen::VectorXd& x;  // the float state and covariance
  const Eigen::MatrixXd& P;
  int dim;
  const BiasProvider* biases;
  AmbiguityFixSummary& summary;
  std::map<ArcId, int> all_slot;  // every bias arc: its state index
  std::map<ArcId, int> slot;      // those high enough for new candidates
  // Step 2-3: the held integers (rows, values) and the float conditioned on them
  // (nullopt: none held, or not positive definite).
  std::vector<PairRow> held_rows;
  std::vector<long> held_values;
  std::optional<Conditioning> held_state;
  ArcComponents components;  // arcs joined by held integers
  // Step 5: the candidates (sigma conditioned on the held integers [cycles]).
  std::vector<WideLaneResolution> per_system;
  std::vector<PairRow> candidates;
  std::vector<double> candidate_sigma;
  int gated = 0;  // steady floats refused by the candidate gate
  // Step 6: the integers of the accepted subset.
  std::map<PairKey, long> fixed_now;
  bool integer_far = false;  // the last subset tried was refused by the candidate gate

  const Eigen::VectorXd& conditionedX() const { return held_state ? held_state->state.x : x; }
  const Eigen::MatrixXd& conditionedP() const { return held_state ? held_state->state.P : P; }
};

namespace {

/// The constraints A x = y of held rows and their integers.
template <typename Row>
void stackConstraints(const std::vector<Row>& rows, const std::vector<long>& values, int dim, Eigen::MatrixXd& A,
                      Eigen::VectorXd& y) {
  const int n = static_cast<int>(rows.size());
  A.resize(n, dim);
  y.resize(n);
  for (int i = 0; i < n; ++i) {
    A.row(i) = rows[static_cast<std::size_t>(i)].d;
    y(i) = static_cast<double>(values[static_cast<std::size_t>(i)]) + rows[static_cast<std::size_t>(i)].offset;
  }
}

/// The candidate gate: a float further from an integer than both
/// max_fraction_cycles and max_fraction_sigmas of its own sigma carries an error its
/// covariance does not hold (an imprecise float is left to the search's success
/// rate and ratio test).
bool offInteger(double fraction_cycles, double sigma_cycles, const AmbiguityHoldOptions& ho) {
  return std::abs(fraction_cycles) > ho.max_fraction_cycles &&
         std::abs(fraction_cycles) > ho.max_fraction_sigmas * sigma_cycles;
}

/// The float history of a single difference is steady (step 5): its spread is
/// at most max_float_spread_cycles, or (max_float_drift_sigmas > 0) every value
/// lies within that many sigmas of the change from the window's first value
/// that the covariance explains, sqrt(sigma_first^2 - sigma_i^2).
template <typename Sample>
bool steadyFloat(const std::vector<Sample>& h, const AmbiguityHoldOptions& ho) {
  const auto [lo, hi] = std::minmax_element(
      h.begin(), h.end(), [](const Sample& a, const Sample& b) { return a.value_cycles < b.value_cycles; });
  if (hi->value_cycles - lo->value_cycles <= ho.max_float_spread_cycles) return true;
  if (ho.max_float_drift_sigmas <= 0.0) return false;
  const Sample& first = h.front();
  return std::all_of(h.begin(), h.end(), [&](const Sample& s) {
    const double explained_cycles =
        std::sqrt(std::max(0.0, first.sigma_cycles * first.sigma_cycles - s.sigma_cycles * s.sigma_cycles));
    return std::abs(s.value_cycles - first.value_cycles) <= ho.max_float_drift_sigmas * explained_cycles;
  });
}

/// The sigma [cycles] of a single difference d x under the covariance P.
double pairSigma_cycles(const Eigen::RowVectorXd& d, const Eigen::MatrixXd& P) {
  return std::sqrt(std::max(0.0, (d * P * d.transpose())(0, 0)));
}

}  // namespace

std::optional<AmbiguityFixedState> AmbiguityResolver::resolveAndHold(const Eigen::VectorXd& x,
                                                                     const Eigen::MatrixXd& P, int receiver_dim,
                                                                     const std::vector<ArcId>& bias_arcs,
                                                                     const BiasProvider* biases,
                                                                     AmbiguityFixSummary& summary,
                                                                     const std::map<ArcId, double>* elevation_rad) {
  summary = AmbiguityFixSummary{};
  if (!options_.enabled) return std::nullopt;
  if (!biases) {
    summary.float_reason = AmbiguityFloatReason::NoConsistentPhaseBiases;
    return std::nullopt;
  }
  HoldEpoch e(x, P, biases, summary);

  // 1. The state index of every bias arc, and the arcs high enough for new candidates.
  slotArcs(receiver_dim, bias_arcs, elevation_rad, e);

  // 2. The held integers whose arcs are present and whose wide lanes are unchanged.
  keepPresentHeld(e);

  // 3. Each held integer against its float conditioned on the other held ones;
  // the worst offender (if any) is released; the float conditioned on the rest.
  if (!conditionOnHeld(e)) {
    summary.float_reason = AmbiguityFloatReason::NumericalFailure;
    return std::nullopt;
  }

  // 4. The held single differences into the summary (float, sigma, integer).
  recordHeld(e);

  // 5. New candidates: wide-lane fixed arcs against this epoch's reference of
  // their system, steady over the float history and through the candidate gate.
  gatherCandidates(e);

  // 6. Partial fixing of the best-determined subset (conditioned on the held ones).
  searchBestSubset(e);

  // 7. Validation across epochs; a validated independent integer is held.
  validateAndHold(e);

  // 8. The held integers applied to a copy of the float state (or why it stays float).
  return applyHeld(e);
}

// Step 1
void AmbiguityResolver::slotArcs(int receiver_dim, const std::vector<ArcId>& bias_arcs,
                                 const std::map<ArcId, double>* elevation_rad, HoldEpoch& e) const {
  for (std::size_t i = 0; i < bias_arcs.size(); ++i) e.all_slot[bias_arcs[i]] = receiver_dim + static_cast<int>(i);
  for (const auto& [arc, index] : e.all_slot)
    if (highEnoughToFix(arc, elevation_rad, options_.min_elevation_rad)) e.slot[arc] = index;
}

std::map<AmbiguityResolver::PairKey, long>::iterator AmbiguityResolver::release(
    std::map<PairKey, long>::iterator it, AmbiguityReleaseReason why, double departure, const SatelliteId& sat,
    const SatelliteId& ref, AmbiguityFixSummary& summary) {
  summary.released.push_back({sat, ref, it->first.arc, it->first.reference_arc, why, departure});
  if (why != AmbiguityReleaseReason::ArcEnded) ++releases_total_;
  return held_.erase(it);
}

SatelliteId AmbiguityResolver::satelliteOf(ArcId arc) const {
  const auto o = last_observation_.find(arc);
  return o == last_observation_.end() ? SatelliteId{} : o->second.satellite;
}

// Step 2
void AmbiguityResolver::keepPresentHeld(HoldEpoch& e) {
  const auto& wl_means = wide_lane_.arcs();
  for (auto it = held_.begin(); it != held_.end();) {
    const auto row = rowOf(it->first, e.dim, e.all_slot, e.biases);
    if (!row) {
      it = release(it, AmbiguityReleaseReason::ArcEnded, 0.0, satelliteOf(it->first.arc),
                   satelliteOf(it->first.reference_arc), e.summary);
      continue;
    }
    const auto m = wl_means.find(it->first.arc), mr = wl_means.find(it->first.reference_arc);
    if (m != wl_means.end() && mr != wl_means.end() && pairDetermined(m->second, mr->second, options_.wide_lane) &&
        std::lround(m->second.mean_cycles - mr->second.mean_cycles) != it->first.wide_lane_cycles) {
      it = release(it, AmbiguityReleaseReason::WideLaneChanged, 0.0, row->satellite, row->reference_satellite,
                   e.summary);
      continue;
    }
    e.held_rows.push_back(*row);
    e.held_values.push_back(it->second);
    ++it;
  }
}

// Step 3: leave-one-out from the one factorisation of the held set.
bool AmbiguityResolver::conditionOnHeld(HoldEpoch& e) {
  const AmbiguityHoldOptions& ho = options_.hold;
  if (!e.held_rows.empty()) {
    Eigen::MatrixXd A;
    Eigen::VectorXd y;
    stackConstraints(e.held_rows, e.held_values, e.dim, A, y);
    e.held_state = conditionOn(e.x, e.P, A, y, true);
  }
  if (e.held_state) {
    int worst = -1;
    double worst_score = 0.0, worst_departure = 0.0;
    for (int i = 0; i < static_cast<int>(e.held_rows.size()); ++i) {
      const double k_ii = e.held_state->s_inv_diag(i);
      const double departure = e.held_state->u(i) / k_ii;
      const double score = std::abs(departure) * std::sqrt(k_ii);  // |departure| / sigma
      if (std::abs(departure) > ho.release_cycles && score > ho.release_sigma && score > worst_score)
        worst = i, worst_score = score, worst_departure = departure;
    }
    if (worst >= 0) {
      const PairRow r = e.held_rows[static_cast<std::size_t>(worst)];
      release(held_.find(r.key), AmbiguityReleaseReason::FloatDeparted, worst_departure, r.satellite,
              r.reference_satellite, e.summary);
      e.held_rows.erase(e.held_rows.begin() + worst);
      e.held_values.erase(e.held_values.begin() + worst);
      e.held_state.reset();
      if (!e.held_rows.empty()) {
        Eigen::MatrixXd A;
        Eigen::VectorXd y;
        stackConstraints(e.held_rows, e.held_values, e.dim, A, y);
        e.held_state = conditionOn(e.x, e.P, A, y, false);
      }
    }
  }
  return e.held_rows.empty() || e.held_state.has_value();
}

// Step 4
void AmbiguityResolver::recordHeld(HoldEpoch& e) const {
  for (const auto& r : e.held_rows) e.components.join(r.key.arc, r.key.reference_arc);
  for (std::size_t i = 0; i < e.held_rows.size(); ++i) {
    const PairRow& r = e.held_rows[i];
    NarrowLaneFloat f{r.key.arc, r.key.reference_arc, r.satellite, r.reference_satellite, r.key.wide_lane_cycles,
                      r.d.dot(e.x) - r.offset, pairSigma_cycles(r.d, e.P), e.held_values[i]};
    e.summary.narrow_lanes.push_back(f);
  }
}

// Step 5
void AmbiguityResolver::gatherCandidates(HoldEpoch& e) {
  const AmbiguityHoldOptions& ho = options_.hold;
  e.per_system = wideLanesPerSystemKeepingReferences(e.slot);
  recordWideLanes(e.per_system, e.summary);
  std::map<PairKey, bool> seen;
  for (std::size_t si = 0; si < e.per_system.size(); ++si) {
    const WideLaneResolution& wl = e.per_system[si];
    for (const WideLaneFix& f : wl.arcs) {
      if (!f.fixed) continue;
      const PairKey key{f.arc, *wl.reference_arc, f.integer_cycles};
      const auto row = rowOf(key, e.dim, e.slot, e.biases);
      if (!row) continue;
      seen[key] = true;
      std::vector<FloatSample>& h = float_history_[key];
      h.push_back({row->d.dot(e.x) - row->offset, pairSigma_cycles(row->d, e.P)});
      if (static_cast<int>(h.size()) > ho.consistency_epochs) h.erase(h.begin());
      if (held_.count(key) || e.components.find(f.arc) == e.components.find(*wl.reference_arc)) continue;
      NarrowLaneFloat nf{key.arc, key.reference_arc, row->satellite, row->reference_satellite, key.wide_lane_cycles,
                         h.back().value_cycles, h.back().sigma_cycles, std::nullopt};
      e.summary.narrow_lanes.push_back(nf);
      if (static_cast<int>(h.size()) < ho.consistency_epochs || !steadyFloat(h, ho)) continue;
      const double conditioned = row->d.dot(e.conditionedX()) - row->offset;
      const double conditioned_sigma = pairSigma_cycles(row->d, e.conditionedP());
      if (offInteger(conditioned - std::round(conditioned), conditioned_sigma, ho) ||
          conditioned_sigma > ho.max_sigma_cycles) {
        ++e.gated;
        continue;
      }
      e.candidates.push_back(*row);
      e.candidate_sigma.push_back(conditioned_sigma);
      ++e.summary.systems[si].narrow_lane_candidates;
    }
  }
  for (auto it = float_history_.begin(); it != float_history_.end();)
    it = seen.count(it->first) ? std::next(it) : float_history_.erase(it);
  e.summary.narrow_lane_candidates = static_cast<int>(e.candidates.size());
}

// Step 6
void AmbiguityResolver::searchBestSubset(HoldEpoch& e) const {
  const AmbiguityHoldOptions& ho = options_.hold;
  AmbiguityFixSummary& summary = e.summary;
  const int min_subset = e.held_rows.size() >= static_cast<std::size_t>(options_.narrow_lane.min_fixed)
                             ? 1
                             : std::max(1, options_.narrow_lane.min_fixed - static_cast<int>(e.held_rows.size()));
  std::vector<std::size_t> order(e.candidates.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return e.candidate_sigma[a] < e.candidate_sigma[b]; });
  const auto t0 = std::chrono::steady_clock::now();
  summary.ils_reason = IlsFloatReason::TooFewAmbiguities;
  for (int n = static_cast<int>(order.size()); n >= min_subset && n > 0; --n) {
    Eigen::MatrixXd D(n, e.dim);
    Eigen::VectorXd o(n);
    for (int i = 0; i < n; ++i) {
      const PairRow& r = e.candidates[order[static_cast<std::size_t>(i)]];
      D.row(i) = r.d;
      o(i) = r.offset;
    }
    IlsOptions io = options_.narrow_lane;
    io.partial = false;
    io.min_fixed = n;
    const Eigen::VectorXd a_hat = D * e.conditionedX() - o;
    const Eigen::MatrixXd Q = D * e.conditionedP() * D.transpose();
    IlsResult ils = solveIntegerLeastSquares(a_hat, Q, io);
    if ((ho.require_subset_success_rate || n <= ho.small_subset_max_size) && ils.isFixed() &&
        ils.bootstrap_success_rate < options_.narrow_lane.min_success_rate) {
      ils.fixed = 0;  // the ratio passed, but the subset is not determined well enough
      ils.fixed_ambiguities.reset();
      ils.float_reason = IlsFloatReason::LowSuccessRate;
    }
    summary.ratio = ils.ratio;
    summary.bootstrap_success_rate = ils.bootstrap_success_rate;
    summary.ils_reason = ils.float_reason;
    e.integer_far = false;
    if (ils.isFixed() && ils.fixed_ambiguities)
      for (int i = 0; i < n; ++i)
        e.integer_far = e.integer_far || offInteger(a_hat(i) - (*ils.fixed_ambiguities)(i),
                                                    std::sqrt(std::max(0.0, Q(i, i))), ho);
    if (e.integer_far) continue;
    if (ils.isFixed() && ils.fixed_ambiguities) {
      for (int i = 0; i < n; ++i)
        e.fixed_now[e.candidates[order[static_cast<std::size_t>(i)]].key] = std::lround((*ils.fixed_ambiguities)(i));
      break;
    }
  }
  summary.search_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Step 7: fewer epochs for a subset whose success rate says it is determined.
void AmbiguityResolver::validateAndHold(HoldEpoch& e) {
  const AmbiguityHoldOptions& ho = options_.hold;
  const int needed_epochs = !e.fixed_now.empty() && ho.fast_validation_success_rate < 1.0 &&
                                    e.summary.bootstrap_success_rate >= ho.fast_validation_success_rate
                                ? std::min(ho.fast_validation_epochs, ho.validation_epochs)
                                : ho.validation_epochs;
  for (auto it = pending_.begin(); it != pending_.end();)
    it = e.fixed_now.count(it->first) ? std::next(it) : pending_.erase(it);
  for (const auto& [key, integer] : e.fixed_now) {
    Pending& p = pending_[key];
    if (p.count > 0 && p.integer == integer) {
      ++p.count;
    } else {
      p.integer = integer;
      p.count = 1;
    }
    if (p.count >= needed_epochs && e.components.join(key.arc, key.reference_arc)) {
      held_[key] = integer;
      ++e.summary.newly_held;
      pending_.erase(key);
      if (const auto row = rowOf(key, e.dim, e.all_slot, e.biases)) {
        e.held_rows.push_back(*row);
        e.held_values.push_back(integer);
      }
    }
  }
}

// Step 8
std::optional<AmbiguityFixedState> AmbiguityResolver::applyHeld(HoldEpoch& e) const {
  AmbiguityFixSummary& summary = e.summary;
  summary.held = static_cast<int>(e.held_rows.size());
  for (SystemAmbiguitySummary& sys : summary.systems)
    sys.held = static_cast<int>(std::count_if(e.held_rows.begin(), e.held_rows.end(), [&](const PairRow& r) {
      return r.satellite.system == sys.system;
    }));
  for (auto& f : summary.narrow_lanes)
    if (!f.held_cycles) {
      const auto h = held_.find(PairKey{f.arc, f.reference_arc, f.wide_lane_cycles});
      if (h != held_.end()) f.held_cycles = h->second;
    }
  if (summary.held < options_.narrow_lane.min_fixed) {
    summary.float_reason = floatReason(e);
    return std::nullopt;
  }
  Eigen::MatrixXd A;
  Eigen::VectorXd y;
  stackConstraints(e.held_rows, e.held_values, e.dim, A, y);
  // Nothing newly held: the held set is the one already conditioned on in step 3.
  std::optional<AmbiguityFixedState> fixed;
  if (summary.newly_held == 0 && e.held_state) {
    fixed = std::move(e.held_state->state);
  } else if (auto c = conditionOn(e.x, e.P, A, y, false)) {
    fixed = std::move(c->state);
  }
  if (!fixed) {
    summary.float_reason = AmbiguityFloatReason::NumericalFailure;
    return std::nullopt;
  }
  summary.held_residual_statistic = fixed->constraint_residual_statistic;
  summary.held_residual_dof = static_cast<int>(A.rows());
  fixed->constraint_rows = A;  // the held integers: what the smoother keeps as factors
  fixed->constraint_values = y;
  summary.narrow_lanes_fixed = summary.held;
  summary.float_reason = AmbiguityFloatReason::None;
  return fixed;
}

AmbiguityFloatReason AmbiguityResolver::floatReason(const HoldEpoch& e) const {
  const AmbiguityFixSummary& summary = e.summary;
  return summary.held > 0 || !pending_.empty()                          ? AmbiguityFloatReason::Validating
         : e.per_system.empty()                                        ? AmbiguityFloatReason::NoWideLaneReference
         : e.candidates.empty() && e.gated > 0                         ? AmbiguityFloatReason::FloatsOffInteger
         : e.candidates.empty() && !summary.narrow_lanes.empty()       ? AmbiguityFloatReason::FloatsDrifting
         : e.candidates.empty()                                        ? AmbiguityFloatReason::TooFewWideLanes
         : e.integer_far                                               ? AmbiguityFloatReason::IntegerFarFromFloat
                                                                       : AmbiguityFloatReason::NarrowLane;
}

}  // namespace ppp
