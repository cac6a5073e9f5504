#pragma once
// Ocean tide loading coefficients of one station, as given by a BLQ file
// (Onsala Space Observatory ocean loading service, H.-G. Scherneck; format as
// in the IERS Conventions 2010 sec. 7.1.2): for each of the 11 main
// constituents, amplitudes [m] and Greenwich phase lags [deg] of the radial
// (up), west and south displacement.
#include <array>
#include <cstddef>

namespace ppp {

/// Number of constituents in a BLQ record.
constexpr std::size_t kOceanLoadingConstituents = 11;

/// Order of the constituents in a BLQ record and in OceanLoadingCoefficients.
enum class TidalConstituent : std::size_t { M2 = 0, S2, N2, K2, K1, O1, P1, Q1, Mf, Mm, Ssa };

/// Names in BLQ order: "M2", "S2", "N2", "K2", "K1", "O1", "P1", "Q1", "MF", "MM", "SSA".
constexpr std::array<const char*, kOceanLoadingConstituents> kTidalConstituentNames = {
    "M2", "S2", "N2", "K2", "K1", "O1", "P1", "Q1", "MF", "MM", "SSA"};

/// BLQ coefficients: amplitudes in metres, phase lags in degrees (positive lag:
/// displacement = A cos(chi(t) - phase)), directions radial-up, west, south as in
/// the file. Index with static_cast<std::size_t>(TidalConstituent::...).
struct OceanLoadingCoefficients {
  std::array<double, kOceanLoadingConstituents> amplitude_radial_m{};
  std::array<double, kOceanLoadingConstituents> amplitude_west_m{};
  std::array<double, kOceanLoadingConstituents> amplitude_south_m{};
  std::array<double, kOceanLoadingConstituents> phase_radial_deg{};
  std::array<double, kOceanLoadingConstituents> phase_west_deg{};
  std::array<double, kOceanLoadingConstituents> phase_south_deg{};
};

}  // namespace ppp
