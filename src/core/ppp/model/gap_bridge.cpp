#include "ppp_bayes_tree/ppp/model/gap_bridge.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "ppp_bayes_tree/ppp/model/chi_square_quantile.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

namespace {

struct Solved {
  Eigen::VectorXd residual_m;  // per active row
  Eigen::VectorXd sigma_m;     // sigma of the predicted value plus the row's noise
};

/// The active rows' design: H = [position Jacobian, clock], the weights, and the
/// normal matrix with the position prior.
struct Design {
  Eigen::MatrixXd H, N;
  Eigen::VectorXd w, y;
};

Design design(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, int clocks,
              const Eigen::Matrix3d& position_cov_m2) {
  const int n = static_cast<int>(active.size()), u = 3 + clocks;
  Design d;
  d.H = Eigen::MatrixXd::Zero(n, u);
  d.w.resize(n);
  d.y.resize(n);
  for (int i = 0; i < n; ++i) {
    const GapBridgeRow& r = rows[static_cast<std::size_t>(active[static_cast<std::size_t>(i)])];
    d.H.block<1, 3>(i, 0) = r.position_jacobian;
    d.H(i, 3 + r.clock) = 1.0;
    d.y(i) = r.residual_m;
    d.w(i) = 1.0 / (r.sigma_m * r.sigma_m);
  }
  d.N = d.H.transpose() * d.w.asDiagonal() * d.H;
  d.N.topLeftCorner<3, 3>() += position_cov_m2.inverse();
  return d;
}

/// Least squares of [dp(3); clocks] over the active rows, dp with the prior covariance.
Solved solveRows(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, int clocks,
                 const Eigen::Matrix3d& position_cov_m2) {
  const Design d = design(rows, active, clocks, position_cov_m2);
  const Eigen::Index n = d.H.rows(), u = d.H.cols();
  const Eigen::MatrixXd Q = d.N.ldlt().solve(Eigen::MatrixXd::Identity(u, u));
  const Eigen::VectorXd x = Q * (d.H.transpose() * d.w.asDiagonal() * d.y);
  Solved s;
  s.residual_m = d.y - d.H * x;
  s.sigma_m.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) s.sigma_m(i) = std::sqrt(d.H.row(i) * Q * d.H.row(i).transpose() + 1.0 / d.w(i));
  return s;
}

/// What a row's choice adds to its residual [m].
double candidateOffset_m(const GapBridgeRow& row, int candidate) {
  return candidate < 0 ? 0.0 : row.candidate_offsets_m[static_cast<std::size_t>(candidate)];
}

/// The least-squares cost of the active rows (with the position prior) as a quadratic
/// form of the residual vector: J(y) = y' M y, M = W - W H N^-1 H' W.
Eigen::MatrixXd costMatrix(const Design& d) {
  const Eigen::MatrixXd WH = d.w.asDiagonal() * d.H;
  Eigen::MatrixXd M = -WH * d.N.ldlt().solve(WH.transpose());
  M.diagonal() += d.w;
  return M;
}

/// An assignment of candidates to the active rows (-1: the slip applied) and its cost.
struct Assignment {
  std::vector<int> choice;  // per active row
  double cost = std::numeric_limits<double>::infinity();
};

/// A candidate's entry of a per-candidate list; missing entries are 0.
template <typename T>
T candidateValue(const std::vector<T>& values, int candidate) {
  return candidate < static_cast<int>(values.size()) ? values[static_cast<std::size_t>(candidate)] : T{0};
}

/// A row's prior cost of a choice (GapBridgeRow::applied_prior_cost, candidate_prior_costs).
double priorCost(const GapBridgeRow& row, int candidate) {
  return candidate < 0 ? row.applied_prior_cost : candidateValue(row.candidate_prior_costs, candidate);
}

/// A row's wide lane offset of a choice [cycles] (GapBridgeRow::candidate_wide_lane_offsets_cycles).
long wideLaneOffset_cycles(const GapBridgeRow& row, int candidate) {
  return candidate < 0 ? 0 : candidateValue(row.candidate_wide_lane_offsets_cycles, candidate);
}

