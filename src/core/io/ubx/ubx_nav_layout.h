#pragma once
// Bit layouts of the GLONASS L1/L2 OF strings and the BeiDou D1/D2 navigation
// subframes as a u-blox receiver delivers them in RXM-SFRBX (internal to the io
// layer: shared by UbxDecoder and the SFRBX encoder, io/ubx/ubx_nav_encoder.h, so
// that both read and write one table).
//
// GLONASS (GLONASS ICD edition 5.1, 2008, section 4.4, figure 4.5 and table
// 4.5): a string is 85 bits, b85 (idle chip 0) first; index i in the tables is
// string bit 85 - i. SFRBX carries it in 4 words, word 0 bit 31 = b85; word 3's
// upper 16 bits identify the frame (strings of one frame share them). Numbers
// are sign-magnitude (ICD 4.4 note: the MSB is the sign). Hamming code: check
// bits b8..b1 (beta8..beta1), section 4.7 / table 4.13, see glonassHammingOk.
//
// BeiDou (BDS-SIS-ICD-B1I version 2.0, 2013 / 3.0, 2019, sections 5.2 (D1) and
// 5.3 (D2)): a subframe (D1) or page (D2) is 10 words of 30 bits, 300 bits;
// SFRBX word k holds word k in its 30 LSBs. Index i in the tables is bit i of
// the subframe (0-based, word k = bits 30k..30k+29). Word 1: 26 data bits
// (15 unencoded: preamble, Rev, FraID; then 11 encoded) and 4 parity bits;
// words 2-10: 22 data bits and 8 parity bits, i.e. two BCH(15,11,1) codewords
// (ICD 5.1.3: generator g(x) = x^4 + x + 1) whose information bits the
// receiver has de-interleaved: data bits 0-10 with parity bits 22-25, data
// bits 11-21 with parity bits 26-29 (the order in which the u-blox interface
// description lists them: 22 data bits, then 8 parity bits). Numbers are two's
// complement; a field split over words is listed MSB part first.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp::ubx_nav {

struct BitPart {
  int start = 0;
  int length = 0;
};

/// One GLONASS broadcast parameter: `unit` = string 0-3 (strings 1-4); its bits
/// are the parts concatenated; value = integer * scale (BeiDou: BdsField below).
struct Field {
  int unit = 0;
  std::array<BitPart, 3> parts{};
  bool is_signed = false;
  double scale = 1.0;
  int bits() const { return parts[0].length + parts[1].length + parts[2].length; }
};

/// 2^e, exact for any |e| < 1000 (constexpr: repeated halving / doubling).
constexpr double p2(int e) {
  double v = 1.0;
  for (int i = 0; i < (e < 0 ? -e : e); ++i) v = e < 0 ? v * 0.5 : v * 2.0;
  return v;
}

// ---------------------------------------------------------------------------
// BeiDou D1 (BDS-SIS-ICD-B1I 5.2.4, figures 5-5 to 5-7): subframes 1-3, units
// 0-2. Common to every subframe: FraID 15/3, SOW 18/8 + 30/12.
// BeiDou D2 (BDS-SIS-ICD-B1I 5.3.3, figure 5-10 and table 5-13): subframe 1,
// pages 1-10, units 0-9; page number Pnum 42/4.
// A field may be split over two units (D2 fields over two pages, the D1 toe
// over subframes 2 and 3): `msb_unit` holds the MSB part, `lsb_unit` the LSB
// part (-1: not split).
// ---------------------------------------------------------------------------
struct BdsField {
  int msb_unit = 0;
  std::array<BitPart, 3> msb{};
  int lsb_unit = -1;  // -1: not split over units
  std::array<BitPart, 3> lsb{};
  bool is_signed = false;
  double scale = 1.0;
};

/// Where each ephemeris parameter of a D1 frame or a D2 page set lies.
struct BdsLayout {
  BdsField sat_h1, aodc, urai, week, toc, tgd1, tgd2, a0, a1, a2, aode;
  BdsField delta_n, cuc, m0, e, cus, crc, crs, sqrt_a, toe, i0, cic, omega_dot, cis, idot, omega0, omega;
};

