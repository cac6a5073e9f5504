#pragma once
// Satellite biases of integer-recovery clocks (CNES/CLS GRG convention): the
// clock file's header lists one wide-lane fractional bias per satellite in
// COMMENT lines ("WL G01 yyyy mm dd hh mi ss.ssssss  1   +x.xxxxxxE-01 ..."),
// in wide-lane cycles. The ionosphere-free clocks themselves carry the
// narrow-lane bias, so the ionosphere-free ambiguity is an integer combination
// once the wide lane is corrected (Laurichesse et al. 2009, "Integer ambiguity
// resolution on undifferenced GPS phase measurements and its application to PPP
// and satellite precise orbit determination", Navigation 56(2)).
//
// To serve that through the phase-OSB interface of BiasProvider, the wide-lane
// bias w [cycles] is split into L1/L2 phase biases b1, b2 [m] whose
// ionosphere-free combination is zero (f1^2 b1 = f2^2 b2: the clocks already
// hold it) and whose Melbourne-Wuebbena phase part (f1 b1 - f2 b2)/(f1 - f2) is
// sign * w * lambda_wl. The code biases are zero for the clocks' reference codes
// and absent for the others.
//
// The frequency pair and reference codes per system (the GRG header names the
// pair in the last field of each line: "0102" GPS L1/L2, "0105" Galileo E1/E5a):
//   GPS      L1/L2   codes C1W/C2W (P1/P2; "SYS / DCBS APPLIED" P1C1)
//   Galileo  E1/E5a  codes C1C/C5Q (or the combined C1X/C5X)
// A line whose pair differs from its system's (e.g. Galileo E1/E5b), that is not
// "WL sat date count value", or whose value is beyond 5 wide-lane cycles
// (io/bias_bounds.h) is reported as a problem with its file line and not used.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/models/bias_provider.h"

namespace ppp {

/// The signals a system's integer-recovery clock wide-lane bias refers to.
struct ClockWideLaneSignals {
  GnssSystem system = GnssSystem::GPS;
  char band1 = '1', band2 = '2';
  std::string code_attributes1, code_attributes2;  // the clocks' reference codes
  std::string header_pair;                         // the header's frequency field, e.g. "0102"
};
/// The table above; nullopt for a system without integer-recovery wide lanes here.
std::optional<ClockWideLaneSignals> clockWideLaneSignals(GnssSystem system);

struct ClockWideLaneBiases {
  std::map<SatelliteId, double> wide_lane_cycles;
  std::vector<std::string> problems;  // refused WL comment lines, with the line
  std::size_t lines = 0;              // "WL " comment lines read
  std::size_t refused = 0;            // of them, refused
};

/// Reads the "WL Xnn ..." comments of a clock header (comments as stored by the
/// RINEX clock reader, trimmed, without the "COMMENT" label; `lines` their file
/// lines, RinexClockHeader::comment_lines: problems name them, else the comment's index).
ClockWideLaneBiases parseClockWideLaneBiases(const std::vector<std::string>& comments,
                                             const std::vector<std::size_t>& lines = {});

class ClockWideLaneBiasProvider : public BiasProvider {
 public:
  /// `sign` is how the header value enters the Melbourne-Wuebbena (N1 - N2)
  /// correction: corrected MW = observed MW - sign * w. GRG: sign -1 (the value is
  /// added). Measured on ESBC 2020-177, single-difference MW means of 86 arcs
  /// over the day: |fraction| < 0.1 cycle for 68 with -1, 12 with +1 and 20
  /// without the biases (test_wide_lane_ambiguity, RealEsbc...).
  ClockWideLaneBiasProvider(std::map<SatelliteId, double> wide_lane_cycles, std::string source, double sign = -1.0)
      : wide_lane_cycles_(std::move(wide_lane_cycles)), source_(std::move(source)), sign_(sign) {}
  BiasAnswer codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  BiasAnswer phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  std::string describeSource() const override { return source_ + " (wide-lane biases of integer-recovery clocks)"; }
  std::size_t size() const { return wide_lane_cycles_.size(); }

 private:
  std::map<SatelliteId, double> wide_lane_cycles_;
  std::string source_;
  double sign_ = -1.0;
};

/// The wide-lane satellite biases of integer-recovery clock headers.
struct IntegerRecoveryClockBiases {
  std::shared_ptr<const ClockWideLaneBiasProvider> provider;  // nullptr unless every clock file lists usable ones
  std::vector<std::string> problems;  // "<file>: line <n> (comment \"...\"): <why>"
  std::size_t lines = 0, refused = 0;  // WL comment lines read and refused, over the files
  /// Why there is no provider although the headers hold WL lines ("" otherwise):
  /// "all 66 wide-lane lines of the clock header refused (first: ...)".
  std::string whyNone() const;
};
/// Reads them from `headers` (read from `clock_files`, in order; GRG sign).
IntegerRecoveryClockBiases readIntegerRecoveryClockBiases(const std::vector<RinexClockHeader>& headers,
                                                          const std::vector<std::string>& clock_files);

/// The provider of readIntegerRecoveryClockBiases; its problems go to `problems`.
std::shared_ptr<const ClockWideLaneBiasProvider> integerRecoveryClockBiases(
    const std::vector<RinexClockHeader>& headers, const std::vector<std::string>& clock_files,
    std::vector<std::string>& problems);

}  // namespace ppp