/// Two assignments differ only by one slip common to every row of a free clock (the
/// same L1 offset and wide lane offset in each), and not at all on the other clocks'
/// rows: the phases cannot tell them apart and the differences between satellites
/// are the same (gap_bridge.h).
bool twins(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, const std::vector<int>& a,
           const std::vector<int>& b) {
  constexpr double kSameOffset_m = 1e-6;
  std::vector<std::optional<std::pair<double, long>>> shift;  // per clock, from its first row
  for (std::size_t i = 0; i < active.size(); ++i) {
    const GapBridgeRow& r = rows[static_cast<std::size_t>(active[i])];
    const double d_m = candidateOffset_m(r, a[i]) - candidateOffset_m(r, b[i]);
    const long d_wl = wideLaneOffset_cycles(r, a[i]) - wideLaneOffset_cycles(r, b[i]);
    if (!r.clock_free) {
      if (std::abs(d_m) > kSameOffset_m || d_wl != 0) return false;
      continue;
    }
    if (shift.size() <= static_cast<std::size_t>(r.clock)) shift.resize(static_cast<std::size_t>(r.clock) + 1);
    auto& s = shift[static_cast<std::size_t>(r.clock)];
    if (!s) s = std::make_pair(d_m, d_wl);
    else if (std::abs(s->first - d_m) > kSameOffset_m || s->second != d_wl) return false;
  }
  return true;
}

/// The cheapest assignments seen, in cost order, at most `size` of them.
class CheapestAssignments {
 public:
  explicit CheapestAssignments(std::size_t size) : size_(size) {}
  void offer(const Assignment& a) {
    if (kept_.size() == size_ && !(a.cost < kept_.back().cost)) return;
    const auto at = std::upper_bound(kept_.begin(), kept_.end(), a.cost,
                                     [](double c, const Assignment& k) { return c < k.cost; });
    kept_.insert(at, a);
    if (kept_.size() > size_) kept_.pop_back();
  }
  const std::vector<Assignment>& kept() const { return kept_; }

 private:
  std::size_t size_;
  std::vector<Assignment> kept_;
};

/// How many of the cheapest assignments are kept to find the best's next best past its twins.
constexpr std::size_t kKeptAssignments = 64;

/// The best assignment, the next best that is not its twin, and its cheapest twin
/// (each with an empty choice and an infinite cost when there is none).
struct Ranked {
  Assignment best, next, twin;
};

/// The `keep` cheapest assignments of the candidate rows, in cost order. The cost is
/// the least-squares cost of the phases plus each row's prior cost of its choice (its
/// wide lane against the Melbourne-Wubbena jump); among twins, only that prior tells
/// them apart.
std::vector<Assignment> cheapestAssignments(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active,
                                            int clocks, const Eigen::Matrix3d& position_cov_m2, std::size_t keep) {
  const Design design_rows = design(rows, active, clocks, position_cov_m2);
  const Eigen::MatrixXd M = costMatrix(design_rows);
  const Eigen::VectorXd My = M * design_rows.y;
  const double base = design_rows.y.dot(My);
  const int n = static_cast<int>(active.size());
  std::vector<int> candidate_rows;
  for (int i = 0; i < n; ++i)
    if (!rows[static_cast<std::size_t>(active[static_cast<std::size_t>(i)])].candidate_offsets_m.empty())
      candidate_rows.push_back(i);
  // Odometer over the candidate rows' choices; the cheapest kept.
  CheapestAssignments cheapest(keep);
  Assignment current;
  current.choice.assign(static_cast<std::size_t>(n), -1);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
  while (true) {
    double prior = 0.0;
    for (const int i : candidate_rows)
      prior += priorCost(rows[static_cast<std::size_t>(active[static_cast<std::size_t>(i)])],
                         current.choice[static_cast<std::size_t>(i)]);
    current.cost = base + 2.0 * d.dot(My) + d.dot(M * d) + prior;
    cheapest.offer(current);
    std::size_t k = 0;
    for (; k < candidate_rows.size(); ++k) {
      const int i = candidate_rows[k];
      const GapBridgeRow& r = rows[static_cast<std::size_t>(active[static_cast<std::size_t>(i)])];
      int& c = current.choice[static_cast<std::size_t>(i)];
      if (c + 1 < static_cast<int>(r.candidate_offsets_m.size())) {
        ++c;
        d(i) = candidateOffset_m(r, c);
        break;
      }
      c = -1;
      d(i) = 0.0;
    }
    if (k == candidate_rows.size()) break;
  }
  return cheapest.kept();
}

