#pragma once
// Private to rtcm_ssr_decoder.cpp / rtcm_ssr_encoder.cpp: the bit layout of the
// SSR messages written ONCE as a template over a reader or a writer, so that
// the decoder and the encoder cannot disagree on a field.
//
// Layouts: RTCM 10403.3 section 3.5.12 (message types 1057-1068, 1240-1263,
// 1264, 1265-1270; data fields DF365-DF415, DF472-DF487) and IGS-SSR v1.00
// (message 4076, sections 5 and 6: IDF001-IDF041).
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/io/bit_reader.h"
#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/types/ssr_corrections.h"

namespace ppp::ssr_layout {

constexpr double kSemicircle_rad = 3.14159265358979323846;

struct TypeInfo {
  GnssSystem system = GnssSystem::GPS;
  SsrMessageKind kind = SsrMessageKind::Orbit;
};

/// Bits of the satellite id and of the issue of data per system.
struct SatelliteFieldBits {
  int id = 6, iod = 8, iod_aux = 0;  // iod_aux: BeiDou toe modulo / SBAS IODCRC
  int prn_offset = 0;                // SatelliteId::prn = raw id + prn_offset
};

/// The SSR systems, one row each.
struct SsrSystemRow {
  GnssSystem system;
  /// RTCM group i: messages 1057 + 6 i (GPS, GLONASS) or 1240 + 6 (i - 2) (the
  /// others), in the kind order orbit, clock, code bias, combined, URA, high-rate
  /// clock; phase biases 1265 + i.
  int rtcm_index;
  /// IGS-SSR group g (IDF002): messages 20 g + 1 ... 20 g + 7.
  int igs_group;
  /// RTCM satellite id and issue-of-data fields.
  SatelliteFieldBits rtcm_bits;
  /// IGS-SSR: 6-bit id, 8-bit IOD for every system (IDF011, IDF012); the PRN offset.
  int igs_prn_offset;
};
inline constexpr SsrSystemRow kSsrSystems[] = {
    {GnssSystem::GPS, 0, 1, {6, 8, 0, 0}, 0},       // DF068, DF071
    {GnssSystem::GLONASS, 1, 2, {5, 8, 0, 0}, 0},   // DF384, DF392
    {GnssSystem::Galileo, 2, 3, {6, 10, 0, 0}, 0},  // DF252, DF459 IODnav
    {GnssSystem::QZSS, 3, 4, {4, 8, 0, 0}, 0},      // DF249, DF460
    {GnssSystem::SBAS, 4, 6, {6, 9, 24, 20}, 19},   // DF?, t0 modulo 9 bits + IODCRC 24 bits
    // toe modulo 10 bits (in iod), then IOD 8 bits (in iod_aux); see satelliteFieldBits
    {GnssSystem::BeiDou, 5, 5, {6, 10, 8, 1}, 0},
};
inline const SsrSystemRow* ssrSystemRow(GnssSystem system) {
  for (const auto& row : kSsrSystems)
    if (row.system == system) return &row;
  return nullptr;
}
inline const SsrSystemRow* ssrSystemRow(int SsrSystemRow::*group, int value) {
  for (const auto& row : kSsrSystems)
    if (row.*group == value) return &row;
  return nullptr;
}

/// RTCM message type -> system and kind (nullopt: not an RTCM SSR type).
inline std::optional<TypeInfo> rtcmTypeInfo(int type) {
  static constexpr SsrMessageKind kinds[6] = {SsrMessageKind::Orbit, SsrMessageKind::Clock,
                                              SsrMessageKind::CodeBias, SsrMessageKind::Combined,
                                              SsrMessageKind::Ura, SsrMessageKind::HighRateClock};
  if (type == 1264) return TypeInfo{GnssSystem::GPS, SsrMessageKind::Vtec};
  if (type >= 1265 && type <= 1270)
    return TypeInfo{ssrSystemRow(&SsrSystemRow::rtcm_index, type - 1265)->system, SsrMessageKind::PhaseBias};
  int index = -1, k = 0;
  if (type >= 1057 && type <= 1068) {
    index = (type - 1057) / 6;
    k = (type - 1057) % 6;
  } else if (type >= 1240 && type <= 1263) {
    index = 2 + (type - 1240) / 6;
    k = (type - 1240) % 6;
  }
  if (index < 0) return std::nullopt;
  return TypeInfo{ssrSystemRow(&SsrSystemRow::rtcm_index, index)->system, kinds[k]};
}
inline int rtcmType(const TypeInfo& info) {
  if (info.kind == SsrMessageKind::Vtec) return 1264;
  const SsrSystemRow* row = ssrSystemRow(info.system);
  if (row == nullptr) return 0;
  const int sys_index = row->rtcm_index;
  if (info.kind == SsrMessageKind::PhaseBias) return 1265 + sys_index;
  int k = 0;
  switch (info.kind) {
    case SsrMessageKind::Orbit: k = 0; break;
    case SsrMessageKind::Clock: k = 1; break;
    case SsrMessageKind::CodeBias: k = 2; break;
    case SsrMessageKind::Combined: k = 3; break;
    case SsrMessageKind::Ura: k = 4; break;
    case SsrMessageKind::HighRateClock: k = 5; break;
    default: return 0;
  }
  return sys_index < 2 ? 1057 + 6 * sys_index + k : 1240 + 6 * (sys_index - 2) + k;
}

/// IGS-SSR message number (IDF002) -> system and kind: GPS 21-27, GLONASS 41-47,
/// Galileo 61-67, QZSS 81-87, BeiDou 101-107, SBAS 121-127 (orbit, clock,
/// combined, high-rate clock, code bias, phase bias, URA), VTEC 201.
inline std::optional<TypeInfo> igsTypeInfo(int subtype) {
  if (subtype == 201) return TypeInfo{GnssSystem::GPS, SsrMessageKind::Vtec};
  static constexpr SsrMessageKind kinds[7] = {SsrMessageKind::Orbit, SsrMessageKind::Clock,
                                              SsrMessageKind::Combined, SsrMessageKind::HighRateClock,
                                              SsrMessageKind::CodeBias, SsrMessageKind::PhaseBias,
                                              SsrMessageKind::Ura};
  if (subtype < 21 || subtype > 127) return std::nullopt;
  const int group = subtype / 20, offset = subtype % 20;
  const SsrSystemRow* row = ssrSystemRow(&SsrSystemRow::igs_group, group);
  if (row == nullptr || offset < 1 || offset > 7) return std::nullopt;
  return TypeInfo{row->system, kinds[offset - 1]};
}
inline int igsSubtype(const TypeInfo& info) {
  if (info.kind == SsrMessageKind::Vtec) return 201;
  const SsrSystemRow* row = ssrSystemRow(info.system);
  if (row == nullptr) return 0;
  int k = 0;
  switch (info.kind) {
    case SsrMessageKind::Orbit: k = 1; break;
    case SsrMessageKind::Clock: k = 2; break;
    case SsrMessageKind::Combined: k = 3; break;
    case SsrMessageKind::HighRateClock: k = 4; break;
    case SsrMessageKind::CodeBias: k = 5; break;
    case SsrMessageKind::PhaseBias: k = 6; break;
    case SsrMessageKind::Ura: k = 7; break;
    default: return 0;
  }
  return 20 * row->igs_group + k;
}

/// `bds_rtklib`: the BeiDou layout of RTKLIB-derived encoders (Swift's
/// gnss-converters): toe modulo 10 bits + IODCRC 24 bits; the IGS streams
/// (BKG's encoder) send toe modulo 10 bits + IOD 8 bits (the table's row).
inline SatelliteFieldBits satelliteFieldBits(GnssSystem system, bool igs, bool bds_rtklib = false) {
  const SsrSystemRow* row = ssrSystemRow(system);
  if (igs) return SatelliteFieldBits{6, 8, 0, row != nullptr ? row->igs_prn_offset : 0};
  if (row == nullptr) return SatelliteFieldBits{6, 8, 0, 0};
  SatelliteFieldBits bits = row->rtcm_bits;
  if (bds_rtklib && system == GnssSystem::BeiDou) bits.iod_aux = 24;
  return bits;
}

/// Reading side: fields go from the bits into the values.
class Reader {
 public:
  explicit Reader(BitReader& r) : r_(r) {}
  static constexpr bool kReading = true;
  template <class T> void uint(int bits, T& v) { v = static_cast<T>(r_.u(bits)); }
  template <class T> void sint(int bits, T& v) { v = static_cast<T>(r_.s(bits)); }
  void flag(bool& v) { v = r_.flag(); }
  void scaled(int bits, double lsb, double& v) { v = static_cast<double>(r_.s(bits)) * lsb; }
  void uscaled(int bits, double lsb, double& v) { v = static_cast<double>(r_.u(bits)) * lsb; }
  bool ok() const { return r_.ok(); }
  std::size_t remainingBits() const { return r_.remainingBits(); }

