#include "ppp_bayes_tree/ppp/ambiguity/phase_bias_consistency.h"

#include <cctype>
#include <sstream>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"

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

std::string PhaseBiasCheck::why() const {
  switch (verdict) {
    case PhaseBiasConsistency::Consistent: return clock_centre;
    case PhaseBiasConsistency::NoBiasProduct: return "no bias product";
    case PhaseBiasConsistency::NoPhaseBiases: return "the bias product holds no phase OSB";
    case PhaseBiasConsistency::UnknownAnalysisCentre:
      return "the analysis centre of a product is not known from its header or name";
    case PhaseBiasConsistency::DifferentAnalysisCentres:
      return "clocks " + clock_centre + ", biases " + bias_centre;
  }
  return "unknown";
}

std::string PhaseBiasCheck::text() const {
  if (consistent())
    return "phase biases consistent with the clocks (" + clock_centre +
           (from_headers ? ", from the headers)" : ", from the file names)");
  return "no consistent phase biases: float (" + why() + ")";
}

std::string clockHeaderCentre(const RinexClockHeader& header) {
  std::string word;
  std::istringstream(header.analysis_center_id.empty() ? header.run_by : header.analysis_center_id) >> word;
  for (auto& c : word) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return word;
}

PhaseBiasCheck checkPhaseBiasConsistency(const std::vector<std::string>& clock_files,
                                         const std::optional<std::string>& bias_file,
                                         bool bias_file_has_phase_osb) {
  std::vector<ProductOrigin> clocks;
  for (const auto& f : clock_files) clocks.push_back({f, ""});
  std::optional<ProductOrigin> bias;
  if (bias_file) bias = ProductOrigin{*bias_file, ""};
  return checkPhaseBiasConsistency(clocks, bias, bias_file_has_phase_osb);
}

PhaseBiasCheck checkPhaseBiasConsistency(const std::vector<ProductOrigin>& clocks,
                                         const std::optional<ProductOrigin>& bias, bool bias_file_has_phase_osb) {
  PhaseBiasCheck out;
  if (!bias) return out;
  if (!bias_file_has_phase_osb) {
    out.verdict = PhaseBiasConsistency::NoPhaseBiases;
    return out;
  }
  bool headers = !bias->header_centre.empty() && !clocks.empty();
  for (const auto& c : clocks) headers &= !c.header_centre.empty();
  const auto centreOf = [&](const ProductOrigin& p) -> std::optional<std::string> {
    if (headers) return p.header_centre;
    return analysisCentreOfProductFile(p.file);
  };
  out.from_headers = headers;
  const auto bias_centre = centreOf(*bias);
  std::optional<std::string> clock_centre;
  bool mixed = false;
  for (const auto& f : clocks) {
    const auto c = centreOf(f);
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