/// Every assignment of the candidate rows, ranked (cheapestAssignments): the best, the
/// next best that is not its twin, and its cheapest twin.
Ranked rankAssignments(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, int clocks,
                       const Eigen::Matrix3d& position_cov_m2) {
  const std::vector<Assignment> kept = cheapestAssignments(rows, active, clocks, position_cov_m2, kKeptAssignments);
  Ranked ranked{kept.front(), {}, {}};
  for (auto a = kept.begin() + 1; a != kept.end(); ++a) {
    Assignment& slot = twins(rows, active, ranked.best.choice, a->choice) ? ranked.twin : ranked.next;
    if (!std::isfinite(slot.cost)) slot = *a;
  }
  return ranked;
}

/// How many assignments the candidate rows make.
double assignmentCount(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active) {
  double count = 1.0;
  for (int i : active) count *= 1.0 + static_cast<double>(rows[static_cast<std::size_t>(i)].candidate_offsets_m.size());
  return count;
}

/// The active row with the most candidates (the first of equals).
std::vector<int>::iterator mostCandidates(const std::vector<GapBridgeRow>& rows, std::vector<int>& active) {
  return std::max_element(active.begin(), active.end(), [&](int a, int b) {
    return rows[static_cast<std::size_t>(a)].candidate_offsets_m.size() <
           rows[static_cast<std::size_t>(b)].candidate_offsets_m.size();
  });
}

/// The assignment chosen for the candidate rows.
struct Chosen {
  double best_cost = 0.0;
  double second_cost = std::numeric_limits<double>::infinity();  // the next best's; infinite without one
  std::vector<int> differing;  // the rows (indices into `rows`) where the two differ
  double twin_cost = std::numeric_limits<double>::infinity();  // the best's cheapest twin's
  std::vector<int> twin_differing;  // the rows where the best and that twin differ
};

/// The candidates of the active rows: the assignment of least cost (each row's choice
/// into `out`, its residual into `work`), with the next best's cost.
Chosen chooseCandidates(const std::vector<GapBridgeRow>& rows, std::vector<GapBridgeRow>& work,
                        std::vector<int>& active, int clocks, const Eigen::Matrix3d& position_cov_m2,
                        const GapBridgeOptions& o, std::vector<GapBridgeVerdict>& out) {
  // Too many assignments: the rows with the most candidates end first.
  while (assignmentCount(rows, active) > o.max_candidate_assignments) {
    const auto most = mostCandidates(rows, active);
    out[static_cast<std::size_t>(*most)].reason =
        format("too many slip candidate assignments (more than %.0f)", o.max_candidate_assignments);
    active.erase(most);
  }
  const Ranked ranked = rankAssignments(rows, active, clocks, position_cov_m2);
  const Assignment& best = ranked.best;
  const Assignment& second = ranked.next;
  Chosen chosen{best.cost, second.cost, {}, ranked.twin.cost, {}};
  for (std::size_t i = 0; i < active.size(); ++i) {
    const auto k = static_cast<std::size_t>(active[i]);
    out[k].candidate = best.choice[i];
    work[k].residual_m = rows[k].residual_m + candidateOffset_m(rows[k], best.choice[i]);
    if (std::isfinite(second.cost) &&
        candidateOffset_m(rows[k], best.choice[i]) != candidateOffset_m(rows[k], second.choice[i]))
      chosen.differing.push_back(active[i]);
    if (std::isfinite(ranked.twin.cost) && best.choice[i] != ranked.twin.choice[i])
      chosen.twin_differing.push_back(active[i]);
  }
  return chosen;
}

