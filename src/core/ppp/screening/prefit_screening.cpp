#include "ppp_bayes_tree/ppp/screening/prefit_screening.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "ppp_bayes_tree/types/number_text.h"

namespace ppp {
namespace {

double median(std::vector<double> v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  if (v.size() % 2 == 1) return v[mid];
  const double upper = v[mid];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
}

}  // namespace

std::string measurementProblem(const SatelliteMeasurement& m) {
  if (!std::isfinite(m.observed_code_m)) return "non-finite observed code";
  if (!std::isfinite(m.observed_phase_m)) return "non-finite observed phase";
  if (!std::isfinite(m.predicted_code_m)) return "non-finite predicted code";
  if (!std::isfinite(m.predicted_phase_m)) return "non-finite predicted phase";
  if (!m.jacobian.allFinite()) return "non-finite Jacobian";
  if (!std::isfinite(m.code_sigma_m) || m.code_sigma_m <= 0.0) return "invalid code sigma " + fixedDecimals(m.code_sigma_m);
  if (!std::isfinite(m.phase_sigma_m) || m.phase_sigma_m <= 0.0)
    return "invalid phase sigma " + fixedDecimals(m.phase_sigma_m);
  return {};
}

bool matchesLayout(const SatelliteMeasurement& m, const ReceiverStateLayout& layout) {
  return m.jacobian.size() == layout.dim();
}

std::vector<SatelliteMeasurement> usableMeasurements(const std::vector<SatelliteMeasurement>& used,
                                                     std::vector<RejectedSatellite>& rejected) {
  std::vector<SatelliteMeasurement> out;
  std::set<SatelliteId> seen;
  for (const auto& m : used) {
    if (!seen.insert(m.satellite).second) {
      rejected.push_back(
          {m.satellite, RejectionReason::DuplicateMeasurement, "duplicate measurement of the satellite in the epoch"});
      continue;
    }
    if (auto problem = measurementProblem(m); !problem.empty()) {
      rejected.push_back({m.satellite, RejectionReason::NonFiniteModel, problem});
      continue;
    }
    out.push_back(m);
  }
  return out;
}

std::optional<double> medianCodeClockShift_m(const std::vector<SatelliteMeasurement>& ms,
                                             const ReceiverStateLayout& layout, GnssSystem system) {
  const int clock = layout.clock(system);
  if (clock < 0) return std::nullopt;
  std::vector<double> code_residuals;
  for (const auto& m : ms)
    if (m.satellite.system == system) code_residuals.push_back(m.codeResidual_m() / m.jacobian(clock));
  if (code_residuals.empty()) return std::nullopt;
  const double shift = median(code_residuals);
  if (!std::isfinite(shift)) return std::nullopt;
  return shift;
}

void applyClockShift(std::vector<SatelliteMeasurement>& ms, const ReceiverStateLayout& layout, GnssSystem system,
                     double shift_m) {
  const int clock = layout.clock(system);
  if (clock < 0) return;
  for (auto& m : ms) {
    if (m.satellite.system != system) continue;
    m.predicted_code_m += m.jacobian(clock) * shift_m;
    m.predicted_phase_m += m.jacobian(clock) * shift_m;
  }
}

std::vector<CodeOutlier> screenCodeOutliers(const std::vector<SatelliteMeasurement>& ms, double threshold_m,
                                            const ReceiverStateLayout& layout) {
  std::vector<CodeOutlier> rejected;
  std::vector<std::size_t> active(ms.size());
  for (std::size_t i = 0; i < ms.size(); ++i) active[i] = i;
  // An outlier is identifiable only with a redundancy of at least 2 (GPS alone:
  // 4 unknowns, position and clock): with 5 satellites every residual of the fit
  // is the same multiple of one number, and the deleted residual r / (1 - h) of
  // a satellite the others barely predict explodes (a 0 m true error showed up
  // as -3186 m in the Monte Carlo figure-eight flights). So at least unknowns + 2
  // satellites, and only satellites with 1 - h >= kMinCheckability are tested.
  // The unknowns: position, and the clock of each system with satellites.
  constexpr double kMinCheckability = 0.05;
  for (;;) {
    std::vector<int> columns;
    for (int i = 0; i < ReceiverStateLayout::kPositionSize; ++i) columns.push_back(layout.position() + i);
    for (const GnssSystem system : layout.clockSystems()) {
      for (const std::size_t k : active) {
        if (ms[k].satellite.system == system) {
          columns.push_back(layout.clock(system));
          break;
        }
      }
    }
    const int unknowns = static_cast<int>(columns.size());
    if (static_cast<int>(active.size()) < unknowns + 2) break;
    const int n = static_cast<int>(active.size());
    Eigen::MatrixXd A(n, unknowns);  // whitened design
    Eigen::VectorXd b(n);            // whitened residuals
    for (int k = 0; k < n; ++k) {
      const auto& m = ms[active[k]];
      for (int c = 0; c < unknowns; ++c) A(k, c) = m.jacobian(columns[static_cast<std::size_t>(c)]) / m.code_sigma_m;
      b(k) = m.codeResidual_m() / m.code_sigma_m;
    }
    Eigen::LDLT<Eigen::MatrixXd> ldlt(A.transpose() * A);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || ldlt.rcond() < 1e-14) break;
    const Eigen::VectorXd r = b - A * ldlt.solve(A.transpose() * b);
    const Eigen::MatrixXd leverage = A * ldlt.solve(A.transpose());
    int worst = -1;
    double worst_w = 0.0;
    for (int k = 0; k < n; ++k) {
      const double one_minus_h = 1.0 - leverage(k, k);
      if (one_minus_h < kMinCheckability) continue;  // not checkable: the others barely predict it
      const double w = std::abs(r(k)) / std::sqrt(one_minus_h);
      if (w > worst_w) {
        worst = k;
        worst_w = w;
      }
    }
    if (worst < 0) break;
    const double worst_m = r(worst) / (1.0 - leverage(worst, worst)) * ms[active[worst]].code_sigma_m;
    if (!(std::abs(worst_m) > threshold_m)) break;
    rejected.push_back({active[worst], worst_m});
    active.erase(active.begin() + worst);
  }
  return rejected;
}

