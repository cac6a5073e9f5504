#pragma once
// Whether the phase biases of a product set are consistent with its clocks, so
// that ionosphere-free (narrow-lane) ambiguities can be fixed to integers.
//
// Satellite phase OSBs are only meaningful together with the clocks they were
// estimated with: the ionosphere-free clock of an analysis centre absorbs its
// own narrow-lane phase biases. A bias file from one centre (e.g. CODE) with
// clocks of another (e.g. the IGS combination, whose combined clocks hold no
// integer property) leaves a fractional narrow-lane bias per satellite that
// fixing would turn into wrong integers. The wide lane (Melbourne-Wuebbena) is
// clock free and is not affected.
//
// Decision by the products (no statistics): the analysis centre of every clock
// file and of the bias file, taken from the IGS long product names
// (AAAVPPPTTT_..., Gurtner/Romero, "IGS long product filenames" 2017: the first
// three characters name the centre), must agree, and the bias file must hold
// phase OSBs. Names that are not IGS long names are not trusted (float).
#include <optional>
#include <string>
#include <vector>

namespace ppp {

enum class PhaseBiasConsistency {
  Consistent,
  NoBiasProduct,              // no bias file
  NoPhaseBiases,              // the bias file has no phase OSB
  UnknownAnalysisCentre,      // a file name is not an IGS long product name
  DifferentAnalysisCentres,   // clocks and biases from different centres
};

struct PhaseBiasCheck {
  PhaseBiasConsistency verdict = PhaseBiasConsistency::NoBiasProduct;
  std::string clock_centre;  // e.g. "WUM"; empty when unknown or mixed
  std::string bias_centre;
  bool consistent() const { return verdict == PhaseBiasConsistency::Consistent; }
  /// "phase biases consistent with the clocks (WUM)" or
  /// "no consistent phase biases: float (clocks IGS, biases COD)".
  std::string text() const;
};

/// The analysis centre of an IGS long product file name (path allowed), e.g.
/// "WUM" for ".../WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"; nullopt otherwise.
std::optional<std::string> analysisCentreOfProductFile(const std::string& path);

PhaseBiasCheck checkPhaseBiasConsistency(const std::vector<std::string>& clock_files,
                                         const std::optional<std::string>& bias_file,
                                         bool bias_file_has_phase_osb);

}  // namespace ppp