/// The best assignment is told apart from the next: its cost at least
/// min_candidate_separation^2 more and min_candidate_ratio times as much.
bool toldApart(double best_cost, double next_cost, const GapBridgeOptions& o) {
  return !std::isfinite(next_cost) ||
         (next_cost - best_cost >= o.min_candidate_separation * o.min_candidate_separation &&
          next_cost >= o.min_candidate_ratio * best_cost);
}

/// The chosen assignment's degrees of freedom: the rows less the clocks (the prior's
/// 3 rows and 3 unknowns cancel), plus each candidate row's wide-lane prior.
int assignmentDof(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, int clocks) {
  int dof = static_cast<int>(active.size()) - clocks;
  for (const int k : active) dof += rows[static_cast<std::size_t>(k)].candidate_offsets_m.empty() ? 0 : 1;
  return dof;
}

/// A row to end, and the best assignment's cost without it.
struct Exclusion {
  std::size_t row = 0;  // index into `active`
  double cost_without = std::numeric_limits<double>::infinity();
};

/// The row to end when the best assignment's cost does not fit: the one whose
/// exclusion lowers the best cost the most (the assignments costed again without it,
/// as the identification step of a detection-identification-adaptation test). A row
/// whose applied slip is wrong and has no candidates drags the rows that have
/// candidates to the ones that match it, at the cost of their wide lanes against their
/// MW jumps; without it they fit. Neither that row's phase residual nor its share of
/// the cost shows it.
Exclusion costliestRow(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, int clocks,
                       const Eigen::Matrix3d& position_cov_m2) {
  Exclusion best;
  std::vector<int> rest;
  for (std::size_t i = 0; i < active.size(); ++i) {
    rest.assign(active.begin(), active.end());
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(i));
    const double cost = cheapestAssignments(rows, rest, clocks, position_cov_m2, 1).front().cost;
    if (cost < best.cost_without) best = {i, cost};
  }
  return best;
}

/// The best assignment's cost does not fit: the row whose exclusion lowers it the
/// most ends (costliestRow), its reason `misfit` and the cost without it. Ranking once
/// per row costs rows x assignments: beyond the assignments' bound the row with the
/// most candidates ends instead, as in chooseCandidates.
void endMisfitRow(const std::vector<GapBridgeRow>& rows, std::vector<int>& active, int clocks,
                  const Eigen::Matrix3d& position_cov_m2, const GapBridgeOptions& o, const std::string& misfit,
                  std::vector<GapBridgeVerdict>& out) {
  if (assignmentCount(rows, active) * static_cast<double>(active.size()) > o.max_candidate_assignments) {
    const auto most = mostCandidates(rows, active);
    out[static_cast<std::size_t>(*most)].reason =
        misfit + "; too many assignments to rank without each arc, this arc has the most candidates";
    active.erase(most);
    return;
  }
  const Exclusion worst = costliestRow(rows, active, clocks, position_cov_m2);
  out[static_cast<std::size_t>(active[worst.row])].reason =
      misfit + format("; without this arc it costs %.1f, the least", worst.cost_without);
  active.erase(active.begin() + static_cast<std::ptrdiff_t>(worst.row));
}

/// Index (into `active`) of the worst failing row; -1 when all pass.
int worstFailing(const std::vector<GapBridgeRow>& rows, const std::vector<int>& active, const Solved& s,
                 const GapBridgeOptions& o, std::vector<GapBridgeVerdict>& out) {
  int worst = -1;
  double worst_excess = 0.0;
  for (std::size_t i = 0; i < active.size(); ++i) {
    const GapBridgeRow& r = rows[static_cast<std::size_t>(active[i])];
    GapBridgeVerdict& v = out[static_cast<std::size_t>(active[i])];
    v.slip_cycles = s.residual_m(static_cast<int>(i)) / r.wavelength_m;
    v.sigma_cycles = s.sigma_m(static_cast<int>(i)) / r.wavelength_m;
    const double excess = std::max(std::abs(v.slip_cycles) - o.max_fraction_cycles, v.sigma_cycles - o.max_sigma_cycles);
    if (excess > 0.0 && (worst < 0 || excess > worst_excess)) worst = static_cast<int>(i), worst_excess = excess;
  }
  return worst;
}

