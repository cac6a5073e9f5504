#pragma once
// Broadcast navigation records as decoded from RINEX navigation files: the
// Keplerian ephemerides of GPS LNAV / QZSS LNAV and Galileo I/NAV / F/NAV, and the
// GLONASS FDMA state-vector ephemeris. Values are kept in SI units (metres,
// seconds, radians); every instant is GPS time (see gnss_time.h).
//
// Field meanings follow RINEX 3.05 (appendix tables A6 GPS, A8 Galileo, A10
// GLONASS, A12 QZSS) and the ICDs cited there.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// Satellite clock polynomial of a broadcast record (IS-GPS-200 20.3.3.3.3.1;
/// Galileo OS SIS ICD 5.1.3): dt = af0 + af1 (t - toc) + af2 (t - toc)^2.
struct ClockPolynomial {
  GnssTime toc;           // clock reference epoch (GPST)
  double af0_s = 0.0;     // bias
  double af1_sps = 0.0;   // drift [s/s]
  double af2_sps2 = 0.0;  // drift rate [s/s^2]
};

/// The sixteen quasi-Keplerian orbit parameters of IS-GPS-200 table 20-III,
/// shared by GPS, QZSS and Galileo.
struct KeplerOrbit {
  GnssTime toe;                  // ephemeris reference epoch (GPST)
  double toe_sow = 0.0;          // toe as seconds of the (GPS/GST) week, as broadcast
  double sqrt_a_sqrtm = 0.0;     // square root of the semi-major axis [m^0.5]
  double eccentricity = 0.0;     // [0, 1)
  double i0_rad = 0.0;           // inclination at toe
  double omega0_rad = 0.0;       // longitude of ascending node at the weekly epoch
  double omega_rad = 0.0;        // argument of perigee
  double m0_rad = 0.0;           // mean anomaly at toe
  double delta_n_radps = 0.0;    // mean motion difference
  double idot_radps = 0.0;       // rate of inclination
  double omega_dot_radps = 0.0;  // rate of right ascension
  double cuc_rad = 0.0, cus_rad = 0.0;  // argument of latitude harmonic corrections
  double crc_m = 0.0, crs_m = 0.0;      // orbit radius harmonic corrections
  double cic_rad = 0.0, cis_rad = 0.0;  // inclination harmonic corrections
};

/// GPS LNAV record (RINEX 3.05 table A6); also QZSS LNAV (table A12), which uses
/// the same layout and the GPS constants (IS-QZSS-PNT 5.5).
struct GpsLnavEphemeris {
  SatelliteId satellite;
  ClockPolynomial clock;
  KeplerOrbit orbit;
  int iode = 0;
  int iodc = 0;
  int week = 0;                  // continuous GPS week of toe, as written
  int health = 0;                // SV health bits (0 = all signals OK)
  double ura_m = 0.0;            // SV accuracy
  double tgd_s = 0.0;            // L1/L2 group delay TGD (IS-GPS-200 20.3.3.3.3.2)
  double fit_interval_h = 4.0;   // curve-fit interval (4 h when the file says 0 / blank)
  std::optional<double> transmission_sow;  // transmission time of message
  int codes_on_l2 = 0;
  int l2p_data_flag = 0;
};

enum class GalileoNavType { INav, FNav };

/// Galileo I/NAV or F/NAV record (RINEX 3.05 table A8).
struct GalileoEphemeris {
  SatelliteId satellite;
  GalileoNavType type = GalileoNavType::INav;
  ClockPolynomial clock;
  KeplerOrbit orbit;
  int iod_nav = 0;
  int data_sources = 0;   // RINEX bit field: 0 I/NAV E1-B, 1 F/NAV E5a-I, 2 I/NAV E5b-I,
                          // 8 clock for E5a/E1, 9 clock for E5b/E1
  int week = 0;           // GAL week of toe as written (RINEX: aligned with the GPS week)
  int health = 0;         // SV health bits: 0 E1B DVS, 1-2 E1B HS, 3 E5a DVS, 4-5 E5a HS,
                          // 6 E5b DVS, 7-8 E5b HS
  std::optional<double> sisa_m;          // signal-in-space accuracy; nullopt for "NAPA" (-1)
  double bgd_e5a_e1_s = 0.0;             // broadcast group delay E1/E5a
  std::optional<double> bgd_e5b_e1_s;    // E1/E5b (I/NAV only; blank in F/NAV files)
  std::optional<double> transmission_sow;
};

/// GLONASS FDMA record (RINEX 3.05 table A10; ICD GLONASS 5.1 section 4.4):
/// PZ-90 state vector at tb plus lunisolar acceleration and clock terms.
struct GlonassEphemeris {
  SatelliteId satellite;
  GnssTime tb;                    // reference epoch (the RINEX toc, given in UTC), as GPST
  double minus_tau_n_s = 0.0;     // -TauN: clock bias as written in RINEX
  double gamma_n = 0.0;           // relative frequency bias +GammaN [s/s]
  double message_frame_time_s = 0.0;  // tk as written (seconds of UTC week / day)
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();          // PZ-90, at tb
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_mps2 = Eigen::Vector3d::Zero();   // lunisolar, constant
  int health = 0;                 // Bn MSB: 0 = healthy
  int frequency_channel = 0;      // FDMA k, -7..+13
  double age_days = 0.0;          // age of operational information E
};

/// Why an orbit cannot be used (non-finite, e outside [0,1), A implausible), or nullopt.
std::optional<std::string> checkKeplerOrbit(const KeplerOrbit& orbit);
/// Same for a GLONASS state vector (non-finite, radius below 6400 km or above 100000 km).
std::optional<std::string> checkGlonassState(const GlonassEphemeris& eph);

/// The record's transmission time of message (RINEX 3.05 A6/A8) as an instant: its
/// seconds of week placed within half a week of toe; nullopt when the file gives none.
std::optional<GnssTime> transmissionTime(const GpsLnavEphemeris& eph);
std::optional<GnssTime> transmissionTime(const GalileoEphemeris& eph);
/// GLONASS: the message frame time tk (RINEX 3.05 A10: seconds of the UTC week, or of
/// the UTC day in some files) as the GPST instant nearest tb.
GnssTime transmissionTime(const GlonassEphemeris& eph);

}  // namespace ppp
