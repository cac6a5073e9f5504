#pragma once
// OceanLoadingCoefficients: the ocean tide loading displacement of one station
// for the 11 main tidal constituents, as tabulated in the BLQ format of the
// Onsala ocean loading service (H.-G. Scherneck) and used by IERS Conventions
// (2010), section 7.1.2: amplitudes [m] and Greenwich phase lags [deg] of the
// radial (up), west and south displacement (displacement = A cos(chi(t) - phase)).
#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace ppp {

/// Number of constituents in a BLQ record.
constexpr std::size_t kOceanLoadingConstituents = 11;

/// Order of the constituents in a BLQ record and in OceanLoadingCoefficients.
enum class TidalConstituent : std::size_t { M2 = 0, S2, N2, K2, K1, O1, P1, Q1, Mf, Mm, Ssa };

/// Names in BLQ column order (the order of every array below).
constexpr std::array<const char*, kOceanLoadingConstituents> kTidalConstituentNames = {
    "M2", "S2", "N2", "K2", "K1", "O1", "P1", "Q1", "MF", "MM", "SSA"};

struct OceanLoadingCoefficients {
  static constexpr std::size_t kConstituentCount = kOceanLoadingConstituents;

  std::string station;  // as written on the station line (first word)
  // Index with static_cast<std::size_t>(TidalConstituent::...).
  std::array<double, kConstituentCount> amplitude_radial_m{};
  std::array<double, kConstituentCount> amplitude_west_m{};
  std::array<double, kConstituentCount> amplitude_south_m{};
  std::array<double, kConstituentCount> phase_radial_deg{};  // Greenwich phase lag
  std::array<double, kConstituentCount> phase_west_deg{};
  std::array<double, kConstituentCount> phase_south_deg{};
  /// Station coordinates from the "$$ ... lon/lat:" comment when present.
  std::optional<double> longitude_deg;
  std::optional<double> latitude_deg;
  std::size_t line = 0;  // line of the station name
};

}  // namespace ppp