/// The prior covariance with each eigenvalue at least floor_sigma_m^2.
Eigen::Matrix3d flooredCovariance(const Eigen::Matrix3d& cov_m2, double floor_sigma_m) {
  if (!(floor_sigma_m > 0.0)) return cov_m2;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (cov_m2 + cov_m2.transpose()));
  const Eigen::Vector3d values = eig.eigenvalues().cwiseMax(floor_sigma_m * floor_sigma_m);
  return eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

std::vector<GapBridgeVerdict> bridgeGap(const std::vector<GapBridgeRow>& rows, const Eigen::Matrix3d& given_cov_m2,
                                        const GapBridgeOptions& options) {
  const Eigen::Matrix3d position_cov_m2 = flooredCovariance(given_cov_m2, options.min_position_sigma_m);
  std::vector<GapBridgeVerdict> out(rows.size());
  std::vector<int> active;
  int clocks = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    active.push_back(static_cast<int>(i));
    clocks = std::max(clocks, rows[i].clock + 1);
    out[i].slip_cycles = std::numeric_limits<double>::quiet_NaN();
  }
  const bool any_candidates = std::any_of(rows.begin(), rows.end(), [](const GapBridgeRow& r) {
    return !r.candidate_offsets_m.empty();
  });
  std::vector<GapBridgeRow> work = rows;  // residuals with each row's chosen candidate
  const ChiSquareUpperQuantile cost_quantile(options.candidate_cost_false_alarm);
  while (static_cast<int>(active.size()) >= 3 + clocks + options.min_extra_rows) {
    // 1. Each candidate row's slip: the assignment of least cost.
    Chosen chosen;
    if (any_candidates) chosen = chooseCandidates(rows, work, active, clocks, position_cov_m2, options, out);
    if (static_cast<int>(active.size()) < 3 + clocks + options.min_extra_rows) break;
    // 2. The slips at it: the worst failing row ends, and all is tried again.
    const Solved s = solveRows(work, active, clocks, position_cov_m2);
    const int worst = worstFailing(work, active, s, options, out);
    if (worst >= 0) {
      GapBridgeVerdict& v = out[static_cast<std::size_t>(active[static_cast<std::size_t>(worst)])];
      v.reason = format("slip %.2f +- %.2f cycles (bounds %.2f, %.2f)", v.slip_cycles, v.sigma_cycles,
                        options.max_fraction_cycles, options.max_sigma_cycles);
      active.erase(active.begin() + worst);
      continue;
    }
    // 3. All pass: with candidates, the assignment's cost must fit the rows' noise
    //    (else the row whose exclusion lowers that cost the most ends) and be told apart from
    //    the next best (else the rows where the two differ end).
    const int dof = assignmentDof(rows, active, clocks);
    if (any_candidates && chosen.best_cost > cost_quantile(dof)) {
      endMisfitRow(rows, active, clocks, position_cov_m2, options,
                   format("the slip candidates' best assignment does not fit (cost %.1f > %.1f for %d degrees of "
                          "freedom)",
                          chosen.best_cost, cost_quantile(dof), dof),
                   out);
      continue;
    }
    if (!toldApart(chosen.best_cost, chosen.second_cost, options)) {
      for (int k : chosen.differing) {
        out[static_cast<std::size_t>(k)].reason =
            format("its slip candidates are not told apart (the best two assignments cost %.1f and %.1f)",
                   chosen.best_cost, chosen.second_cost);
        active.erase(std::find(active.begin(), active.end(), k));
      }
      continue;
    }
    // 4. Kept. A twin the wide lanes could not tell apart leaves the shift common to
    //    its rows undecided (GapBridgeVerdict::common_shift_undecided).
    for (int i : active) out[static_cast<std::size_t>(i)].keep = true;
    if (!toldApart(chosen.best_cost, chosen.twin_cost, options))
      for (int k : chosen.twin_differing) out[static_cast<std::size_t>(k)].common_shift_undecided = true;
    return out;
  }
  for (int i : active)
    out[static_cast<std::size_t>(i)].reason = format("%d arcs back after the gap, too few to test the slips",
                                                    static_cast<int>(active.size()));
  return out;
}

}  // namespace ppp
