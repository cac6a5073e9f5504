#pragma once
// The Kepler block of the RTCM 3 broadcast ephemeris messages (RTCM 10403.3
// 3.5.10-3.5.14), internal to the io layer: Rtcm3Decoder reads it and the
// ephemeris encoder (io/rtcm/rtcm3_ephemeris_encoder.h) writes it from one layout.
// 1019/1044 (GPS/QZSS), 1045/1046 (Galileo) and 1042 (BeiDou) carry the same
// elements in the same order: Crs, delta n, M0, Cuc, e, Cus, sqrt(A), toe, Cic,
// Omega0, Cis, i0, Crc, omega, Omega dot. They differ in the harmonic
// corrections (16 bits at 2^-5 m / 2^-29 rad; BeiDou 18 bits at 2^-6 m /
// 2^-31 rad, BDS-SIS-ICD-B1I 5.2.4) and in toe (GPS 16 bits of 16 s, Galileo
// 14 bits of 60 s, BeiDou 17 bits of 8 s). Angles are in semicircles (pi =
// kPi), rates in semicircles/s.
#include <cmath>
#include <cstdint>

#include "ppp_bayes_tree/io/bit_reader.h"
#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp::rtcm_eph {

struct KeplerLayout {
  int harmonic_bits = 16;  // Crs, Cuc, Cus, Cic, Cis, Crc
  int radius_exp = -5;     // Crs, Crc: 2^radius_exp m
  int angle_exp = -29;     // Cuc, Cus, Cic, Cis: 2^angle_exp rad
  int toe_bits = 16;
  double toe_scale_s = 16.0;
};
constexpr KeplerLayout kKeplerLnav{16, -5, -29, 16, 16.0};     // 1019, 1044
constexpr KeplerLayout kKeplerGalileo{16, -5, -29, 14, 60.0};  // 1045, 1046
constexpr KeplerLayout kKeplerBeidou{18, -6, -31, 17, 8.0};    // 1042

inline double p2(int e) { return std::ldexp(1.0, e); }

inline void readKepler(BitReader& r, const KeplerLayout& l, KeplerOrbit& o) {
  o.crs_m = r.s(l.harmonic_bits) * p2(l.radius_exp);
  o.delta_n_radps = r.s(16) * p2(-43) * kPi;
  o.m0_rad = r.s(32) * p2(-31) * kPi;
  o.cuc_rad = r.s(l.harmonic_bits) * p2(l.angle_exp);
  o.eccentricity = r.u(32) * p2(-33);
  o.cus_rad = r.s(l.harmonic_bits) * p2(l.angle_exp);
  o.sqrt_a_sqrtm = r.u(32) * p2(-19);
  o.toe_sow = r.u(l.toe_bits) * l.toe_scale_s;
  o.cic_rad = r.s(l.harmonic_bits) * p2(l.angle_exp);
  o.omega0_rad = r.s(32) * p2(-31) * kPi;
  o.cis_rad = r.s(l.harmonic_bits) * p2(l.angle_exp);
  o.i0_rad = r.s(32) * p2(-31) * kPi;
  o.crc_m = r.s(l.harmonic_bits) * p2(l.radius_exp);
  o.omega_rad = r.s(32) * p2(-31) * kPi;
  o.omega_dot_radps = r.s(24) * p2(-43) * kPi;
}

/// value / scale, rounded to the nearest integer.
inline std::int64_t q(double value, double scale) { return std::llround(value / scale); }
/// A semicircle quantity (value in radians) on a 2^e grid of semicircles.
inline std::int64_t semicircles(double value_rad, int e) { return std::llround(value_rad / kPi / p2(e)); }

inline void putKepler(BitWriter& w, const KeplerLayout& l, const KeplerOrbit& o) {
  w.putSigned(q(o.crs_m, p2(l.radius_exp)), l.harmonic_bits);
  w.putSigned(semicircles(o.delta_n_radps, -43), 16);
  w.putSigned(semicircles(o.m0_rad, -31), 32);
  w.putSigned(q(o.cuc_rad, p2(l.angle_exp)), l.harmonic_bits);
  w.putUnsigned(static_cast<std::uint64_t>(q(o.eccentricity, p2(-33))), 32);
  w.putSigned(q(o.cus_rad, p2(l.angle_exp)), l.harmonic_bits);
  w.putUnsigned(static_cast<std::uint64_t>(q(o.sqrt_a_sqrtm, p2(-19))), 32);
  w.putUnsigned(static_cast<std::uint64_t>(q(o.toe_sow, l.toe_scale_s)), l.toe_bits);
  w.putSigned(q(o.cic_rad, p2(l.angle_exp)), l.harmonic_bits);
  w.putSigned(semicircles(o.omega0_rad, -31), 32);
  w.putSigned(q(o.cis_rad, p2(l.angle_exp)), l.harmonic_bits);
  w.putSigned(semicircles(o.i0_rad, -31), 32);
  w.putSigned(q(o.crc_m, p2(l.radius_exp)), l.harmonic_bits);
  w.putSigned(semicircles(o.omega_rad, -31), 32);
  w.putSigned(semicircles(o.omega_dot_radps, -43), 24);
}

}  // namespace ppp::rtcm_eph