// Angles in semicircles (and semicircles/s), times in s, clock terms in s, s/s, s/s^2.
constexpr BdsLayout kBdsD1{
    /* sat_h1    */ {0, {{{42, 1}}}, -1, {}, false, 1},
    /* aodc      */ {0, {{{43, 5}}}, -1, {}, false, 1},
    /* urai      */ {0, {{{48, 4}}}, -1, {}, false, 1},
    /* week      */ {0, {{{60, 13}}}, -1, {}, false, 1},
    /* toc       */ {0, {{{73, 9}, {90, 8}}}, -1, {}, false, 8.0},
    /* tgd1      */ {0, {{{98, 10}}}, -1, {}, true, 0.1e-9},
    /* tgd2      */ {0, {{{108, 4}, {120, 6}}}, -1, {}, true, 0.1e-9},
    /* a0        */ {0, {{{225, 7}, {240, 17}}}, -1, {}, true, p2(-33)},
    /* a1        */ {0, {{{257, 5}, {270, 17}}}, -1, {}, true, p2(-50)},
    /* a2        */ {0, {{{214, 11}}}, -1, {}, true, p2(-66)},
    /* aode      */ {0, {{{287, 5}}}, -1, {}, false, 1},
    /* delta_n   */ {1, {{{42, 10}, {60, 6}}}, -1, {}, true, p2(-43)},
    /* cuc       */ {1, {{{66, 16}, {90, 2}}}, -1, {}, true, p2(-31)},
    /* m0        */ {1, {{{92, 20}, {120, 12}}}, -1, {}, true, p2(-31)},
    /* e         */ {1, {{{132, 10}, {150, 22}}}, -1, {}, false, p2(-33)},
    /* cus       */ {1, {{{180, 18}}}, -1, {}, true, p2(-31)},
    /* crc       */ {1, {{{198, 4}, {210, 14}}}, -1, {}, true, p2(-6)},
    /* crs       */ {1, {{{224, 8}, {240, 10}}}, -1, {}, true, p2(-6)},
    /* sqrt_a    */ {1, {{{250, 12}, {270, 20}}}, -1, {}, false, p2(-19)},
    /* toe       */ {1, {{{290, 2}}}, 2, {{{42, 10}, {60, 5}}}, false, 8.0},
    /* i0        */ {2, {{{65, 17}, {90, 15}}}, -1, {}, true, p2(-31)},
    /* cic       */ {2, {{{105, 7}, {120, 11}}}, -1, {}, true, p2(-31)},
    /* omega_dot */ {2, {{{131, 11}, {150, 13}}}, -1, {}, true, p2(-43)},
    /* cis       */ {2, {{{163, 9}, {180, 9}}}, -1, {}, true, p2(-31)},
    /* idot      */ {2, {{{189, 13}, {210, 1}}}, -1, {}, true, p2(-43)},
    /* omega0    */ {2, {{{211, 21}, {240, 11}}}, -1, {}, true, p2(-31)},
    /* omega     */ {2, {{{251, 11}, {270, 21}}}, -1, {}, true, p2(-31)},
};
constexpr BdsLayout kBdsD2{
    /* sat_h1    */ {0, {{{46, 1}}}, -1, {}, false, 1},
    /* aodc      */ {0, {{{47, 5}}}, -1, {}, false, 1},
    /* urai      */ {0, {{{60, 4}}}, -1, {}, false, 1},
    /* week      */ {0, {{{64, 13}}}, -1, {}, false, 1},
    /* toc       */ {0, {{{77, 5}, {90, 12}}}, -1, {}, false, 8.0},
    /* tgd1      */ {0, {{{102, 10}}}, -1, {}, true, 0.1e-9},
    /* tgd2      */ {0, {{{120, 10}}}, -1, {}, true, 0.1e-9},
    /* a0        */ {2, {{{100, 12}, {120, 12}}}, -1, {}, true, p2(-33)},
    /* a1        */ {2, {{{132, 4}}}, 3, {{{46, 6}, {60, 12}}}, true, p2(-50)},
    /* a2        */ {3, {{{72, 10}, {90, 1}}}, -1, {}, true, p2(-66)},
    /* aode      */ {3, {{{91, 5}}}, -1, {}, false, 1},
    /* delta_n   */ {3, {{{96, 16}}}, -1, {}, true, p2(-43)},
    /* cuc       */ {3, {{{120, 14}}}, 4, {{{46, 4}}}, true, p2(-31)},
    /* m0        */ {4, {{{50, 2}, {60, 22}, {90, 8}}}, -1, {}, true, p2(-31)},
    /* e         */ {4, {{{124, 10}}}, 5, {{{46, 6}, {60, 16}}}, false, p2(-33)},
    /* cus       */ {4, {{{98, 14}, {120, 4}}}, -1, {}, true, p2(-31)},
    /* crc       */ {7, {{{65, 17}, {90, 1}}}, -1, {}, true, p2(-6)},
    /* crs       */ {7, {{{91, 18}}}, -1, {}, true, p2(-6)},
    /* sqrt_a    */ {5, {{{76, 6}, {90, 22}, {120, 4}}}, -1, {}, false, p2(-19)},
    /* toe       */ {6, {{{80, 2}, {90, 15}}}, -1, {}, false, 8.0},
    /* i0        */ {6, {{{105, 7}, {120, 14}}}, 7, {{{46, 6}, {60, 5}}}, true, p2(-31)},
    /* cic       */ {5, {{{124, 10}}}, 6, {{{46, 6}, {60, 2}}}, true, p2(-31)},
    /* omega_dot */ {7, {{{109, 3}, {120, 16}}}, 8, {{{46, 5}}}, true, p2(-43)},
    /* cis       */ {6, {{{62, 18}}}, -1, {}, true, p2(-31)},
    /* idot      */ {9, {{{51, 1}, {60, 13}}}, -1, {}, true, p2(-43)},
    /* omega0    */ {8, {{{51, 1}, {60, 22}, {90, 9}}}, -1, {}, true, p2(-31)},
    /* omega     */ {8, {{{99, 13}, {120, 14}}}, 9, {{{46, 5}}}, true, p2(-31)},
};

