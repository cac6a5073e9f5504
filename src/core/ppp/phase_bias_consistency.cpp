#include "ppp_bayes_tree/ppp/phase_bias_consistency.h"

#include <cctype>

namespace ppp {

std::optional<std::string> analysisCentreOfProductFile(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  // AAA V PPP TTT _ : centre (3 alphanumerics), version digit, project, type.
  if (name.size() < 11 || name[10] != '_') return std::nullopt;
  for (int i = 0; i < 10; ++i) {
    const unsigned char c = static_cast<unsigned char>(name[static_cast<std::size_t>(i)]);
    if (!(std::isupper(c) || std::isdigit(c))) return std::nullopt;
  }
  if (!std::isdigit(static_cast<unsigned char>(name[3]))) return std::nullopt;
  return name.substr(0, 3);
}

std::string PhaseBiasCheck::text() const {
  switch (verdict) {
    case PhaseBiasConsistency::Consistent:
      return "phase biases consistent with the clocks (" + clock_centre + ")";
    case PhaseBiasConsistency::NoBiasProduct: return "no consistent phase biases: float (no bias product)";
    case PhaseBiasConsistency::NoPhaseBiases:
      return "no consistent phase biases: float (the bias product holds no phase OSB)";
    case PhaseBiasConsistency::UnknownAnalysisCentre:
      return "no consistent phase biases: float (the analysis centre of a product is not known from its name)";
    case PhaseBiasConsistency::DifferentAnalysisCentres:
      return "no consistent phase biases: float (clocks " + clock_centre + ", biases " + bias_centre + ")";
  }
  return "unknown";
}

PhaseBiasCheck checkPhaseBiasConsistency(const std::vector<std::string>& clock_files,
                                         const std::optional<std::string>& bias_file,
                                         bool bias_file_has_phase_osb) {
  PhaseBiasCheck out;
  if (!bias_file) return out;
  if (!bias_file_has_phase_osb) {
    out.verdict = PhaseBiasConsistency::NoPhaseBiases;
    return out;
  }
  const auto bias_centre = analysisCentreOfProductFile(*bias_file);
  std::optional<std::string> clock_centre;
  bool mixed = false;
  for (const auto& f : clock_files) {
    const auto c = analysisCentreOfProductFile(f);
    if (!c) {
      out.verdict = PhaseBiasConsistency::UnknownAnalysisCentre;
      return out;
    }
    if (clock_centre && *clock_centre != *c) mixed = true;
    clock_centre = c;
  }
  if (!bias_centre || !clock_centre) {
    out.verdict = PhaseBiasConsistency::UnknownAnalysisCentre;
    return out;
  }
  out.bias_centre = *bias_centre;
  out.clock_centre = mixed ? std::string("mixed") : *clock_centre;
  out.verdict = (!mixed && *clock_centre == *bias_centre) ? PhaseBiasConsistency::Consistent
                                                          : PhaseBiasConsistency::DifferentAnalysisCentres;
  return out;
}

}  // namespace ppp