std::string codeOutlierReason(const CodeOutlier& outlier, double threshold_m) {
  return "prefit code residual " + fixedDecimals(outlier.residual_m) + " m (against a fit to the others) > " +
         fixedDecimals(threshold_m) + " m";
}

std::optional<std::string> phaseInnovationRejection(const SatelliteMeasurement& m, double bias_m,
                                                    double bias_variance_m2, double sigmas) {
  const double innovation = m.phaseResidualWithoutBias_m() - bias_m - m.codeResidual_m();
  const double sigma =
      std::sqrt(bias_variance_m2 + m.code_sigma_m * m.code_sigma_m + m.phase_sigma_m * m.phase_sigma_m);
  if (std::abs(innovation) > sigmas * sigma)
    return "prefit phase-minus-code innovation " + fixedDecimals(innovation) + " m > " + fixedDecimals(sigmas, 1) + " sigma (" +
           fixedDecimals(sigma) + " m)";
  return std::nullopt;
}

std::string ScreeningOptions::validate() const {
  if (min_satellites < 1) return "min_satellites must be >= 1";
  if (!(prefit_code_threshold_m > 0.0)) return "prefit_code_threshold_m must be > 0";
  if (!(prefit_phase_sigmas > 0.0)) return "prefit_phase_sigmas must be > 0";
  if (!(stale_arc_timeout_s >= 0.0)) return "stale_arc_timeout_s must be >= 0";
  if (!(postfit_sigmas > 0.0)) return "postfit_sigmas must be > 0";
  if (postfit_max_rejections < 0) return "postfit_max_rejections must be >= 0";
  if (!(consistency_false_alarm > 0.0 && consistency_false_alarm < 0.5))
    return "consistency_false_alarm must be in (0, 0.5)";
  return {};
}

std::string toString(ConsistencyAction action) {
  switch (action) {
    case ConsistencyAction::Inflate: return "inflate";
    case ConsistencyAction::Withhold: return "withhold";
  }
  return "unknown";
}

PrefitScreeningResult screenPrefit(const std::vector<SatelliteMeasurement>& candidates,
                                   const ScreeningOptions& options, const ArcBiasLookup& bias_of,
                                   const ReceiverStateLayout& layout) {
  PrefitScreeningResult out;
  std::vector<bool> keep(candidates.size(), true);
  for (const auto& outlier : screenCodeOutliers(candidates, options.prefit_code_threshold_m, layout)) {
    keep[outlier.index] = false;
    out.rejected.push_back({candidates[outlier.index].satellite, RejectionReason::PrefitCode,
                            codeOutlierReason(outlier, options.prefit_code_threshold_m)});
  }
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (!keep[k]) continue;
    const std::optional<ArcBiasPrior> bias = bias_of(candidates[k].arc);
    if (!bias) continue;
    if (auto why = phaseInnovationRejection(candidates[k], bias->bias_m, bias->variance_m2,
                                            options.prefit_phase_sigmas)) {
      keep[k] = false;
      out.rejected.push_back({candidates[k].satellite, RejectionReason::PrefitPhase, *why});
    }
  }
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (keep[k]) out.kept.push_back(candidates[k]);
  return out;
}

}  // namespace ppp