 private:
  BitReader& r_;
};

/// Writing side: values go into the bits, rounded to the field's resolution;
/// a value that does not fit its field throws std::out_of_range naming the field.
class Writer {
 public:
  explicit Writer(BitWriter& w) : w_(w) {}
  static constexpr bool kReading = false;
  template <class T> void uint(int bits, T& v) {
    const auto u = static_cast<std::uint64_t>(v);
    if (v < 0 || !BitWriter::fits(u, bits)) throw std::out_of_range("SSR field of " + std::to_string(bits) + " bits: " + std::to_string(v));
    w_.putUnsigned(u, bits);
  }
  template <class T> void sint(int bits, T& v) { put(static_cast<std::int64_t>(v), bits); }
  void flag(bool& v) { w_.putFlag(v); }
  void scaled(int bits, double lsb, double& v) {
    if (!std::isfinite(v)) throw std::out_of_range("SSR field: non-finite value");
    put(static_cast<std::int64_t>(std::llround(v / lsb)), bits);
  }
  void uscaled(int bits, double lsb, double& v) {
    if (!std::isfinite(v) || v < 0) throw std::out_of_range("SSR field: negative or non-finite value");
    auto u = static_cast<std::uint64_t>(std::llround(v / lsb));
    uint(bits, u);
  }
  bool ok() const { return true; }
  std::size_t remainingBits() const { return 0; }

