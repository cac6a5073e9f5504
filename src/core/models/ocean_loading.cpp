#include "ppp_bayes_tree/models/ocean_loading.h"

#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

struct ConstituentArgument {
  double speed_radps;  ///< angular speed omega_k
  double h0, s0, p0;   ///< multipliers of the mean longitudes at 0 h UT
  double offset_cycles;
};

// Schwiderski (1980) / Onsala ARG conventions, BLQ order.
constexpr std::array<ConstituentArgument, kOceanLoadingConstituents> kArguments = {{
    {1.40519e-4, 2.0, -2.0, 0.0, 0.00},   // M2
    {1.45444e-4, 0.0, 0.0, 0.0, 0.00},    // S2
    {1.37880e-4, 2.0, -3.0, 1.0, 0.00},   // N2
    {1.45842e-4, 2.0, 0.0, 0.0, 0.00},    // K2
    {0.72921e-4, 1.0, 0.0, 0.0, 0.25},    // K1
    {0.67598e-4, 1.0, -2.0, 0.0, -0.25},  // O1
    {0.72523e-4, -1.0, 0.0, 0.0, -0.25},  // P1
    {0.64959e-4, 1.0, -3.0, 1.0, -0.25},  // Q1
    {0.53234e-5, 0.0, 2.0, 0.0, 0.00},    // Mf
    {0.26392e-5, 0.0, 1.0, -1.0, 0.00},   // Mm
    {0.03982e-5, 2.0, 0.0, 0.0, 0.00},    // Ssa
}};

double wrapTwoPi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  return a < 0.0 ? a + 2.0 * kPi : a;
}

}  // namespace

std::array<double, kOceanLoadingConstituents> oceanLoadingArguments_rad(const GnssTime& t) {
  const double mjd_utc = t.mjd(TimeSystem::UTC);
  const double mjd_day = std::floor(mjd_utc);
  const double seconds_of_day = (mjd_utc - mjd_day) * 86400.0;
  // Julian centuries from 1900 Jan 0.5 (MJD 15019.5) at 0 h UT; ARG's 1.000000035
  // factor kept for consistency with the BLQ generator.
  const double T = (mjd_day - 15019.5) * 1.000000035 / 36525.0;
  const double T2 = T * T, T3 = T2 * T;
  const double h0 = (279.69668 + 36000.768930485 * T + 3.03e-4 * T2) * kDegToRad;
  const double s0 = std::fmod(270.434358 + 481267.88314137 * T - 0.001133 * T2 + 1.9e-6 * T3, 360.0) * kDegToRad;
  const double p0 = (334.329653 + 4069.0340329577 * T - 0.010325 * T2 - 1.2e-5 * T3) * kDegToRad;
  std::array<double, kOceanLoadingConstituents> chi{};
  for (std::size_t k = 0; k < kOceanLoadingConstituents; ++k) {
    const ConstituentArgument& a = kArguments[k];
    chi[k] = wrapTwoPi(a.speed_radps * seconds_of_day + a.h0 * h0 + a.s0 * s0 + a.p0 * p0 +
                       2.0 * kPi * a.offset_cycles);
  }
  return chi;
}

Eigen::Vector3d oceanLoadingDisplacementEnu_m(const OceanLoadingCoefficients& c, const GnssTime& t) {
  const auto chi = oceanLoadingArguments_rad(t);
  double up = 0.0, west = 0.0, south = 0.0;
  for (std::size_t k = 0; k < kOceanLoadingConstituents; ++k) {
    up += c.amplitude_radial_m[k] * std::cos(chi[k] - c.phase_radial_deg[k] * kDegToRad);
    west += c.amplitude_west_m[k] * std::cos(chi[k] - c.phase_west_deg[k] * kDegToRad);
    south += c.amplitude_south_m[k] * std::cos(chi[k] - c.phase_south_deg[k] * kDegToRad);
  }
  return {-west, -south, up};
}

}  // namespace ppp
