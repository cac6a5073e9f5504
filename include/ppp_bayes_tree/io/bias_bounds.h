#pragma once
// Plausibility bounds on the inputs of ambiguity resolution: satellite and station
// biases (Bias-SINEX rows, SSR code and phase biases) and the wide-lane satellite
// biases of integer-recovery clock headers. A value beyond its bound is refused
// (reported with its file and line, or its stream frame, and not used): such a
// value is a corrupt file or stream, and fixing on it makes wrong integers.
//
// The bounds, with the largest magnitudes of the real products they were set on:
//   phase bias   |b| <= 100 ns (~30 m). Phase OSBs absorb no code hardware delay:
//                WUM 2021-210 ABS.BIA: at most 7.3 ns (C16 L6I), GPS/Galileo 3.3 ns;
//                CODE 2026-133 OSB.BIA: at most 1.8 ns. 100 ns leaves a factor 13.
//                (RTCM 1265-1270 DF482 and IGS-SSR IDF023 reach +-52.4 m: the fields
//                allow what the bound refuses.)
//   code bias    |b| <= 1000 ns (~300 m). Satellite code OSBs: WUM at most 149 ns
//                (C60 C6I), CODE 25 ns; station rows: CODE at most 480 ns (Galileo
//                C1X receiver bias). 1000 ns leaves a factor 2 over every real row.
//   (rows in cycles: the ns bound at the highest GNSS carrier, 1.6 GHz: phase 160,
//    code 1600 cycles.)
//   wide-lane satellite bias (integer-recovery clock header "WL" lines)
//                |w| <= 5 wide-lane cycles. A satellite's wide-lane bias is defined
//                up to whole cycles; GRG publishes it unreduced: ESBC 2020-177 GPS
//                -2.04 ... +0.45, Galileo -0.44 ... +0.45 cycles. 5 cycles is twice
//                the largest published value.
#include <optional>
#include <string>

namespace ppp {

enum class BiasKind { Code, Phase };

struct BiasBounds {
  double phase_ns = 100.0;
  double code_ns = 1000.0;
  double highest_carrier_hz = 1.6e9;  // converts the ns bounds to cycles
  double wide_lane_cycles = 5.0;
};
inline const BiasBounds& biasBounds() {
  static const BiasBounds kBounds;
  return kBounds;
}

/// Why `value` (in ns, or in cycles when `in_cycles`) of a bias of `kind` is refused;
/// nullopt when within the bound. E.g. "phase bias 1000000 ns beyond the bound of 100 ns".
std::optional<std::string> biasBeyondBound(BiasKind kind, double value, bool in_cycles);
/// The same for a bias in metres (SSR): the ns bound times c.
std::optional<std::string> biasBeyondBound_m(BiasKind kind, double value_m);
/// The same for a wide-lane satellite bias in wide-lane cycles.
std::optional<std::string> wideLaneBiasBeyondBound(double value_cycles);

}  // namespace ppp
