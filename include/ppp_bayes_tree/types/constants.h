#pragma once
// Physical and geodetic constants with their sources.
namespace ppp {

/// Speed of light in vacuum [m/s] (IS-GPS-200, 20.3.4.3; exact by SI definition).
constexpr double kSpeedOfLight_mps = 299792458.0;
/// Earth rotation rate [rad/s] (WGS 84 / IS-GPS-200 value).
constexpr double kEarthRotationRate_radps = 7.2921151467e-5;
/// Earth gravitational constant GM [m^3/s^2] (WGS 84, IS-GPS-200 20.3.3.4.3).
constexpr double kGmGps_m3ps2 = 3.986005e14;
/// Galileo GM [m^3/s^2] (Galileo OS SIS ICD 2.1, 5.1.1).
constexpr double kGmGalileo_m3ps2 = 3.986004418e14;
/// Relativistic clock constant F = -2 sqrt(GM)/c^2 [s/sqrt(m)] (IS-GPS-200, 20.3.3.3.3.1).
constexpr double kRelativisticF_GPS = -4.442807633e-10;
/// Galileo value of F (Galileo OS SIS ICD 2.1, 5.1.4).
constexpr double kRelativisticF_Galileo = -4.442807309e-10;
/// WGS 84 semi-major axis [m] and flattening (NIMA TR8350.2).
constexpr double kWgs84SemiMajorAxis_m = 6378137.0;
constexpr double kWgs84Flattening = 1.0 / 298.257223563;
constexpr double kPi = 3.1415926535897932;
/// The value of pi the navigation message ICDs define for the semicircle
/// conversion (IS-GPS-200 20.3.3.4.3; Galileo OS SIS ICD 5.1.1; BDS-SIS-ICD-B1I
/// 5.2.4.1), used where broadcast words are decoded or encoded bit for bit.
constexpr double kIcdPi = 3.1415926535898;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

}  // namespace ppp
