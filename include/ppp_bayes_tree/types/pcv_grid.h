#pragma once
// PcvGrid: the phase-centre-variation table of one antenna and one frequency,
// as defined by ANTEX 1.4 (IGS, Rothacher & Schmid): values on a regular grid of
// zenith (receiver) or nadir (satellite) angles ZEN1..ZEN2 step DZEN, either
// azimuth-independent (the NOAZI row) or on azimuths 0..360 step DAZI.
//
// Interpolation (our convention, documented here):
//  - NOAZI only (DAZI = 0): linear in the zenith/nadir angle.
//  - Azimuth-dependent (DAZI > 0): bilinear in (azimuth, zenith); the azimuth
//    wraps at 360 deg (the 360 row equals the 0 row in valid files). The NOAZI
//    row is then not used (ANTEX 1.4: it is the azimuth mean).
//  - Angles outside [ZEN1, ZEN2] are REFUSED (std::nullopt), never clamped, so
//    that a caller cannot silently use an extrapolated value; non-finite input
//    is refused as well.
#include <cstddef>
#include <optional>
#include <vector>

namespace ppp {

struct PcvGrid {
  /// Grid limits in degrees, exactly as written in the ANTEX block.
  double zenith_first_deg = 0.0;  // ZEN1
  double zenith_last_deg = 0.0;   // ZEN2
  double zenith_step_deg = 0.0;   // DZEN (> 0)
  double azimuth_step_deg = 0.0;  // DAZI (0: no azimuth dependence)

  /// NOAZI row, one value per zenith node [m].
  std::vector<double> noazi_m;
  /// Azimuth rows 0, DAZI, ..., 360 deg (row-major: azimuth row, then zenith
  /// node) [m]; empty when azimuth_step_deg == 0.
  std::vector<double> azimuth_m;

  std::size_t zenithCount() const { return noazi_m.size(); }
  std::size_t azimuthRowCount() const;
  bool azimuthDependent() const { return azimuth_step_deg > 0.0 && !azimuth_m.empty(); }

  /// Value at one azimuth row / zenith node [m] (no bounds check beyond assert).
  double node_m(std::size_t azimuth_row, std::size_t zenith_node) const {
    return azimuth_m[azimuth_row * zenithCount() + zenith_node];
  }

  /// Phase-centre variation [m] at a zenith (receiver) / nadir (satellite)
  /// angle and an azimuth, both in radians. nullopt when the angle lies outside
  /// the grid or an input is not finite (see the file comment).
  std::optional<double> evaluate_m(double zenith_rad, double azimuth_rad) const;
  /// Same, using only the NOAZI row (linear in zenith).
  std::optional<double> evaluateNoAzimuth_m(double zenith_rad) const;
};

}  // namespace ppp
