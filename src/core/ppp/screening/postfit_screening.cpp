#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/types/number_text.h"

namespace ppp {

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