// ---------------------------------------------------------------------------
// GLONASS strings 1-4 (GLONASS ICD 5.1 table 4.5; index = 85 - bit number).
// Sign-magnitude numbers are marked is_signed.
// ---------------------------------------------------------------------------
namespace glo {
constexpr Field kP1{0, {{{7, 2}}}, false, 1};
constexpr Field kTkHours{0, {{{9, 5}}}, false, 1};
constexpr Field kTkMinutes{0, {{{14, 6}}}, false, 1};
constexpr Field kTkHalfMinute{0, {{{20, 1}}}, false, 1};
constexpr Field kVx{0, {{{21, 24}}}, true, p2(-20)};   // km/s
constexpr Field kAx{0, {{{45, 5}}}, true, p2(-30)};    // km/s^2
constexpr Field kX{0, {{{50, 27}}}, true, p2(-11)};    // km
constexpr Field kBn{1, {{{5, 3}}}, false, 1};
constexpr Field kP2{1, {{{8, 1}}}, false, 1};
constexpr Field kTb{1, {{{9, 7}}}, false, 1};          // 15 min units of the Moscow day
constexpr Field kVy{1, {{{21, 24}}}, true, p2(-20)};
constexpr Field kAy{1, {{{45, 5}}}, true, p2(-30)};
constexpr Field kY{1, {{{50, 27}}}, true, p2(-11)};
constexpr Field kP3{2, {{{5, 1}}}, false, 1};
constexpr Field kGammaN{2, {{{6, 11}}}, true, p2(-40)};
constexpr Field kP{2, {{{18, 2}}}, false, 1};
constexpr Field kLn3{2, {{{20, 1}}}, false, 1};
constexpr Field kVz{2, {{{21, 24}}}, true, p2(-20)};
constexpr Field kAz{2, {{{45, 5}}}, true, p2(-30)};
constexpr Field kZ{2, {{{50, 27}}}, true, p2(-11)};
constexpr Field kTauN{3, {{{5, 22}}}, true, p2(-30)};
constexpr Field kDeltaTauN{3, {{{27, 5}}}, true, p2(-30)};
constexpr Field kEn{3, {{{32, 5}}}, false, 1};         // age of operational information, days
constexpr Field kP4{3, {{{51, 1}}}, false, 1};
constexpr Field kFt{3, {{{52, 4}}}, false, 1};
constexpr Field kNt{3, {{{59, 11}}}, false, 1};
constexpr Field kSlot{3, {{{70, 5}}}, false, 1};
constexpr Field kM{3, {{{75, 2}}}, false, 1};
}  // namespace glo

}  // namespace ppp::ubx_nav

