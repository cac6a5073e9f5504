#pragma once
// Broadcast ephemeris models: satellite position, velocity and clock from a
// broadcast navigation record (pure functions).
//
//  - GPS LNAV / QZSS LNAV: IS-GPS-200 section 20.3.3.4.3, table 20-IV (user
//    algorithm for ephemeris determination), clock 20.3.3.3.3.1.
//  - Galileo I/NAV and F/NAV: Galileo OS SIS ICD (version 2.1) section 5.1.1
//    (table 59) with the Galileo GM, and 5.1.4 with the Galileo value of F.
//  - BeiDou D1/D2: BDS-SIS-ICD-B1I (version 2.0, 2013; 3.0, 2019) section
//    5.2.4.12, table 5-11 (user algorithm for ephemeris parameters), with the
//    CGCS2000 constants GM = 3.986004418e14 m^3/s^2 and Omega_e = 7.2921150e-5
//    rad/s (5.2.4.12 / 3.2). MEO and IGSO satellites as GPS. GEO satellites
//    (C01-C05, C59-C63): the node longitude omits the Earth rotation since toe,
//    the position so found is rotated by -5 deg about X and then by
//    Omega_e (t - toe) about Z: X = R_Z(Omega_e tk) R_X(-5 deg) X_GK. Times in
//    the record are GPST instants (BDT = GPST - 14 s); toe_sow is BDT seconds
//    of the BDT week, the epoch to which Omega0 refers. Clock: 5.2.4.10 with F
//    of the CGCS2000 GM; the broadcast clock refers to B3I (TGD1 B1I, TGD2 B2I).
//  - GLONASS FDMA: 4th-order Runge-Kutta integration of the PZ-90 equations of
//    motion of the GLONASS ICD (edition 5.1, appendix A.3.1.2), clock per 3.3.3.
//
// Time arguments are the GPST instant of signal transmission. Positions and
// velocities are Earth-fixed (WGS 84 / PZ-90.11 as broadcast, no transformation).
// The clock bias is that of the broadcast clock reference: for GPS the L1/L2
// ionosphere-free P(Y) combination (apply tgd for single-frequency L1, see
// gpsL1ClockCorrection_s), for Galileo I/NAV E1/E5b, for F/NAV E1/E5a.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

/// Satellite state from a broadcast record.
struct BroadcastState {
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();
  /// Satellite clock bias including the relativistic correction [s].
  double clock_bias_s = 0.0;
  /// Satellite clock drift including the relativistic correction's rate [s/s].
  double clock_drift_sps = 0.0;
  /// The relativistic (eccentricity) part of clock_bias_s, F e sqrt(A) sin(E) [s];
  /// 0 for GLONASS, whose broadcast clock includes it.
  double relativistic_s = 0.0;
};

/// Result of solving Kepler's equation M = E - e sin(E).
struct KeplerSolution {
  double eccentric_anomaly_rad = 0.0;
  int iterations = 0;
  bool converged = false;
};

/// Kepler's equation by Newton iteration to |dE| < 1e-14 rad, at most 30
/// iterations (converges in < 10 for any e < 1 from the start chosen; never
/// loops without bound). Non-finite input gives converged = false.
KeplerSolution solveKepler(double mean_anomaly_rad, double eccentricity);

/// Constants of one system's Keplerian user algorithm.
struct KeplerConstants {
  double gm_m3ps2;
  double earth_rotation_radps;
  double relativistic_f;  // F = -2 sqrt(GM) / c^2 [s/m^0.5]
};
KeplerConstants gpsKeplerConstants();      // IS-GPS-200 20.3.3.4.3 / 20.3.3.3.3.1
KeplerConstants galileoKeplerConstants();  // Galileo OS SIS ICD 5.1.1 / 5.1.4
KeplerConstants beidouKeplerConstants();   // BDS-SIS-ICD-B1I 5.2.4.10 / 5.2.4.12

/// Position, velocity and the relativistic term from a Keplerian orbit at GPST t
/// (clock fields: relativistic part only). Velocity is the analytic time
/// derivative of the table 20-IV equations. Preconditions (checked by
/// checkKeplerOrbit): finite elements, 0 <= e < 1, A above 6400 km.
BroadcastState keplerState(const KeplerOrbit& orbit, const KeplerConstants& constants,
                           const GnssTime& t);


/// af0 + af1 dt + af2 dt^2 with dt = t - toc [s].
double clockPolynomial_s(const ClockPolynomial& clock, const GnssTime& t);

/// Full states: position, velocity, clock bias = polynomial + relativistic term.
BroadcastState satelliteState(const GpsLnavEphemeris& eph, const GnssTime& t);
BroadcastState satelliteState(const GalileoEphemeris& eph, const GnssTime& t);
/// BeiDou: MEO/IGSO as keplerState with the BeiDou constants; GEO (eph.isGeo())
/// with the rotated algorithm of the header comment (velocity differentiated
/// through both rotations).
BroadcastState satelliteState(const BeidouEphemeris& eph, const GnssTime& t);
/// GLONASS: -TauN + GammaN (t - tb) and the integrated orbit. Integration takes
/// 60 s Runge-Kutta steps from tb to t; |t - tb| is limited by the caller
/// (the ephemeris store uses 15 min + margin).
BroadcastState satelliteState(const GlonassEphemeris& eph, const GnssTime& t);

/// GPS single-frequency L1 C/A (or P(Y)) user clock: the ionosphere-free clock
/// minus TGD (IS-GPS-200 20.3.3.3.3.2).
inline double gpsL1ClockCorrection_s(const GpsLnavEphemeris& eph, double clock_bias_s) {
  return clock_bias_s - eph.tgd_s;
}
/// GPS L2 P(Y) user clock: clock - gamma TGD, gamma = (77/60)^2 (IS-GPS-200 20.3.3.3.3.2).
inline double gpsL2ClockCorrection_s(const GpsLnavEphemeris& eph, double clock_bias_s) {
  return clock_bias_s - (77.0 / 60.0) * (77.0 / 60.0) * eph.tgd_s;
}
/// Galileo single-frequency E1 user clock: clock - BGD(E1,E5a) for F/NAV or
/// BGD(E1,E5b) for I/NAV (Galileo OS SIS ICD 5.1.5); nullopt when the needed BGD is absent.
std::optional<double> galileoE1ClockCorrection_s(const GalileoEphemeris& eph, double clock_bias_s);

/// True when the record's health bits mark the satellite usable for its message:
/// GPS health == 0; Galileo I/NAV: E1-B and E5b DVS/HS bits clear, F/NAV: E5a bits
/// clear (OS SIS ICD 5.1.9.3); GLONASS Bn == 0.
bool isHealthy(const GpsLnavEphemeris& eph);
bool isHealthy(const GalileoEphemeris& eph);
bool isHealthy(const GlonassEphemeris& eph);
/// BeiDou: SatH1 == 0 (BDS-SIS-ICD-B1I 5.2.4.6).
bool isHealthy(const BeidouEphemeris& eph);

}  // namespace ppp
