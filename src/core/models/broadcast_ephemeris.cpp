#include "ppp_bayes_tree/models/broadcast_ephemeris.h"

#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

namespace {

constexpr int kMaxKeplerIterations = 30;
constexpr double kKeplerTolerance_rad = 1e-14;

// GLONASS ICD edition 5.1, section 3.1.3 table 3.2 (PZ-90.11 constants).
constexpr double kGlonassGm_m3ps2 = 398600.4418e9;
constexpr double kGlonassSemiMajorAxis_m = 6378136.0;
constexpr double kGlonassJ2 = 1082625.75e-9;
constexpr double kGlonassEarthRotation_radps = 7.2921150e-5;
constexpr double kGlonassStep_s = 30.0;

// BDS-SIS-ICD-B1I 5.2.4.12: CGCS2000 Earth rotation rate and the GEO tilt (-5 deg about X).
constexpr double kBeidouEarthRotation_radps = 7.2921150e-5;
constexpr double kBeidouGeoTilt_rad = -5.0 * kPi / 180.0;

// Wraps an angle into [-pi, pi).
double wrapPi(double angle_rad) {
  double a = std::fmod(angle_rad + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

}  // namespace

KeplerSolution solveKepler(double mean_anomaly_rad, double eccentricity) {
  KeplerSolution s;
  if (!std::isfinite(mean_anomaly_rad) || !std::isfinite(eccentricity) || eccentricity < 0.0 ||
      eccentricity >= 1.0) {
    return s;
  }
  const double m = wrapPi(mean_anomaly_rad);
  // Starting at E = M for small e and at E = pi otherwise makes Newton's method
  // converge monotonically for every e < 1 (Danby, Fundamentals of Celestial
  // Mechanics, 6.6).
  double e_anom = eccentricity < 0.8 ? m : (m < 0 ? -kPi : kPi);
  for (int k = 1; k <= kMaxKeplerIterations; ++k) {
    const double f = e_anom - eccentricity * std::sin(e_anom) - m;
    const double step = f / (1.0 - eccentricity * std::cos(e_anom));
    e_anom -= step;
    s.iterations = k;
    if (std::fabs(step) < kKeplerTolerance_rad) {
      s.converged = true;
      break;
    }
  }
  // Return E consistent with the unwrapped mean anomaly (E - M is periodic).
  s.eccentric_anomaly_rad = e_anom + (mean_anomaly_rad - m);
  return s;
}

KeplerConstants gpsKeplerConstants() {
  return {kGmGps_m3ps2, kEarthRotationRate_radps, kRelativisticF_GPS};
}

KeplerConstants galileoKeplerConstants() {
  // Galileo OS SIS ICD 5.1.1: mu = 3.986004418e14, Omega_e = 7.2921151467e-5.
  return {kGmGalileo_m3ps2, 7.2921151467e-5, kRelativisticF_Galileo};
}

BroadcastState keplerState(const KeplerOrbit& o, const KeplerConstants& k, const GnssTime& t) {
  // IS-GPS-200 table 20-IV, step by step. tk = t - toe as an exact difference of
  // full GPST instants: no week-crossover ambiguity remains (the +-302400 s rule
  // of 20.3.3.4.3 is applied when toe is built from the broadcast seconds of week).
  const double tk = t - o.toe;
  const double a = o.sqrt_a_sqrtm * o.sqrt_a_sqrtm;
  const double n0 = std::sqrt(k.gm_m3ps2 / (a * a * a));
  const double n = n0 + o.delta_n_radps;
  const double mk = o.m0_rad + n * tk;
  const KeplerSolution kepler = solveKepler(mk, o.eccentricity);
  const double ek = kepler.eccentric_anomaly_rad;
  const double e = o.eccentricity;
  const double sin_e = std::sin(ek), cos_e = std::cos(ek);
  const double one_minus_ecos = 1.0 - e * cos_e;
  const double sqrt_1me2 = std::sqrt(1.0 - e * e);
  const double nu = std::atan2(sqrt_1me2 * sin_e, cos_e - e);
  const double phi = nu + o.omega_rad;
  const double s2 = std::sin(2.0 * phi), c2 = std::cos(2.0 * phi);
  const double du = o.cus_rad * s2 + o.cuc_rad * c2;
  const double dr = o.crs_m * s2 + o.crc_m * c2;
  const double di = o.cis_rad * s2 + o.cic_rad * c2;
  const double u = phi + du;
  const double r = a * one_minus_ecos + dr;
  const double inc = o.i0_rad + di + o.idot_radps * tk;
  const double xp = r * std::cos(u), yp = r * std::sin(u);
  const double node_rate = o.omega_dot_radps - k.earth_rotation_radps;
  const double node = o.omega0_rad + node_rate * tk - k.earth_rotation_radps * o.toe_sow;
  const double cn = std::cos(node), sn = std::sin(node);
  const double ci = std::cos(inc), si = std::sin(inc);

  BroadcastState s;
  s.position_ecef_m = {xp * cn - yp * ci * sn, xp * sn + yp * ci * cn, yp * si};

  // Time derivatives of the same expressions.
  const double e_dot = n / one_minus_ecos;
  const double nu_dot = e_dot * sqrt_1me2 / one_minus_ecos;
  const double u_dot = nu_dot * (1.0 + 2.0 * (o.cus_rad * c2 - o.cuc_rad * s2));
  const double r_dot = a * e * sin_e * e_dot + 2.0 * nu_dot * (o.crs_m * c2 - o.crc_m * s2);
  const double i_dot = o.idot_radps + 2.0 * nu_dot * (o.cis_rad * c2 - o.cic_rad * s2);
  const double xp_dot = r_dot * std::cos(u) - yp * u_dot;
  const double yp_dot = r_dot * std::sin(u) + xp * u_dot;
  const Eigen::Vector3d& p = s.position_ecef_m;
  s.velocity_ecef_mps = {xp_dot * cn - yp_dot * ci * sn + yp * si * sn * i_dot - p.y() * node_rate,
                         xp_dot * sn + yp_dot * ci * cn - yp * si * cn * i_dot + p.x() * node_rate,
                         yp_dot * si + yp * ci * i_dot};

  // Relativistic correction, IS-GPS-200 20.3.3.3.3.1: dtr = F e sqrt(A) sin(Ek).
  s.relativistic_s = k.relativistic_f * e * o.sqrt_a_sqrtm * sin_e;
  s.clock_bias_s = s.relativistic_s;
  s.clock_drift_sps = k.relativistic_f * e * o.sqrt_a_sqrtm * cos_e * e_dot;
  return s;
}

double clockPolynomial_s(const ClockPolynomial& c, const GnssTime& t) {
  // IS-GPS-200 20.3.3.3.3.1; t - toc is an exact difference of full instants, so
  // the end-of-week crossover needs no special case.
  const double dt = t - c.toc;
  return c.af0_s + dt * (c.af1_sps + dt * c.af2_sps2);
}

namespace {
BroadcastState withClock(BroadcastState s, const ClockPolynomial& c, const GnssTime& t) {
  const double dt = t - c.toc;
  s.clock_bias_s += clockPolynomial_s(c, t);
  s.clock_drift_sps += c.af1_sps + 2.0 * c.af2_sps2 * dt;
  return s;
}
}  // namespace

BroadcastState satelliteState(const GpsLnavEphemeris& eph, const GnssTime& t) {
  return withClock(keplerState(eph.orbit, gpsKeplerConstants(), t), eph.clock, t);
}

BroadcastState satelliteState(const GalileoEphemeris& eph, const GnssTime& t) {
  return withClock(keplerState(eph.orbit, galileoKeplerConstants(), t), eph.clock, t);
}

KeplerConstants beidouKeplerConstants() {
  // BDS-SIS-ICD-B1I 5.2.4.12: mu = 3.986004418e14 (CGCS2000), Omega_e = 7.2921150e-5;
  // F = -2 sqrt(mu) / c^2 (5.2.4.10), the Galileo value since the GM is the same.
  return {kGmGalileo_m3ps2, kBeidouEarthRotation_radps, kRelativisticF_Galileo};
}

BroadcastState satelliteState(const BeidouEphemeris& eph, const GnssTime& t) {
  const KeplerConstants k = beidouKeplerConstants();
  if (!eph.isGeo()) return withClock(keplerState(eph.orbit, k, t), eph.clock, t);
  // GEO (BDS-SIS-ICD-B1I 5.2.4.12, table 5-11, the GEO rows): Omega_k = Omega0 +
  // OmegaDot tk - Omega_e toe. keplerState with no Earth rotation and Omega0
  // shifted by -Omega_e toe gives exactly X_GK and its time derivative.
  KeplerOrbit inertial = eph.orbit;
  inertial.omega0_rad -= k.earth_rotation_radps * eph.orbit.toe_sow;
  BroadcastState s = keplerState(inertial, {k.gm_m3ps2, 0.0, k.relativistic_f}, t);
  const double tk = t - eph.orbit.toe;
  const double phi = k.earth_rotation_radps * tk;
  const double cz = std::cos(phi), sz = std::sin(phi);
  const double cx = std::cos(kBeidouGeoTilt_rad), sx = std::sin(kBeidouGeoTilt_rad);
  // R_X(a) = [1 0 0; 0 cos a  sin a; 0 -sin a  cos a], R_Z(a) = [cos a  sin a 0; -sin a  cos a 0; 0 0 1].
  Eigen::Matrix3d rx, rz, rz_dot;
  rx << 1, 0, 0, 0, cx, sx, 0, -sx, cx;
  rz << cz, sz, 0, -sz, cz, 0, 0, 0, 1;
  rz_dot << -sz, cz, 0, -cz, -sz, 0, 0, 0, 0;
  rz_dot *= k.earth_rotation_radps;
  const Eigen::Vector3d p_gk = s.position_ecef_m, v_gk = s.velocity_ecef_mps;
  s.position_ecef_m = rz * rx * p_gk;
  s.velocity_ecef_mps = rz * rx * v_gk + rz_dot * rx * p_gk;
  return withClock(s, eph.clock, t);
}

namespace {

struct GlonassDerivative {
  Eigen::Vector3d velocity;
  Eigen::Vector3d acceleration;
};

// GLONASS ICD 5.1, appendix A.3.1.2: equations of motion in the rotating PZ-90
// frame (central field, J2 term, centrifugal and Coriolis terms, plus the
// broadcast lunisolar acceleration held constant over the interval).
GlonassDerivative glonassDerivative(const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                                    const Eigen::Vector3d& lunisolar) {
  const double r2 = x.squaredNorm();
  const double r = std::sqrt(r2);
  const double gm_r3 = kGlonassGm_m3ps2 / (r2 * r);
  const double j2_term = 1.5 * kGlonassJ2 * kGlonassGm_m3ps2 * kGlonassSemiMajorAxis_m *
                         kGlonassSemiMajorAxis_m / (r2 * r2 * r);
  const double z2_r2 = x.z() * x.z() / r2;
  const double w = kGlonassEarthRotation_radps;
  GlonassDerivative d;
  d.velocity = v;
  d.acceleration.x() = -gm_r3 * x.x() - j2_term * x.x() * (1.0 - 5.0 * z2_r2) + w * w * x.x() +
                       2.0 * w * v.y() + lunisolar.x();
  d.acceleration.y() = -gm_r3 * x.y() - j2_term * x.y() * (1.0 - 5.0 * z2_r2) + w * w * x.y() -
                       2.0 * w * v.x() + lunisolar.y();
  d.acceleration.z() = -gm_r3 * x.z() - j2_term * x.z() * (3.0 - 5.0 * z2_r2) + lunisolar.z();
  return d;
}

void rungeKuttaStep(Eigen::Vector3d& x, Eigen::Vector3d& v, const Eigen::Vector3d& acc, double h) {
  const GlonassDerivative k1 = glonassDerivative(x, v, acc);
  const GlonassDerivative k2 =
      glonassDerivative(x + 0.5 * h * k1.velocity, v + 0.5 * h * k1.acceleration, acc);
  const GlonassDerivative k3 =
      glonassDerivative(x + 0.5 * h * k2.velocity, v + 0.5 * h * k2.acceleration, acc);
  const GlonassDerivative k4 = glonassDerivative(x + h * k3.velocity, v + h * k3.acceleration, acc);
  x += h / 6.0 * (k1.velocity + 2.0 * k2.velocity + 2.0 * k3.velocity + k4.velocity);
  v += h / 6.0 * (k1.acceleration + 2.0 * k2.acceleration + 2.0 * k3.acceleration + k4.acceleration);
}

}  // namespace

BroadcastState satelliteState(const GlonassEphemeris& eph, const GnssTime& t) {
  BroadcastState s;
  Eigen::Vector3d x = eph.position_m, v = eph.velocity_mps;
  const double dt = t - eph.tb;
  if (std::isfinite(dt)) {
    // Equal steps of at most 60 s; the count is bounded by the caller's limit on
    // |dt| and capped here (one day) so that no input can make this loop long.
    const double span = std::fmin(std::fabs(dt), 86400.0);
    const int steps = static_cast<int>(std::ceil(span / kGlonassStep_s));
    const double h = steps > 0 ? std::copysign(span / steps, dt) : 0.0;
    for (int i = 0; i < steps; ++i) rungeKuttaStep(x, v, eph.acceleration_mps2, h);
  }
  s.position_ecef_m = x;
  s.velocity_ecef_mps = v;
  // GLONASS ICD 3.3.3: t_sat - t_glonass = -TauN + GammaN (t - tb); RINEX writes -TauN.
  s.clock_bias_s = eph.minus_tau_n_s + eph.gamma_n * dt;
  s.clock_drift_sps = eph.gamma_n;
  return s;
}

std::optional<double> galileoE1ClockCorrection_s(const GalileoEphemeris& eph,
                                                 double clock_bias_s) {
  if (eph.type == GalileoNavType::FNav) return clock_bias_s - eph.bgd_e5a_e1_s;
  if (!eph.bgd_e5b_e1_s) return std::nullopt;
  return clock_bias_s - *eph.bgd_e5b_e1_s;
}

bool isHealthy(const GpsLnavEphemeris& eph) { return eph.health == 0; }

bool isHealthy(const GalileoEphemeris& eph) {
  // Bits 0-2: E1-B DVS and HS; 3-5: E5a; 6-8: E5b (RINEX 3.05 table A8).
  const int mask = eph.type == GalileoNavType::FNav ? 0x038 : (0x007 | 0x1C0);
  return (eph.health & mask) == 0;
}

bool isHealthy(const GlonassEphemeris& eph) { return eph.health == 0; }

bool isHealthy(const BeidouEphemeris& eph) { return eph.health == 0; }

}  // namespace ppp