 private:
  void put(std::int64_t value, int bits) {
    if (!BitWriter::fitsSigned(value, bits))
      throw std::out_of_range("SSR field of " + std::to_string(bits) + " bits cannot hold " + std::to_string(value));
    w_.putSigned(value, bits);
  }
  BitWriter& w_;
};

/// A satellite id read from the stream that no SatelliteId can hold.
struct BadSatellite {
  int raw_id = 0;
};

template <class IO>
bool satelliteField(IO& io, const SatelliteFieldBits& bits, GnssSystem system, SatelliteId& sat, std::vector<BadSatellite>& bad) {
  int raw = 0;
  if constexpr (!IO::kReading) raw = sat.prn - bits.prn_offset;
  io.uint(bits.id, raw);
  if constexpr (IO::kReading) {
    sat.system = system;
    sat.prn = raw + bits.prn_offset;
    if (sat.prn < 1 || sat.prn > SatelliteId::maxPrn(system)) {
      bad.push_back(BadSatellite{raw});
      return false;
    }
  }
  return true;
}

template <class IO>
void orbitFields(IO& io, const SatelliteFieldBits& bits, SsrOrbitCorrection& o) {
  io.uint(bits.iod, o.iod);
  if (bits.iod_aux > 0) {
    std::uint32_t aux = o.iod_aux.value_or(0);
    io.uint(bits.iod_aux, aux);
    if constexpr (IO::kReading) o.iod_aux = aux;
  }
  io.scaled(22, 1e-4, o.radial_m);         // DF365 0.1 mm
  io.scaled(20, 4e-4, o.along_m);          // DF366 0.4 mm
  io.scaled(20, 4e-4, o.cross_m);          // DF367 0.4 mm
  io.scaled(21, 1e-6, o.radial_dot_mps);   // DF368 0.001 mm/s
  io.scaled(19, 4e-6, o.along_dot_mps);    // DF369 0.004 mm/s
  io.scaled(19, 4e-6, o.cross_dot_mps);    // DF370 0.004 mm/s
}

template <class IO>
void clockFields(IO& io, SsrClockCorrection& c) {
  io.scaled(22, 1e-4, c.c0_m);        // DF376 0.1 mm
  io.scaled(21, 1e-6, c.c1_m_per_s);  // DF377 0.001 mm/s
  io.scaled(27, 2e-8, c.c2_m_per_s2); // DF378 0.00002 mm/s^2
}

/// The number of satellites of a message's kind (writing side).
inline int satelliteCount(const SsrMessage& m) {
  switch (m.header.kind) {
    case SsrMessageKind::Orbit: return static_cast<int>(m.orbits.size());
    case SsrMessageKind::Clock: return static_cast<int>(m.clocks.size());
    case SsrMessageKind::Combined: return static_cast<int>(m.orbits.size());
    case SsrMessageKind::CodeBias: return static_cast<int>(m.code_biases.size());
    case SsrMessageKind::PhaseBias: return static_cast<int>(m.phase_biases.size());
    case SsrMessageKind::Ura: return static_cast<int>(m.uras.size());
    case SsrMessageKind::HighRateClock: return static_cast<int>(m.high_rate_clocks.size());
    case SsrMessageKind::Vtec: break;
  }
  return 0;
}

/// Satellite i of an orbit or a combined message (reading: appended when good).
template <class IO>
void orbitBlock(IO& io, SsrMessage& m, int i, const SatelliteFieldBits& bits, std::vector<BadSatellite>& bad) {
  const GnssSystem sys = m.header.system;
  const bool combined = m.header.kind == SsrMessageKind::Combined;
  SatelliteId sat;
  SsrOrbitCorrection o;
  SsrClockCorrection c;
  if constexpr (!IO::kReading) { o = m.orbits[i]; sat = o.satellite; if (combined) c = m.clocks[i]; }
  const bool good = satelliteField(io, bits, sys, sat, bad);
  orbitFields(io, bits, o);
  if (combined) clockFields(io, c);
  if constexpr (IO::kReading) {
    if (good && io.ok()) {
      o.satellite = c.satellite = sat;
      m.orbits.push_back(o);
      if (combined) m.clocks.push_back(c);
    }
  }
}

template <class IO>
void clockBlock(IO& io, SsrMessage& m, int i, const SatelliteFieldBits& bits, std::vector<BadSatellite>& bad) {
  SatelliteId sat;
  SsrClockCorrection c;
  if constexpr (!IO::kReading) { c = m.clocks[i]; sat = c.satellite; }
  const bool good = satelliteField(io, bits, m.header.system, sat, bad);
  clockFields(io, c);
  if constexpr (IO::kReading) if (good && io.ok()) { c.satellite = sat; m.clocks.push_back(c); }
}

template <class IO>
void highRateClockBlock(IO& io, SsrMessage& m, int i, const SatelliteFieldBits& bits, std::vector<BadSatellite>& bad) {
  SatelliteId sat;
  SsrHighRateClock h;
  if constexpr (!IO::kReading) { h = m.high_rate_clocks[i]; sat = h.satellite; }
  const bool good = satelliteField(io, bits, m.header.system, sat, bad);
  io.scaled(22, 1e-4, h.clock_m);  // DF404 0.1 mm
  if constexpr (IO::kReading) if (good && io.ok()) { h.satellite = sat; m.high_rate_clocks.push_back(h); }
}

template <class IO>
void uraBlock(IO& io, SsrMessage& m, int i, const SatelliteFieldBits& bits, std::vector<BadSatellite>& bad) {
  SatelliteId sat;
  SsrUra u;
  if constexpr (!IO::kReading) { u = m.uras[i]; sat = u.satellite; }
  const bool good = satelliteField(io, bits, m.header.system, sat, bad);
  io.uint(3, u.ura_class);  // DF389 bits 5-3
  io.uint(3, u.ura_value);  // DF389 bits 2-0
  if constexpr (IO::kReading) {
    const int code = u.ura_class * 8 + u.ura_value;
    if (code > 0 && code < 63) u.ura_m = (std::pow(3.0, u.ura_class) * (1.0 + u.ura_value / 4.0) - 1.0) * 1e-3;
    if (good && io.ok()) { u.satellite = sat; m.uras.push_back(u); }
  }
}

template <class IO>
void codeBiasBlock(IO& io, SsrMessage& m, int i, const SatelliteFieldBits& bits, std::vector<BadSatellite>& bad,
                   bool igs) {
  const GnssSystem sys = m.header.system;
  SatelliteId sat;
  SsrCodeBias b;
  if constexpr (!IO::kReading) { b = m.code_biases[i]; sat = b.satellite; }
  const bool good = satelliteField(io, bits, sys, sat, bad);
  int nbias = static_cast<int>(b.biases.size());
  io.uint(5, nbias);  // DF379
  for (int k = 0; k < nbias && io.ok(); ++k) {
    SsrSignalCodeBias s;
    if constexpr (!IO::kReading) s = b.biases[k];
    io.uint(5, s.signal_id);         // DF380
    io.scaled(14, 0.01, s.bias_m);   // DF383 0.01 m
    if constexpr (IO::kReading) { s.code = ssrSignalCode(sys, s.signal_id, igs); b.biases.push_back(s); }
  }
  if constexpr (IO::kReading) if (good && io.ok()) { b.satellite = sat; m.code_biases.push_back(b); }
}

template <class IO>
void phaseBiasBlock(IO& io, SsrMessage& m, int i, const SatelliteFieldBits& bits, std::vector<BadSatellite>& bad,
                    bool igs) {
  const GnssSystem sys = m.header.system;
  SatelliteId sat;
  SsrPhaseBias p;
  if constexpr (!IO::kReading) { p = m.phase_biases[i]; sat = p.satellite; }
  const bool good = satelliteField(io, bits, sys, sat, bad);
  int nbias = static_cast<int>(p.biases.size());
  io.uint(5, nbias);
  io.uscaled(9, kSemicircle_rad / 256.0, p.yaw_rad);               // DF480 1/256 semicircle
  io.scaled(8, kSemicircle_rad / 8192.0, p.yaw_rate_rad_per_s);    // DF481 1/8192 semicircle/s
  for (int k = 0; k < nbias && io.ok(); ++k) {
    SsrSignalPhaseBias s;
    if constexpr (!IO::kReading) s = p.biases[k];
    io.uint(5, s.signal_id);
    io.flag(s.integer);                 // DF483
    io.uint(2, s.widelane_integer);     // DF484
    io.uint(4, s.discontinuity_counter);// DF485
    io.scaled(20, 1e-4, s.bias_m);      // DF482 0.1 mm
    if constexpr (IO::kReading) { s.code = ssrSignalCode(sys, s.signal_id, igs); p.biases.push_back(s); }
  }
  if constexpr (IO::kReading) if (good && io.ok()) { p.satellite = sat; m.phase_biases.push_back(p); }
}

/// The satellites' part of a message (after the header), for every kind but VTEC:
/// the satellite count, then one block per satellite of the message's kind.
template <class IO>
void satelliteBlocks(IO& io, SsrMessage& m, bool igs, std::vector<BadSatellite>& bad, bool bds_rtklib = false) {
  const SatelliteFieldBits bits = satelliteFieldBits(m.header.system, igs, bds_rtklib);
  int nsat = satelliteCount(m);
  if constexpr (!IO::kReading) {
    if (m.header.kind == SsrMessageKind::Combined && m.clocks.size() != m.orbits.size())
      throw std::invalid_argument("combined SSR message: as many clocks as orbits needed");
  }
  io.uint(6, nsat);  // DF387 / IDF010
  for (int i = 0; i < nsat && io.ok(); ++i) {
    switch (m.header.kind) {
      case SsrMessageKind::Orbit:
      case SsrMessageKind::Combined: orbitBlock(io, m, i, bits, bad); break;
      case SsrMessageKind::Clock: clockBlock(io, m, i, bits, bad); break;
      case SsrMessageKind::HighRateClock: highRateClockBlock(io, m, i, bits, bad); break;
      case SsrMessageKind::Ura: uraBlock(io, m, i, bits, bad); break;
      case SsrMessageKind::CodeBias: codeBiasBlock(io, m, i, bits, bad, igs); break;
      case SsrMessageKind::PhaseBias: phaseBiasBlock(io, m, i, bits, bad, igs); break;
      case SsrMessageKind::Vtec: break;
    }
  }
}

/// VTEC block after the common header (DF478, DF472-DF477 / IDF041, IDF035-IDF040).
template <class IO>
void vtecBlock(IO& io, SsrMessage& m) {
  if constexpr (IO::kReading) m.vtec = SsrVtec{};
  SsrVtec& v = *m.vtec;
  io.uscaled(9, 0.05, v.quality_tecu);
  int nlayers = static_cast<int>(v.layers.size()) - 1;
  io.uint(2, nlayers);
  if constexpr (IO::kReading) v.layers.resize(static_cast<std::size_t>(nlayers + 1));
  for (auto& layer : v.layers) {
    io.uscaled(8, 10000.0, layer.height_m);
    int degree = layer.degree - 1, order = layer.order - 1;
    io.uint(4, degree);
    io.uint(4, order);
    layer.degree = degree + 1;
    layer.order = order + 1;
    std::size_t ncos = 0, nsin = 0;
    for (int n = 0; n <= layer.degree; ++n)
      for (int k = 0; k <= std::min(n, layer.order); ++k) { ++ncos; if (k > 0) ++nsin; }
    if constexpr (IO::kReading) { layer.cosine_tecu.resize(ncos); layer.sine_tecu.resize(nsin); }
    for (auto& c : layer.cosine_tecu) io.scaled(16, 0.005, c);
    for (auto& s : layer.sine_tecu) io.scaled(16, 0.005, s);
    if (!io.ok()) return;
  }
}

/// Header after the message number (and, IGS-SSR, after version and subtype).
template <class IO>
void header(IO& io, SsrMessage& m, bool igs) {
  SsrHeader& h = m.header;
  const bool glonass_tod = !igs && h.system == GnssSystem::GLONASS && h.kind != SsrMessageKind::Vtec;
  io.uint(glonass_tod ? 17 : 20, h.epoch_time_s);  // DF386 / DF385 / IDF003
  io.uint(4, h.update_interval_code);               // DF391
  io.flag(h.multiple_message);                      // DF388
  if (h.kind == SsrMessageKind::Orbit || h.kind == SsrMessageKind::Combined) {
    bool regional = h.datum_regional.value_or(false);
    io.flag(regional);                              // DF375
    if constexpr (IO::kReading) h.datum_regional = regional;
  }
  io.uint(4, h.iod_ssr);       // DF413
  io.uint(16, h.provider_id);  // DF414
  io.uint(4, h.solution_id);   // DF415
  if constexpr (IO::kReading) h.update_interval_s = ssrUpdateInterval_s(h.update_interval_code);
  if (h.kind == SsrMessageKind::PhaseBias) {
    io.flag(m.dispersive_consistent);  // DF486
    io.flag(m.mw_consistent);          // DF487
  }
}

}  // namespace ppp::ssr_layout
