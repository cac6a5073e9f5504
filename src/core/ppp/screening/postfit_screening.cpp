#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/types/number_text.h"

namespace ppp {
namespace {

/// Upper standard-normal quantile z with P(Z > z) = alpha, by bisection on erfc
/// (exact to double rounding; alpha in (0, 0.5]).
double normalUpperQuantile(double alpha) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(mid / std::sqrt(2.0)) > alpha)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

std::optional<PostfitOutlier> worstPostfitResidual(const std::vector<PostfitResidualPair>& pairs, double sigmas) {
  std::optional<PostfitOutlier> worst;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PostfitResidualPair& p = pairs[i];
    for (const bool code : {true, false}) {
      const double r = code ? p.code_m : p.phase_m;
      const double ratio = std::abs(r) / (code ? p.code_sigma_m : p.phase_sigma_m);
      if (!worst || ratio > worst->normalised) worst = PostfitOutlier{i, code, r, ratio};
    }
  }
  if (worst && worst->normalised > sigmas) return worst;
  return std::nullopt;
}

RejectedSatellite postfitRejection(const SatelliteId& satellite, const PostfitOutlier& o, double sigmas) {
  return {satellite, o.code ? RejectionReason::PostfitCode : RejectionReason::PostfitPhase,
          std::string("postfit ") + (o.code ? "code" : "phase") + " residual " + fixedDecimals(o.residual_m) + " m = " +
              fixedDecimals(o.normalised, 1) + " sigma > " + fixedDecimals(sigmas, 1) + " sigma"};
}

double chiSquareUpperQuantile(int dof, double alpha) {
  if (dof <= 0) return 0.0;
  return ChiSquareUpperQuantile(alpha)(dof);
}

ChiSquareUpperQuantile::ChiSquareUpperQuantile(double alpha)
    : alpha_(alpha), normal_quantile_(normalUpperQuantile(alpha)) {}

double ChiSquareUpperQuantile::operator()(int dof) const {
  if (dof <= 0) return 0.0;
  const double z = normal_quantile_;
  const double k = static_cast<double>(dof);
  const double a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + z * std::sqrt(a);
  return k * c * c * c;
}

std::string ConsistencyTest::describe(double alpha) const {
  std::ostringstream os;
  os << "postfit chi-square " << fixedDecimals(statistic, 1) << (consistent() ? " <= " : " > ") << fixedDecimals(threshold, 1) << " ("
     << dof << " measurements; false alarm " << alpha << ")";
  return os.str();
}

ConsistencyTest postfitConsistency(const std::vector<PostfitResidualPair>& pairs, double alpha) {
  return postfitConsistency(pairs, ChiSquareUpperQuantile(alpha));
}

ConsistencyTest postfitConsistency(const std::vector<PostfitResidualPair>& pairs,
                                   const ChiSquareUpperQuantile& quantile) {
  ConsistencyTest t;
  for (const auto& p : pairs) {
    const double c = p.code_m / p.code_sigma_m, f = p.phase_m / p.phase_sigma_m;
    t.statistic += c * c + f * f;
  }
  t.dof = 2 * static_cast<int>(pairs.size());
  t.threshold = quantile(t.dof);
  return t;
}

}  // namespace ppp