namespace ppp::ubx_nav {

/// A subframe / page (300 bits) or a GLONASS string (85 bits), MSB first.
using Unit = std::array<std::uint8_t, 38>;

inline std::uint64_t getBits(const Unit& u, int start, int length) {
  std::uint64_t v = 0;
  for (int i = 0; i < length; ++i) {
    const int b = start + i;
    v = (v << 1) | ((u[static_cast<std::size_t>(b / 8)] >> (7 - b % 8)) & 1u);
  }
  return v;
}
inline void setBits(Unit& u, int start, int length, std::uint64_t value) {
  for (int i = 0; i < length; ++i) {
    const int b = start + i;
    const bool bit = ((value >> (length - 1 - i)) & 1u) != 0;
    auto& byte = u[static_cast<std::size_t>(b / 8)];
    const auto mask = static_cast<std::uint8_t>(0x80u >> (b % 8));
    byte = static_cast<std::uint8_t>(bit ? (byte | mask) : (byte & ~mask));
  }
}

/// The raw bits of parts of one unit, concatenated.
inline std::uint64_t getParts(const Unit& u, const std::array<BitPart, 3>& parts, int& bits) {
  std::uint64_t v = 0;
  for (const auto& p : parts) {
    if (p.length == 0) continue;
    v = (v << p.length) | getBits(u, p.start, p.length);
    bits += p.length;
  }
  return v;
}
inline void setParts(Unit& u, const std::array<BitPart, 3>& parts, std::uint64_t value, int bits_below) {
  int total = 0;
  for (const auto& p : parts) total += p.length;
  int shift = bits_below + total;
  for (const auto& p : parts) {
    if (p.length == 0) continue;
    shift -= p.length;
    setBits(u, p.start, p.length, (value >> shift) & ((std::uint64_t{1} << p.length) - 1));
  }
}

/// Interprets `bits` raw bits as two's complement (sign_magnitude = false) or sign-magnitude.
inline double toSigned(std::uint64_t raw, int bits, bool is_signed, bool sign_magnitude) {
  if (!is_signed) return static_cast<double>(raw);
  const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
  if (sign_magnitude) return (raw & sign) ? -static_cast<double>(raw & (sign - 1)) : static_cast<double>(raw);
  return (raw & sign) ? static_cast<double>(static_cast<std::int64_t>(raw) - static_cast<std::int64_t>(sign << 1))
                      : static_cast<double>(raw);
}
/// The raw bits of integer n (false when n does not fit).
inline bool fromSigned(long long n, int bits, bool is_signed, bool sign_magnitude, std::uint64_t& raw) {
  const long long limit = 1LL << (is_signed ? bits - 1 : bits);
  if (!is_signed) {
    if (n < 0 || n >= limit) return false;
    raw = static_cast<std::uint64_t>(n);
    return true;
  }
  if (sign_magnitude) {
    if (n <= -limit || n >= limit) return false;
    raw = n < 0 ? (static_cast<std::uint64_t>(-n) | (std::uint64_t{1} << (bits - 1))) : static_cast<std::uint64_t>(n);
    return true;
  }
  if (n < -limit || n >= limit) return false;
  raw = static_cast<std::uint64_t>(n) & ((std::uint64_t{1} << bits) - 1);
  return true;
}

template <std::size_t N>
double readField(const std::array<Unit, N>& units, const Field& f, bool sign_magnitude = false) {
  int bits = 0;
  const std::uint64_t raw = getParts(units[static_cast<std::size_t>(f.unit)], f.parts, bits);
  return toSigned(raw, bits, f.is_signed, sign_magnitude) * f.scale;
}
template <std::size_t N>
bool writeField(std::array<Unit, N>& units, const Field& f, double value, bool sign_magnitude = false) {
  const long long n = std::llround(value / f.scale);
  std::uint64_t raw = 0;
  if (!fromSigned(n, f.bits(), f.is_signed, sign_magnitude, raw)) return false;
  setParts(units[static_cast<std::size_t>(f.unit)], f.parts, raw, 0);
  return true;
}
template <std::size_t N>
double readField(const std::array<Unit, N>& units, const BdsField& f) {
  int bits = 0;
  std::uint64_t raw = getParts(units[static_cast<std::size_t>(f.msb_unit)], f.msb, bits);
  if (f.lsb_unit >= 0) {
    int low = 0;
    const std::uint64_t lsb = getParts(units[static_cast<std::size_t>(f.lsb_unit)], f.lsb, low);
    raw = (raw << low) | lsb;
    bits += low;
  }
  return toSigned(raw, bits, f.is_signed, false) * f.scale;
}
template <std::size_t N>
bool writeField(std::array<Unit, N>& units, const BdsField& f, double value) {
  int msb_bits = 0, lsb_bits = 0;
  for (const auto& p : f.msb) msb_bits += p.length;
  if (f.lsb_unit >= 0)
    for (const auto& p : f.lsb) lsb_bits += p.length;
  const long long n = std::llround(value / f.scale);
  std::uint64_t raw = 0;
  if (!fromSigned(n, msb_bits + lsb_bits, f.is_signed, false, raw)) return false;
  setParts(units[static_cast<std::size_t>(f.msb_unit)], f.msb, raw, lsb_bits);
  if (f.lsb_unit >= 0) setParts(units[static_cast<std::size_t>(f.lsb_unit)], f.lsb, raw, 0);
  return true;
}
/// writeField, throwing std::invalid_argument that names the parameter when
/// the value does not fit its field (the SFRBX encoder).
template <std::size_t N, typename F>
void putField(std::array<Unit, N>& units, const F& field, double value, const char* name,
              bool sign_magnitude = false) {
  bool ok;
  if constexpr (std::is_same_v<F, BdsField>) {
    ok = writeField(units, field, value);
  } else {
    ok = writeField(units, field, value, sign_magnitude);
  }
  if (!ok)
    throw std::invalid_argument(std::string("SFRBX encoder: ") + name + " = " + std::to_string(value) +
                                " does not fit its broadcast field");
}

/// What a D1 frame / D2 page set broadcasts beside the record's values as kept:
/// the URA index, the 13-bit BDT week and toc (BDT seconds of week).
struct BdsBroadcast {
  int urai = 0;
  int week13 = 0;
  double toc_sow = 0.0;
};

/// The ephemeris parameters of D1 subframes 1-3 or D2 pages 1-10 (`layout`
/// kBdsD1 / kBdsD2) into `eph` (angles from semicircles with kIcdPi); toe and
/// toc are left as seconds of week (orbit.toe_sow, the returned toc_sow).
inline BdsBroadcast readBeidou(const std::array<Unit, 10>& u, const BdsLayout& l, BeidouEphemeris& eph) {
  KeplerOrbit& o = eph.orbit;
  BdsBroadcast b;
  eph.health = static_cast<int>(readField(u, l.sat_h1));
  eph.aodc = static_cast<int>(readField(u, l.aodc));
  b.urai = static_cast<int>(readField(u, l.urai));
  b.week13 = static_cast<int>(readField(u, l.week));
  b.toc_sow = readField(u, l.toc);
  eph.tgd1_s = readField(u, l.tgd1);
  eph.tgd2_s = readField(u, l.tgd2);
  eph.clock.af0_s = readField(u, l.a0);
  eph.clock.af1_sps = readField(u, l.a1);
  eph.clock.af2_sps2 = readField(u, l.a2);
  eph.aode = static_cast<int>(readField(u, l.aode));
  o.delta_n_radps = readField(u, l.delta_n) * kIcdPi;
  o.cuc_rad = readField(u, l.cuc);
  o.m0_rad = readField(u, l.m0) * kIcdPi;
  o.eccentricity = readField(u, l.e);
  o.cus_rad = readField(u, l.cus);
  o.crc_m = readField(u, l.crc);
  o.crs_m = readField(u, l.crs);
  o.sqrt_a_sqrtm = readField(u, l.sqrt_a);
  o.toe_sow = readField(u, l.toe);
  o.i0_rad = readField(u, l.i0) * kIcdPi;
  o.cic_rad = readField(u, l.cic);
  o.omega_dot_radps = readField(u, l.omega_dot) * kIcdPi;
  o.cis_rad = readField(u, l.cis);
  o.idot_radps = readField(u, l.idot) * kIcdPi;
  o.omega0_rad = readField(u, l.omega0) * kIcdPi;
  o.omega_rad = readField(u, l.omega) * kIcdPi;
  return b;
}

/// The inverse of readBeidou: writes the record's parameters into `u`; throws
/// std::invalid_argument naming a parameter that does not fit its field.
inline void writeBeidou(std::array<Unit, 10>& u, const BdsLayout& l, const BeidouEphemeris& eph,
                        const BdsBroadcast& b) {
  const KeplerOrbit& o = eph.orbit;
  putField(u, l.sat_h1, eph.health, "SatH1");
  putField(u, l.aodc, eph.aodc, "AODC");
  putField(u, l.urai, b.urai, "URAI");
  putField(u, l.week, b.week13, "WN");
  putField(u, l.toc, b.toc_sow, "toc");
  putField(u, l.tgd1, eph.tgd1_s, "TGD1");
  putField(u, l.tgd2, eph.tgd2_s, "TGD2");
  putField(u, l.a0, eph.clock.af0_s, "a0");
  putField(u, l.a1, eph.clock.af1_sps, "a1");
  putField(u, l.a2, eph.clock.af2_sps2, "a2");
  putField(u, l.aode, eph.aode, "AODE");
  putField(u, l.delta_n, o.delta_n_radps / kIcdPi, "delta n");
  putField(u, l.cuc, o.cuc_rad, "Cuc");
  putField(u, l.m0, o.m0_rad / kIcdPi, "M0");
  putField(u, l.e, o.eccentricity, "e");
  putField(u, l.cus, o.cus_rad, "Cus");
  putField(u, l.crc, o.crc_m, "Crc");
  putField(u, l.crs, o.crs_m, "Crs");
  putField(u, l.sqrt_a, o.sqrt_a_sqrtm, "sqrt(A)");
  putField(u, l.toe, o.toe_sow, "toe");
  putField(u, l.i0, o.i0_rad / kIcdPi, "i0");
  putField(u, l.cic, o.cic_rad, "Cic");
  putField(u, l.omega_dot, o.omega_dot_radps / kIcdPi, "OmegaDot");
  putField(u, l.cis, o.cis_rad, "Cis");
  putField(u, l.idot, o.idot_radps / kIcdPi, "IDOT");
  putField(u, l.omega0, o.omega0_rad / kIcdPi, "Omega0");
  putField(u, l.omega, o.omega_rad / kIcdPi, "omega");
}

// ---------------------------------------------------------------------------
// BeiDou BCH(15,11,1), generator x^4 + x + 1 (BDS-SIS-ICD-B1I 5.1.3).
// ---------------------------------------------------------------------------
inline std::uint32_t bch15Parity(std::uint32_t info11) {
  std::uint32_t r = info11 << 4;
  for (int bit = 14; bit >= 4; --bit)
    if (r & (1u << bit)) r ^= 0x13u << (bit - 4);
  return r & 0xFu;
}
/// Writes the parity bits of word `w` (0-9) of a subframe / page.
inline void setBdsParity(Unit& u, int w) {
  const int base = 30 * w;
  if (w == 0) {
    setBits(u, base + 26, 4, bch15Parity(static_cast<std::uint32_t>(getBits(u, base + 15, 11))));
    return;
  }
  setBits(u, base + 22, 4, bch15Parity(static_cast<std::uint32_t>(getBits(u, base, 11))));
  setBits(u, base + 26, 4, bch15Parity(static_cast<std::uint32_t>(getBits(u, base + 11, 11))));
}
/// True when every word's BCH parity holds.
inline bool bdsParityOk(const Unit& u) {
  for (int w = 0; w < 10; ++w) {
    const int base = 30 * w;
    if (w == 0) {
      if (getBits(u, base + 26, 4) != bch15Parity(static_cast<std::uint32_t>(getBits(u, base + 15, 11)))) return false;
      continue;
    }
    if (getBits(u, base + 22, 4) != bch15Parity(static_cast<std::uint32_t>(getBits(u, base, 11)))) return false;
    if (getBits(u, base + 26, 4) != bch15Parity(static_cast<std::uint32_t>(getBits(u, base + 11, 11)))) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------
// GLONASS Hamming code (ICD 5.1, 4.7, table 4.13). Data bits b9..b85 sit at the
// positions of a Hamming code that skips the check positions 1, 2, 4, 8, 16,
// 32, 64: b9 -> 3, b10 -> 5, b11 -> 6, b12 -> 7, b13 -> 9, ...; check bit
// beta_k (k = 1..7, string bit k) covers the data bits whose position has bit
// k-1 set (the ICD's sums c1..c7: c1 over b9, b10, b12, b13, b15, ...; c7 over
// b66..b85), beta8 makes the parity of all 85 bits even (c_sigma).
// ---------------------------------------------------------------------------
inline int glonassBit(const Unit& s, int bit) { return static_cast<int>(getBits(s, 85 - bit, 1)); }
/// The checksums c1..c7 (bits 0-6) and c_sigma (bit 7) of a string.
inline unsigned glonassChecksums(const Unit& s) {
  unsigned c = 0;
  int position = 2, all = 0;
  for (int bit = 9; bit <= 85; ++bit) {
    do ++position;
    while ((position & (position - 1)) == 0);  // skip powers of two
    const int b = glonassBit(s, bit);
    all ^= b;
    for (int k = 0; k < 7; ++k)
      if (b && (position >> k & 1)) c ^= 1u << k;
  }
  for (int k = 0; k < 7; ++k) c ^= static_cast<unsigned>(glonassBit(s, k + 1)) << k;
  for (int k = 1; k <= 8; ++k) all ^= glonassBit(s, k);
  return c | (static_cast<unsigned>(all) << 7);
}
/// ICD 4.7 a): correct when every checksum is 0, or exactly one of c1..c7 is 1
/// together with c_sigma (an error in that check bit only).
inline bool glonassHammingOk(const Unit& s) {
  const unsigned c = glonassChecksums(s);
  if (c == 0) return true;
  const unsigned low = c & 0x7Fu;
  return (c & 0x80u) && low != 0 && (low & (low - 1)) == 0;
}
/// Sets beta1..beta8 of a string whose data bits are written.
inline void setGlonassHamming(Unit& s) {
  for (int bit = 1; bit <= 8; ++bit) setBits(s, 85 - bit, 1, 0);
  const unsigned c = glonassChecksums(s);
  for (int k = 0; k < 7; ++k) setBits(s, 85 - (k + 1), 1, (c >> k) & 1u);
  const unsigned after = glonassChecksums(s);
  setBits(s, 85 - 8, 1, (after >> 7) & 1u);
}

}  // namespace ppp::ubx_nav
