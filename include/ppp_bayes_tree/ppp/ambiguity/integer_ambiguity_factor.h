#pragma once
// IntegerAmbiguityFactor: one fixed narrow-lane ambiguity of the PPP graph
// (ppp_factors.h) as a tight factor on the IF phase biases it involves.
//
// The ambiguity resolver (ambiguity_resolution.h) fixes the between-satellite
// single differences dN1_s = (B_s - B_ref - o_s) / lambda_NL of the float IF
// biases B [m] (o_s holds the satellite phase OSBs and the fixed wide lane),
// or, with partial fixing, integer combinations of them (rows of the LAMBDA
// decorrelation, Teunissen 1995). Each accepted constraint is linear in the
// biases:
//     sum_j a_j B_j = y          (a_j [1/m], y [cycles])
// and enters the graph as this factor, error = sum_j a_j B_j - y [cycles] with
// a tight sigma (fixed_ambiguity_sigma_cycles, 1e-3 cycle = 0.1 mm on the IF
// bias): iSAM2 then carries the fix into every state the arcs' phase factors
// touch, before the fix epoch too (the smoothed trajectory improves backwards),
// which a filter cannot do. The factor is affine in every bias (constant
// coefficients), so it never triggers a relinearization. A plain single
// difference has two keys (a_s = 1/lambda_NL, a_ref = -1/lambda_NL); a partial
// fix's decorrelated combination has more.
#include <vector>

#include "ppp_bayes_tree/smoother/nonlinear_factor.h"

namespace ppp {

class IntegerAmbiguityFactor : public smoother::NonlinearFactor {
 public:
  /// `biases` (scalar bias keys) and `coefficients_per_m` of the same size; the
  /// integer value `value_cycles` (already including the offsets, see top).
  IntegerAmbiguityFactor(smoother::KeyVector biases, std::vector<double> coefficients_per_m, double value_cycles,
                         double sigma_cycles);

  smoother::Vector unwhitenedError(const smoother::Values& x, std::vector<smoother::Matrix>* jacobians) const override;
  bool affineIn(smoother::Key) const override { return true; }

  const std::vector<double>& coefficients_per_m() const { return coefficients_per_m_; }
  double value_cycles() const { return value_cycles_; }
  double sigma_cycles() const { return sigma_cycles_; }

 private:
  std::vector<double> coefficients_per_m_;
  double value_cycles_;
  double sigma_cycles_;
};

}  // namespace ppp
