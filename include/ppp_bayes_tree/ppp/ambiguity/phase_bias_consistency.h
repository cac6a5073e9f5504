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
// file and of the bias file must agree, and the bias file must hold phase OSBs.
// The centres come from the files' headers when every file names one: a clock
// file's "ANALYSIS CENTER" (A3), else the agency of its "PGM / RUN BY / DATE";
// a Bias-SINEX file's agency on its first line ("%=BIA 1.00 WHU ..."). Otherwise
// from the IGS long product names (AAAVPPPTTT_..., Gurtner/Romero, "IGS long
// product filenames" 2017: the first three characters name the centre). Names
// that are neither are not trusted (float).
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

/// A product file and the analysis centre its header names ("" when none).
struct ProductOrigin {
  std::string file;  // path or name
  std::string header_centre;
};

struct PhaseBiasCheck {
  PhaseBiasConsistency verdict = PhaseBiasConsistency::NoBiasProduct;
  std::string clock_centre;  // e.g. "WUM"; empty when unknown or mixed
  std::string bias_centre;
  bool from_headers = false;  // the centres are the headers' (else the file names')
  bool consistent() const { return verdict == PhaseBiasConsistency::Consistent; }
  /// The specifics: "clocks IGS, biases COD", "no bias product", ...
  std::string why() const;
  /// "phase biases consistent with the clocks (WUM)" or
  /// "no consistent phase biases: float (clocks IGS, biases COD)".
  std::string text() const;
};

/// The analysis centre of an IGS long product file name (path allowed), e.g.
/// "WUM" for ".../WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"; nullopt otherwise.
std::optional<std::string> analysisCentreOfProductFile(const std::string& path);

/// The analysis centre a RINEX clock header names: its "ANALYSIS CENTER" id, else
/// the first word of the agency in "PGM / RUN BY / DATE", upper case; "" for none.
struct RinexClockHeader;
std::string clockHeaderCentre(const RinexClockHeader& header);

/// By file names only (IGS long product names).
PhaseBiasCheck checkPhaseBiasConsistency(const std::vector<std::string>& clock_files,
                                         const std::optional<std::string>& bias_file,
                                         bool bias_file_has_phase_osb);
/// By the centres the headers name when every file names one, else by file names.
PhaseBiasCheck checkPhaseBiasConsistency(const std::vector<ProductOrigin>& clocks,
                                         const std::optional<ProductOrigin>& bias, bool bias_file_has_phase_osb);

}  // namespace ppp
