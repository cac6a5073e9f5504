#include "ppp_bayes_tree/types/navigation_records.h"

#include <cmath>
#include <cstdint>
#include <initializer_list>

namespace ppp {
namespace {

constexpr double kMinSemiMajorAxis_m = 6.4e6;  // below the Earth's surface: not an orbit
constexpr double kMaxSemiMajorAxis_m = 1.0e8;  // far beyond any GNSS orbit (~4.2e7 for GEO)

bool allFinite(std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

std::optional<std::string> checkKeplerOrbit(const KeplerOrbit& o) {
  if (!allFinite({o.toe_sow, o.sqrt_a_sqrtm, o.eccentricity, o.i0_rad, o.omega0_rad, o.omega_rad,
                  o.m0_rad, o.delta_n_radps, o.idot_radps, o.omega_dot_radps, o.cuc_rad, o.cus_rad,
                  o.crc_m, o.crs_m, o.cic_rad, o.cis_rad})) {
    return "non-finite orbital element";
  }
  if (!(o.eccentricity >= 0.0 && o.eccentricity < 1.0)) return "eccentricity outside [0, 1)";
  const double a = o.sqrt_a_sqrtm * o.sqrt_a_sqrtm;
  if (!(o.sqrt_a_sqrtm > 0.0) || a < kMinSemiMajorAxis_m || a > kMaxSemiMajorAxis_m) {
    return "semi-major axis outside [6400 km, 100000 km]";
  }
  if (o.toe_sow < 0.0 || o.toe_sow > 604800.0) return "toe outside the week";
  // Rates and corrections far beyond anything broadcast (|dn|, |Omega dot|,
  // |IDOT| ~ 1e-8 rad/s; corrections ~ 1e-5 rad, 1e3 m) mean a corrupt record.
  if (std::fabs(o.delta_n_radps) > 1e-5 || std::fabs(o.idot_radps) > 1e-5 ||
      std::fabs(o.omega_dot_radps) > 1e-5) {
    return "orbital rate implausibly large";
  }
  if (std::fabs(o.cuc_rad) > 0.1 || std::fabs(o.cus_rad) > 0.1 || std::fabs(o.cic_rad) > 0.1 ||
      std::fabs(o.cis_rad) > 0.1 || std::fabs(o.crc_m) > 1e5 || std::fabs(o.crs_m) > 1e5) {
    return "harmonic correction implausibly large";
  }
  return std::nullopt;
}

std::optional<std::string> checkGlonassState(const GlonassEphemeris& eph) {
  if (!eph.position_m.allFinite() || !eph.velocity_mps.allFinite() ||
      !eph.acceleration_mps2.allFinite() || !std::isfinite(eph.minus_tau_n_s) ||
      !std::isfinite(eph.gamma_n)) {
    return "non-finite GLONASS state";
  }
  const double r = eph.position_m.norm();
  if (r < kMinSemiMajorAxis_m || r > kMaxSemiMajorAxis_m) {
    return "GLONASS position radius outside [6400 km, 100000 km]";
  }
  if (eph.velocity_mps.norm() > 2e4 || eph.acceleration_mps2.norm() > 1.0) {
    return "GLONASS velocity or acceleration implausibly large";
  }
  return std::nullopt;
}

std::optional<GnssTime> transmissionTime(const GpsLnavEphemeris& eph) {
  if (!eph.transmission_sow) return std::nullopt;
  return nearestSecondsOfWeek(eph.orbit.toe, *eph.transmission_sow);
}

std::optional<GnssTime> transmissionTime(const GalileoEphemeris& eph) {
  if (!eph.transmission_sow) return std::nullopt;
  return nearestSecondsOfWeek(eph.orbit.toe, *eph.transmission_sow);
}

GnssTime transmissionTime(const GlonassEphemeris& eph) {
  const double utc_minus_gpst = eph.tb.offsetToSystem_s(TimeSystem::UTC);
  const GnssTime tb_utc = eph.tb + utc_minus_gpst;
  const double tk = eph.message_frame_time_s;
  GnssTime tx_utc;
  if (tk >= 86400.0) {
    tx_utc = nearestSecondsOfWeek(tb_utc, tk);
  } else {
    const double day_start_s = std::floor(tb_utc.toGpsSecondsDouble() / 86400.0) * 86400.0;
    tx_utc = GnssTime::fromGpsSeconds(static_cast<std::int64_t>(day_start_s), 0.0) + tk;
    if (tb_utc - tx_utc > 43200.0) tx_utc += 86400.0;
    else if (tx_utc - tb_utc > 43200.0) tx_utc -= 86400.0;
  }
  return tx_utc - utc_minus_gpst;
}

}  // namespace ppp
