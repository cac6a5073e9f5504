#include "ppp_bayes_tree/io/ubx/ubx_decoder.h"

#include <array>
#include <cmath>
#include <cstring>
#include <string>

#include "ppp_bayes_tree/io/crc24q.h"  // Galileo I/NAV pages
#include "ppp_bayes_tree/types/broadcast_accuracy.h"
#include "ubx_nav_layout.h"

namespace ppp {
namespace {

constexpr int kGnssGps = 0, kGnssSbas = 1, kGnssGalileo = 2, kGnssBeidou = 3, kGnssQzss = 5, kGnssGlonass = 6,
              kGnssNavic = 7;

// Little-endian fields (UBX is little-endian: interface description 3.3).
std::uint16_t u2(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t u4(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
float r4(const std::uint8_t* p) {
  const std::uint32_t bits = u4(p);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
double r8(const std::uint8_t* p) {
  const std::uint64_t bits = static_cast<std::uint64_t>(u4(p)) | (static_cast<std::uint64_t>(u4(p + 4)) << 32);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// MSB-first bit fields of a byte array.
std::uint64_t bitsU(const std::uint8_t* data, std::size_t start, int count) {
  std::uint64_t value = 0;
  for (int i = 0; i < count; ++i) {
    const std::size_t bit = start + static_cast<std::size_t>(i);
    value = (value << 1) | ((data[bit / 8] >> (7 - bit % 8)) & 1u);
  }
  return value;
}
std::int64_t bitsS(const std::uint8_t* data, std::size_t start, int count) {
  const std::uint64_t u = bitsU(data, start, count);
  const std::uint64_t sign = std::uint64_t{1} << (count - 1);
  return (u & sign) ? static_cast<std::int64_t>(u) - static_cast<std::int64_t>(sign << 1) : static_cast<std::int64_t>(u);
}
void setBit(std::uint8_t* data, std::size_t bit, bool value) {
  if (value) data[bit / 8] = static_cast<std::uint8_t>(data[bit / 8] | (0x80u >> (bit % 8)));
}

bool knownClass(int message_class) {
  switch (message_class) {
    case 0x01: case 0x02: case 0x04: case 0x05: case 0x06: case 0x09: case 0x0A: case 0x0B:
    case 0x0D: case 0x10: case 0x13: case 0x21: case 0x27: case 0x28:
      return true;
    default:
      return false;
  }
}

// Curve-fit interval [h] from the fit interval flag and IODC (IS-GPS-200 20.3.4.4, table 20-XII).
double gpsFitIntervalHours(int flag, int iodc) {
  if (flag == 0) return 4.0;
  if (iodc >= 240 && iodc <= 247) return 8.0;
  if ((iodc >= 248 && iodc <= 255) || iodc == 496) return 14.0;
  if (iodc >= 497 && iodc <= 503) return 26.0;
  if (iodc >= 504 && iodc <= 510) return 50.0;
  if (iodc == 511 || (iodc >= 752 && iodc <= 756)) return 74.0;
  if (iodc >= 757 && iodc <= 763) return 98.0;
  if ((iodc >= 764 && iodc <= 767) || (iodc >= 1008 && iodc <= 1010)) return 122.0;
  if (iodc >= 1011 && iodc <= 1020) return 146.0;
  return 6.0;
}

int resolveWeek(int truncated, int modulus, int reference) {
  const double k = std::round(static_cast<double>(reference - truncated) / modulus);
  return truncated + modulus * static_cast<int>(k);
}

}  // namespace

std::optional<ObservationCode> ubxSignalCode(int gnss_id, int sig_id) {
  auto code = [](char band, char attribute) {
    return std::optional<ObservationCode>(ObservationCode{ObservableType::Pseudorange, band, attribute});
  };
  switch (gnss_id) {
    case kGnssGps:
      switch (sig_id) {
        case 0: return code('1', 'C');
        case 3: return code('2', 'L');
        case 4: return code('2', 'S');
        case 6: return code('5', 'I');
        case 7: return code('5', 'Q');
      }
      break;
    case kGnssSbas:
      if (sig_id == 0) return code('1', 'C');
      break;
    case kGnssGalileo:
      switch (sig_id) {
        case 0: return code('1', 'C');
        case 1: return code('1', 'B');
        case 3: return code('5', 'I');
        case 4: return code('5', 'Q');
        case 5: return code('7', 'I');
        case 6: return code('7', 'Q');
        case 8: return code('6', 'B');
        case 9: return code('6', 'C');
        case 10: return code('6', 'A');
      }
      break;
    case kGnssBeidou:
      switch (sig_id) {
        case 0: case 1: return code('2', 'I');
        case 2: case 3: return code('7', 'I');
        case 4: case 10: return code('6', 'I');
        case 5: return code('1', 'P');
        case 6: return code('1', 'D');
        case 7: return code('5', 'P');
        case 8: return code('5', 'D');
      }
      break;
    case kGnssQzss:
      switch (sig_id) {
        case 0: return code('1', 'C');
        case 1: return code('1', 'Z');
        case 4: return code('2', 'S');
        case 5: return code('2', 'L');
        case 8: return code('5', 'I');
        case 9: return code('5', 'Q');
      }
      break;
    case kGnssGlonass:
      if (sig_id == 0) return code('1', 'C');
      if (sig_id == 2) return code('2', 'C');
      break;
    case kGnssNavic:
      if (sig_id == 0) return code('5', 'A');
      break;
  }
  return std::nullopt;
}

std::optional<SatelliteId> ubxSatellite(int gnss_id, int sv_id) {
  SatelliteId sat;
  switch (gnss_id) {
    case kGnssGps: sat = {GnssSystem::GPS, sv_id}; break;
    case kGnssSbas: sat = {GnssSystem::SBAS, sv_id - 100}; break;  // svId 120..158 -> S20..S58
    case kGnssGalileo: sat = {GnssSystem::Galileo, sv_id}; break;
    case kGnssBeidou: sat = {GnssSystem::BeiDou, sv_id}; break;
    case kGnssQzss: sat = {GnssSystem::QZSS, sv_id}; break;  // svId 1..10 = PRN 193..202
    case kGnssGlonass: sat = {GnssSystem::GLONASS, sv_id}; break;
    case kGnssNavic: sat = {GnssSystem::IRNSS, sv_id}; break;
    default: return std::nullopt;
  }
  if (sat.prn < 1 || sat.prn > SatelliteId::maxPrn(sat.system)) return std::nullopt;
  return sat;
}

void UbxDecoder::problem(const UbxFrame& frame, StreamProblemKind kind, std::string detail) {
  framer_.counters().add(
      StreamProblem{kind, frame.byte_offset, frame.frame_index, frame.messageType(), std::move(detail)});
}

void UbxDecoder::feed(const std::uint8_t* data, std::size_t size, const Handlers& handlers) {
  framer_.feed(data, size, [&](const UbxFrame& f) { frame(f, handlers); });
}

void UbxDecoder::frame(const UbxFrame& f, const Handlers& handlers) {
  const int type = f.messageType();
  if (type == 0x0215) {
    rawx(f, handlers);
  } else if (type == 0x0213) {
    sfrbx(f, handlers);
  } else if (knownClass(f.message_class)) {
    ++statistics_.known_not_used;
  } else {
    problem(f, StreamProblemKind::UnknownMessage, "UBX class/id " + ubxTypeText(type) + " is not a UBX class we know");
  }
}

void UbxDecoder::rawx(const UbxFrame& f, const Handlers& handlers) {
  const std::vector<std::uint8_t>& p = f.payload;
  if (p.size() < 16) {
    problem(f, StreamProblemKind::MalformedMessage, "RXM-RAWX of " + std::to_string(p.size()) + " bytes (at least 16)");
    return;
  }
  const double tow_s = r8(p.data());
  const int week = u2(p.data() + 8);
  const int leap_s = static_cast<std::int8_t>(p[10]);
  const int count = p[11];
  const int status = p[12];
  if (p.size() < 16u + 32u * static_cast<std::size_t>(count)) {
    problem(f, StreamProblemKind::MalformedMessage,
            "RXM-RAWX of " + std::to_string(p.size()) + " bytes for " + std::to_string(count) + " measurements");
    return;
  }
  if (!std::isfinite(tow_s) || tow_s < 0.0 || tow_s >= 604800.0) {
    problem(f, StreamProblemKind::MalformedMessage, "RXM-RAWX rcvTow " + std::to_string(tow_s) + " s out of a week");
    return;
  }
  if (week == 0) {
    problem(f, StreamProblemKind::UnresolvedTime, "RXM-RAWX week 0: the receiver does not know the week yet");
    return;
  }
  week_ = week;
  UbxObservationEpoch epoch;
  epoch.time = GnssTime::fromGpsWeek(week, tow_s);
  if (status & 0x01) epoch.leap_seconds = leap_s;
  epoch.clock_reset = (status & 0x02) != 0;
  epoch.byte_offset = f.byte_offset;
  epoch.frame_index = f.frame_index;
  // The same epoch sent again is dropped here (it would count its lock times twice);
  // any other time order is the stream's epoch-time policy (io/epoch_time_screen.h),
  // so that one epoch with a bad week does not decide the time of the next ones.
  if (last_time_ && epoch.time == *last_time_) {
    problem(f, StreamProblemKind::MalformedMessage,
            "RXM-RAWX time " + epoch.time.toString() + " repeats the previous epoch: epoch dropped");
    return;
  }
  last_time_ = epoch.time;
  epoch.measurements.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    if (auto m = rawxMeasurement(p.data() + 16 + 32 * i)) epoch.measurements.push_back(*m);
  }
  statistics_.measurements += epoch.measurements.size();
  ++statistics_.observation_epochs;
  if (handlers.on_epoch) handlers.on_epoch(epoch);
}

std::optional<UbxSignalMeasurement> UbxDecoder::rawxMeasurement(const std::uint8_t* m) {
  const int gnss = m[20], sv = m[21], sig = m[22], freq = m[23];
  const auto sat = ubxSatellite(gnss, sv);
  const auto code = ubxSignalCode(gnss, sig);
  if (!sat || !code) {
    ++statistics_.unmapped_signals[{gnss, sig}];
    return std::nullopt;
  }
  const double pr = r8(m);
  const double cp = r8(m + 8);
  const int lock_ms = u2(m + 24);
  const int cp_stdev = m[28] & 0x0F;
  const int trk = m[30];
  UbxSignalMeasurement out;
  out.satellite = *sat;
  out.signal = *code;
  out.gnss_id = gnss;
  out.sv_id = sv;
  out.sig_id = sig;
  if ((trk & 0x01) && std::isfinite(pr)) out.pseudorange_m = pr;
  if ((trk & 0x02) && std::isfinite(cp) && cp != -0.5 && cp_stdev <= options_.max_phase_stdev_index) {
    out.carrier_phase_cycles = cp;
  }
  const double doppler = r4(m + 16);
  out.doppler_hz = std::isfinite(doppler) ? doppler : 0.0;
  out.cn0_dbhz = m[26];
  out.lock_time_s = lock_ms * 1e-3;
  out.tracking_status = static_cast<std::uint8_t>(trk);
  if (gnss == kGnssGlonass) out.glonass_channel = freq - 7;
  // Loss of lock: lock time restarted or shorter, or the half-cycle state changed;
  // reported with the next phase.
  const bool half_valid = (trk & 0x04) != 0;
  const bool half_subtracted = (trk & 0x08) != 0;
  const auto [lock_it, first_sight] = lock_.try_emplace({*sat, sig});
  LockState& lock = lock_it->second;
  const bool slip = lock_ms == 0 || out.lock_time_s < lock.lock_time_s || half_subtracted != lock.half_cycle_subtracted;
  lock.lock_time_s = out.lock_time_s;
  lock.half_cycle_subtracted = half_subtracted;
  lock.pending_loss_of_lock = lock.pending_loss_of_lock || slip;
  out.lli = static_cast<std::uint8_t>((first_sight || lock.pending_loss_of_lock ? kLliLossOfLock : 0) |
                                      (half_valid ? 0 : kLliHalfCycle));
  if (out.carrier_phase_cycles) lock.pending_loss_of_lock = false;
  return out;
}

void UbxDecoder::sfrbx(const UbxFrame& f, const Handlers& handlers) {
  const std::vector<std::uint8_t>& p = f.payload;
  if (p.size() < 8) {
    problem(f, StreamProblemKind::MalformedMessage, "RXM-SFRBX of " + std::to_string(p.size()) + " bytes (at least 8)");
    return;
  }
  const int gnss = p[0], sv = p[1], sig = p[2], words = p[4];
  if (p.size() < 8u + 4u * static_cast<std::size_t>(words)) {
    problem(f, StreamProblemKind::MalformedMessage,
            "RXM-SFRBX of " + std::to_string(p.size()) + " bytes for " + std::to_string(words) + " words");
    return;
  }
  ++statistics_.navigation_words[{gnss, sig}];
  const auto sat = ubxSatellite(gnss, sv);
  const bool lnav_signal = (gnss == kGnssGps || gnss == kGnssQzss) && sig == 0 && words >= 10;
  // sigId 0 only on u-blox M8 (reserved there, E1-B the only data signal); 1 E1-B, 5 E5b-I.
  const bool inav_signal = gnss == kGnssGalileo && (sig == 0 || sig == 1 || sig == 5) && words >= 8;
  // GLONASS L1OF / L2OF strings; BeiDou B1I / B2I D1 and D2.
  const bool glonass_signal = gnss == kGnssGlonass && (sig == 0 || sig == 2) && words >= 4;
  const bool beidou_signal = gnss == kGnssBeidou && sig >= 0 && sig <= 3 && words >= 10;
  if (!sat || !(lnav_signal || inav_signal || glonass_signal || beidou_signal)) {
    ++statistics_.navigation_not_decoded[{gnss, sig}];
    return;
  }
  if (lnav_signal) lnav(f, *sat, handlers);
  else if (inav_signal) inav(f, *sat, handlers);
  else if (glonass_signal) glonassString(f, *sat, handlers);
  else beidouSubframe(f, *sat, handlers);
}

namespace {

/// The 300 bits of each of LNAV subframes 1-3, IS-GPS-200 bit n at index n-1.
using LnavSubframes = std::array<std::array<std::uint8_t, 38>, 3>;

LnavSubframes lnavSubframes(const std::optional<std::uint32_t> (&words)[3][10]) {
  LnavSubframes sf{};
  for (int s = 0; s < 3; ++s) {
    for (int w = 0; w < 10; ++w) {
      for (int b = 0; b < 30; ++b) setBit(sf[s].data(), 30 * w + b, ((*words[s][w] >> (29 - b)) & 1u) != 0);
    }
  }
  return sf;
}

/// The fields of LNAV subframes 1-3 by subframe (0-2) and IS-GPS-200 bit number.
class LnavFields {
 public:
  explicit LnavFields(const LnavSubframes& sf) : sf_(sf) {}
  std::uint64_t U(int s, int n, int len) const { return bitsU(sf_[s].data(), n - 1, len); }
  double S(int s, int n, int len) const { return static_cast<double>(bitsS(sf_[s].data(), n - 1, len)); }
  /// A 32-bit field split into 8 MSBs at n1 and 24 LSBs at n2.
  double U32(int s, int n1, int n2) const { return static_cast<double>((U(s, n1, 8) << 24) | U(s, n2, 24)); }
  double S32(int s, int n1, int n2) const {
    return static_cast<double>(static_cast<std::int32_t>(static_cast<std::uint32_t>((U(s, n1, 8) << 24) | U(s, n2, 24))));
  }
  int iodc() const { return static_cast<int>((U(0, 83, 2) << 8) | U(0, 211, 8)); }
  int iode2() const { return static_cast<int>(U(1, 61, 8)); }
  int iode3() const { return static_cast<int>(U(2, 271, 8)); }

 private:
  const LnavSubframes& sf_;
};

/// The orbit of subframes 2 and 3 (IS-GPS-200 table 20-III), without its epoch.
KeplerOrbit lnavOrbit(const LnavFields& f) {
  KeplerOrbit o;
  o.crs_m = f.S(1, 69, 16) * std::ldexp(1.0, -5);
  o.delta_n_radps = f.S(1, 91, 16) * std::ldexp(1.0, -43) * kIcdPi;
  o.m0_rad = f.S32(1, 107, 121) * std::ldexp(1.0, -31) * kIcdPi;
  o.cuc_rad = f.S(1, 151, 16) * std::ldexp(1.0, -29);
  o.eccentricity = f.U32(1, 167, 181) * std::ldexp(1.0, -33);
  o.cus_rad = f.S(1, 211, 16) * std::ldexp(1.0, -29);
  o.sqrt_a_sqrtm = f.U32(1, 227, 241) * std::ldexp(1.0, -19);
  o.toe_sow = static_cast<double>(f.U(1, 271, 16)) * 16.0;
  o.cic_rad = f.S(2, 61, 16) * std::ldexp(1.0, -29);
  o.omega0_rad = f.S32(2, 77, 91) * std::ldexp(1.0, -31) * kIcdPi;
  o.cis_rad = f.S(2, 121, 16) * std::ldexp(1.0, -29);
  o.i0_rad = f.S32(2, 137, 151) * std::ldexp(1.0, -31) * kIcdPi;
  o.crc_m = f.S(2, 181, 16) * std::ldexp(1.0, -5);
  o.omega_rad = f.S32(2, 197, 211) * std::ldexp(1.0, -31) * kIcdPi;
  o.omega_dot_radps = f.S(2, 241, 24) * std::ldexp(1.0, -43) * kIcdPi;
  o.idot_radps = f.S(2, 279, 14) * std::ldexp(1.0, -43) * kIcdPi;
  return o;
}

/// The ephemeris of subframes 1-3 whose subframe 1 began at HOW count tow_count0;
/// the 10-bit week resolved with the receiver week.
GpsLnavEphemeris lnavEphemeris(const SatelliteId& sat, const LnavFields& f, int receiver_week, int tow_count0) {
  GpsLnavEphemeris eph;
  eph.satellite = sat;
  const int week = resolveWeek(static_cast<int>(f.U(0, 61, 10)), 1024, receiver_week);
  eph.codes_on_l2 = static_cast<int>(f.U(0, 71, 2));
  eph.ura_m = gpsUra_m(static_cast<int>(f.U(0, 73, 4)));
  eph.health = static_cast<int>(f.U(0, 77, 6));
  eph.l2p_data_flag = static_cast<int>(f.U(0, 91, 1));
  eph.tgd_s = f.S(0, 197, 8) * std::ldexp(1.0, -31);
  eph.iodc = f.iodc();
  eph.iode = f.iode2();
  const double toc_sow = static_cast<double>(f.U(0, 219, 16)) * 16.0;
  eph.clock.af2_sps2 = f.S(0, 241, 8) * std::ldexp(1.0, -55);
  eph.clock.af1_sps = f.S(0, 249, 16) * std::ldexp(1.0, -43);
  eph.clock.af0_s = f.S(0, 271, 22) * std::ldexp(1.0, -31);
  eph.orbit = lnavOrbit(f);
  eph.fit_interval_h = gpsFitIntervalHours(static_cast<int>(f.U(1, 287, 1)), eph.iodc);
  // Transmission: the start of subframe 1 (its HOW count gives the start of subframe 2).
  const GnssTime transmission = GnssTime::fromGpsWeek(week, 0.0) + (tow_count0 - 1) * 6.0;
  eph.transmission_sow = transmission.gpsWeek().seconds_of_week;
  eph.orbit.toe = nearestSecondsOfWeek(transmission, eph.orbit.toe_sow);
  eph.clock.toc = nearestSecondsOfWeek(transmission, toc_sow);
  eph.week = eph.orbit.toe.gpsWeek().week;
  return eph;
}

}  // namespace

void UbxDecoder::lnav(const UbxFrame& f, const SatelliteId& sat, const Handlers& handlers) {
  // 1. The ten words: the preamble, the subframe id; almanac pages are not used.
  std::array<std::uint32_t, 10> words{};
  for (int i = 0; i < 10; ++i) words[i] = u4(f.payload.data() + 8 + 4 * i) & 0x3FFFFFFFu;
  if (((words[0] >> 22) & 0xFFu) != 0x8Bu) {
    problem(f, StreamProblemKind::MalformedMessage, sat.toString() + " LNAV word 1 without the preamble 0x8B");
    return;
  }
  const int id = static_cast<int>((words[1] >> 8) & 0x7u);
  const int tow_count = static_cast<int>((words[1] >> 13) & 0x1FFFFu);
  if (id < 1 || id > 5) {
    problem(f, StreamProblemKind::MalformedMessage, sat.toString() + " LNAV subframe id " + std::to_string(id));
    return;
  }
  if (id > 3) return;  // almanac / ionosphere / UTC pages: not used
  // 2. Subframes 1-3 of one frame: consecutive HOW TOW counts (6 s each).
  LnavFrame& frame = lnav_[sat];
  for (int i = 0; i < 10; ++i) frame.words[id - 1][i] = words[i];
  frame.tow_count[id - 1] = tow_count;
  if (id != 3) return;
  if (frame.tow_count[0] < 0 || frame.tow_count[1] != frame.tow_count[0] + 1 ||
      frame.tow_count[2] != frame.tow_count[0] + 2) {
    return;
  }
  // 3. One issue of data in all three; a known week.
  const LnavSubframes sf = lnavSubframes(frame.words);
  const LnavFields fields(sf);
  const int iodc = fields.iodc(), iode2 = fields.iode2(), iode3 = fields.iode3();
  if (iode2 != iode3 || iode2 != (iodc & 0xFF)) {
    problem(f, StreamProblemKind::InconsistentEphemeris,
            sat.toString() + " LNAV frame with IODC " + std::to_string(iodc) + ", IODE " + std::to_string(iode2) +
                " (subframe 2) and " + std::to_string(iode3) + " (subframe 3): not used");
    return;
  }
  if (!week_) {
    problem(f, StreamProblemKind::UnresolvedTime,
            sat.toString() + " LNAV ephemeris before any RXM-RAWX week: the 10-bit week cannot be resolved");
    return;
  }
  // 4. The ephemeris, passed on once per issue and epoch.
  const GpsLnavEphemeris eph = lnavEphemeris(sat, fields, *week_, frame.tow_count[0]);
  const auto last = last_gps_.find(sat);
  if (last != last_gps_.end() && last->second.first == iodc && last->second.second == eph.orbit.toe) return;
  last_gps_[sat] = {iodc, eph.orbit.toe};
  ++statistics_.gps_ephemerides;
  if (handlers.on_gps) handlers.on_gps(eph);
}

namespace {

/// The page of an I/NAV RXM-SFRBX: words 0-3 the even half, 4-7 the odd half, each
/// word's first bit its MSB.
std::array<std::uint8_t, 32> inavPage(const UbxFrame& f) {
  std::array<std::uint8_t, 32> page{};
  for (int i = 0; i < 8; ++i) {
    const std::uint32_t w = u4(f.payload.data() + 8 + 4 * i);
    for (int j = 0; j < 4; ++j) page[4 * i + j] = static_cast<std::uint8_t>(w >> (24 - 8 * j));
  }
  return page;
}

/// CRC-24Q over even bits 0-113 and odd bits 0-81 (196 bits, 4 leading zero bits
/// make 25 bytes; OS SIS ICD 4.3.2.1), against odd bits 82-105.
bool inavCrcOk(const std::uint8_t* even, const std::uint8_t* odd) {
  std::array<std::uint8_t, 25> crc_input{};
  std::size_t at = 4;
  for (std::size_t i = 0; i < 114; ++i) setBit(crc_input.data(), at++, bitsU(even, i, 1) != 0);
  for (std::size_t i = 0; i < 82; ++i) setBit(crc_input.data(), at++, bitsU(odd, i, 1) != 0);
  return crc24q(crc_input.data(), crc_input.size()) == bitsU(odd, 82, 24);
}

/// The 128-bit word: even data bits 2-113, odd data bits 2-17.
std::vector<std::uint8_t> inavWord(const std::uint8_t* even, const std::uint8_t* odd) {
  std::vector<std::uint8_t> word(16, 0);
  for (std::size_t i = 0; i < 112; ++i) setBit(word.data(), i, bitsU(even, 2 + i, 1) != 0);
  for (std::size_t i = 0; i < 16; ++i) setBit(word.data(), 112 + i, bitsU(odd, 2 + i, 1) != 0);
  return word;
}

double inavS(const std::uint8_t* w, int start, int len) { return static_cast<double>(bitsS(w, start, len)); }
double inavU(const std::uint8_t* w, int start, int len) { return static_cast<double>(bitsU(w, start, len)); }

/// The orbit of I/NAV words 1-4 (OS SIS ICD 4.3.5), without its epoch.
KeplerOrbit inavOrbit(const std::uint8_t* w1, const std::uint8_t* w2, const std::uint8_t* w3, const std::uint8_t* w4) {
  KeplerOrbit o;
  o.toe_sow = inavU(w1, 16, 14) * 60.0;
  o.m0_rad = inavS(w1, 30, 32) * std::ldexp(1.0, -31) * kIcdPi;
  o.eccentricity = inavU(w1, 62, 32) * std::ldexp(1.0, -33);
  o.sqrt_a_sqrtm = inavU(w1, 94, 32) * std::ldexp(1.0, -19);
  o.omega0_rad = inavS(w2, 16, 32) * std::ldexp(1.0, -31) * kIcdPi;
  o.i0_rad = inavS(w2, 48, 32) * std::ldexp(1.0, -31) * kIcdPi;
  o.omega_rad = inavS(w2, 80, 32) * std::ldexp(1.0, -31) * kIcdPi;
  o.idot_radps = inavS(w2, 112, 14) * std::ldexp(1.0, -43) * kIcdPi;
  o.omega_dot_radps = inavS(w3, 16, 24) * std::ldexp(1.0, -43) * kIcdPi;
  o.delta_n_radps = inavS(w3, 40, 16) * std::ldexp(1.0, -43) * kIcdPi;
  o.cuc_rad = inavS(w3, 56, 16) * std::ldexp(1.0, -29);
  o.cus_rad = inavS(w3, 72, 16) * std::ldexp(1.0, -29);
  o.crc_m = inavS(w3, 88, 16) * std::ldexp(1.0, -5);
  o.crs_m = inavS(w3, 104, 16) * std::ldexp(1.0, -5);
  o.cic_rad = inavS(w4, 22, 16) * std::ldexp(1.0, -29);
  o.cis_rad = inavS(w4, 38, 16) * std::ldexp(1.0, -29);
  return o;
}

/// The ephemeris of I/NAV words 1-5 of one IOD; the GST week resolved with the
/// receiver week when known; sig: the RXM-SFRBX sigId (5: E5b-I, else E1-B).
GalileoEphemeris inavEphemeris(const SatelliteId& sat, int iod, const std::map<int, std::vector<std::uint8_t>>& words,
                               const std::vector<std::uint8_t>& word5, std::optional<int> receiver_week, int sig) {
  const std::uint8_t* w3 = words.at(3).data();
  const std::uint8_t* w4 = words.at(4).data();
  const std::uint8_t* w5 = word5.data();
  GalileoEphemeris eph;
  eph.satellite = sat;
  eph.type = GalileoNavType::INav;
  eph.iod_nav = iod;
  KeplerOrbit& o = eph.orbit;
  o = inavOrbit(words.at(1).data(), words.at(2).data(), w3, w4);
  eph.sisa_m = galileoSisa_m(static_cast<int>(inavU(w3, 120, 8)));
  const double toc_sow = inavU(w4, 54, 14) * 60.0;
  eph.clock.af0_s = inavS(w4, 68, 31) * std::ldexp(1.0, -34);
  eph.clock.af1_sps = inavS(w4, 99, 21) * std::ldexp(1.0, -46);
  eph.clock.af2_sps2 = inavS(w4, 120, 6) * std::ldexp(1.0, -59);
  // Word 5: ionosphere (6..46), BGDs, health, GST week and time of week.
  eph.bgd_e5a_e1_s = inavS(w5, 47, 10) * std::ldexp(1.0, -32);
  eph.bgd_e5b_e1_s = inavS(w5, 57, 10) * std::ldexp(1.0, -32);
  const int e5b_hs = static_cast<int>(inavU(w5, 67, 2));
  const int e1b_hs = static_cast<int>(inavU(w5, 69, 2));
  const int e5b_dvs = static_cast<int>(inavU(w5, 71, 1));
  const int e1b_dvs = static_cast<int>(inavU(w5, 72, 1));
  const int gst_week = static_cast<int>(inavU(w5, 73, 12));
  const double tow_s = inavU(w5, 85, 20);
  eph.health = e1b_dvs | (e1b_hs << 1) | (e5b_dvs << 6) | (e5b_hs << 7);
  // GST week 0 began with GPS week 1024 (OS SIS ICD 5.1.2); 12-bit roll-over resolved
  // with the receiver week.
  const int week = receiver_week ? resolveWeek(gst_week + 1024, 4096, *receiver_week) : gst_week + 1024;
  const GnssTime transmission = GnssTime::fromGpsWeek(week, tow_s);
  eph.transmission_sow = tow_s;
  o.toe = nearestSecondsOfWeek(transmission, o.toe_sow);
  eph.clock.toc = nearestSecondsOfWeek(transmission, toc_sow);
  eph.week = o.toe.gpsWeek().week;
  eph.data_sources = (sig == 5 ? (1 << 2) : (1 << 0)) | (1 << 9);  // I/NAV E1-B or E5b-I; clock E5b/E1
  return eph;
}

}  // namespace

void UbxDecoder::inav(const UbxFrame& f, const SatelliteId& sat, const Handlers& handlers) {
  // 1. The page: alert pages skipped; the halves even then odd; CRC-24Q.
  const std::array<std::uint8_t, 32> page = inavPage(f);
  const std::uint8_t* even = page.data();
  const std::uint8_t* odd = page.data() + 16;
  if (bitsU(even, 1, 1) == 1 || bitsU(odd, 1, 1) == 1) return;  // alert page
  if (bitsU(even, 0, 1) != 0 || bitsU(odd, 0, 1) != 1) {
    problem(f, StreamProblemKind::MalformedMessage, sat.toString() + " I/NAV page halves not even then odd");
    return;
  }
  if (!inavCrcOk(even, odd)) {
    problem(f, StreamProblemKind::ChecksumError, sat.toString() + " Galileo I/NAV page CRC-24Q mismatch");
    return;
  }
  // 2. The word: types 1-4 kept by IOD (the last four IODs), type 5 the latest.
  std::vector<std::uint8_t> word = inavWord(even, odd);
  const int type = static_cast<int>(bitsU(word.data(), 0, 6));
  InavState& state = inav_[sat];
  int iod = -1;
  if (type >= 1 && type <= 4) {
    iod = static_cast<int>(bitsU(word.data(), 6, 10));
    state.words_by_iod[iod][type] = word;
    while (state.words_by_iod.size() > 4) state.words_by_iod.erase(state.words_by_iod.begin());
  } else if (type == 5) {
    state.word5 = word;
  } else {
    return;
  }
  if (!state.word5) return;
  // 3. Release every IOD with words 1-4 complete (normally the one just completed).
  for (auto& [record_iod, words] : state.words_by_iod) {
    if (iod >= 0 && record_iod != iod) continue;
    if (words.size() < 4) continue;
    const int svid = static_cast<int>(bitsU(words[4].data(), 16, 6));
    if (svid != sat.prn) {
      problem(f, StreamProblemKind::InconsistentEphemeris,
              sat.toString() + " I/NAV word 4 names SVID " + std::to_string(svid) + ": not used");
      words.erase(4);
      continue;
    }
    const GalileoEphemeris eph = inavEphemeris(sat, record_iod, words, *state.word5, week_, f.payload[2]);
    const auto last = last_galileo_.find(sat);
    if (last != last_galileo_.end() && last->second.first == record_iod && last->second.second == eph.orbit.toe) continue;
    last_galileo_[sat] = {record_iod, eph.orbit.toe};
    ++statistics_.galileo_ephemerides;
    if (handlers.on_galileo) handlers.on_galileo(eph);
  }
}

namespace {

/// The ephemeris of GLONASS strings 1-4 (ICD GLONASS 4.4); tb and tk, Moscow times
/// (UTC + 3 h) of the day, placed around the receiver time `now`.
GlonassEphemeris glonassEphemeris(const SatelliteId& sat, const std::array<ubx_nav::Unit, 4>& u, int channel,
                                  const GnssTime& now) {
  using namespace ubx_nav;
  GlonassEphemeris eph;
  eph.satellite = sat;
  eph.frequency_channel = channel;
  const bool sm = true;  // sign-magnitude numbers
  eph.position_m = 1e3 * Eigen::Vector3d(readField(u, glo::kX, sm), readField(u, glo::kY, sm), readField(u, glo::kZ, sm));
  eph.velocity_mps = 1e3 * Eigen::Vector3d(readField(u, glo::kVx, sm), readField(u, glo::kVy, sm), readField(u, glo::kVz, sm));
  eph.acceleration_mps2 =
      1e3 * Eigen::Vector3d(readField(u, glo::kAx, sm), readField(u, glo::kAy, sm), readField(u, glo::kAz, sm));
  eph.gamma_n = readField(u, glo::kGammaN, sm);
  eph.minus_tau_n_s = -readField(u, glo::kTauN, sm);
  eph.health = static_cast<int>(readField(u, glo::kBn)) >> 2;  // Bn MSB
  eph.age_days = readField(u, glo::kEn);
  const double moscow_sod = glonassSecondsOfDay(now);
  auto nearestInDay = [&](double sod) {
    double d = sod - moscow_sod;
    if (d > 43200.0) d -= 86400.0;
    if (d < -43200.0) d += 86400.0;
    return now + d;  // GPST: the Moscow offset cancels in the difference
  };
  const int tb = static_cast<int>(readField(u, glo::kTb));
  eph.tb = nearestInDay(tb * 900.0);
  const double tk_sod = readField(u, glo::kTkHours) * 3600.0 + readField(u, glo::kTkMinutes) * 60.0 +
                        readField(u, glo::kTkHalfMinute) * 30.0;
  const GnssTime tk = nearestInDay(tk_sod);
  eph.message_frame_time_s = (tk + tk.offsetToSystem_s(TimeSystem::UTC)).gpsWeek().seconds_of_week;
  return eph;
}

}  // namespace

void UbxDecoder::glonassString(const UbxFrame& f, const SatelliteId& sat, const Handlers& handlers) {
  using namespace ubx_nav;
  // The string: words 0-2 MSB first (b85 = word 0 bit 31); word 3's upper half: frame id.
  Unit s{};
  for (int w = 0; w < 3; ++w) setBits(s, 32 * w, 32, u4(f.payload.data() + 8 + 4 * w));
  const std::uint32_t frame_id = u4(f.payload.data() + 8 + 12) >> 16;
  if (!glonassHammingOk(s)) {
    problem(f, StreamProblemKind::ChecksumError, sat.toString() + " GLONASS string Hamming code check failed (ICD 4.7)");
    return;
  }
  const int m = static_cast<int>(getBits(s, 1, 4));
  if (m < 1 || m > 15) {
    problem(f, StreamProblemKind::MalformedMessage, sat.toString() + " GLONASS string number 0");
    return;
  }
  if (m > 4) return;  // almanac and time scale strings: not used
  GlonassFrame& frame = glonass_[sat];
  if (frame.frame_id != frame_id) frame = GlonassFrame{frame_id, {}};
  frame.strings[static_cast<std::size_t>(m - 1)] = s;
  if (m != 4) return;
  for (const auto& str : frame.strings)
    if (!str) return;
  std::array<Unit, 4> u{*frame.strings[0], *frame.strings[1], *frame.strings[2], *frame.strings[3]};
  frame.strings = {};
  const int slot = static_cast<int>(readField(u, glo::kSlot));
  if (slot != sat.prn) {
    problem(f, StreamProblemKind::InconsistentEphemeris,
            sat.toString() + " GLONASS string 4 names slot " + std::to_string(slot) + ": not used");
    return;
  }
  if (!last_time_) {
    problem(f, StreamProblemKind::UnresolvedTime,
            sat.toString() + " GLONASS ephemeris before any RXM-RAWX: the day of tb cannot be resolved");
    return;
  }
  const GlonassEphemeris eph = glonassEphemeris(sat, u, static_cast<int>(f.payload[3]) - 7, *last_time_);
  if (const auto why = checkGlonassState(eph)) {
    problem(f, StreamProblemKind::MalformedMessage, sat.toString() + ": " + *why);
    return;
  }
  const auto last = last_glonass_.find(sat);
  if (last != last_glonass_.end() && last->second == eph.tb) return;
  last_glonass_[sat] = eph.tb;
  ++statistics_.glonass_ephemerides;
  if (handlers.on_glonass) handlers.on_glonass(eph);
}

void UbxDecoder::beidouSubframe(const UbxFrame& f, const SatelliteId& sat, const Handlers& handlers) {
  using namespace ubx_nav;
  Unit u{};
  for (int w = 0; w < 10; ++w) setBits(u, 30 * w, 30, u4(f.payload.data() + 8 + 4 * w) & 0x3FFFFFFFu);
  const bool geo = isBeidouGeo(sat.prn);
  const char* kind = geo ? "D2" : "D1";
  if (!bdsParityOk(u)) {
    problem(f, StreamProblemKind::ChecksumError, sat.toString() + " BeiDou " + kind + " word parity (BCH) check failed");
    return;
  }
  if (getBits(u, 0, 11) != 0x712u) {  // preamble 11100010010
    problem(f, StreamProblemKind::MalformedMessage, sat.toString() + " BeiDou subframe without the preamble");
    return;
  }
  const int fra = static_cast<int>(getBits(u, 15, 3));
  const long sow = static_cast<long>((getBits(u, 18, 8) << 12) | getBits(u, 30, 12));
  BeidouFrame& parts = beidou_[sat];
  if (geo) {
    if (fra != 1) return;  // D2 subframes 2-5: integrity, almanac, time: not used
    const int page = static_cast<int>(getBits(u, 42, 4));
    if (page < 1 || page > 10) return;
    parts.units[static_cast<std::size_t>(page - 1)] = u;
    parts.sow[static_cast<std::size_t>(page - 1)] = sow;
    if (page == 10) releaseBeidou(f, sat, parts, true, handlers);
  } else {
    if (fra < 1 || fra > 3) return;  // subframes 4-5: almanac
    parts.units[static_cast<std::size_t>(fra - 1)] = u;
    parts.sow[static_cast<std::size_t>(fra - 1)] = sow;
    if (fra == 3) releaseBeidou(f, sat, parts, false, handlers);
  }
}

void UbxDecoder::releaseBeidou(const UbxFrame& f, const SatelliteId& sat, BeidouFrame& parts, bool geo,
                               const Handlers& handlers) {
  using namespace ubx_nav;
  // D1: subframes 1-3 of one frame, 6 s apart. D2: pages 1 and 3-10 of subframe 1,
  // one per 3-s frame (page 2, ionosphere, is not needed).
  const int count = geo ? 10 : 3;
  for (int k = 0; k < count; ++k) {
    if (geo && k == 1) continue;
    if (!parts.units[static_cast<std::size_t>(k)]) return;
    const long expected = parts.sow[0] + (geo ? 3L * k : 6L * k);
    if (parts.sow[static_cast<std::size_t>(k)] != expected) return;  // parts of different frames: wait
  }
  const long sow1 = parts.sow[0];  // transmission of subframe 1 / page 1 (BDT)
  BeidouEphemeris eph;
  eph.satellite = sat;
  KeplerOrbit& o = eph.orbit;
  std::array<Unit, 10> u{};
  for (int k = 0; k < count; ++k)
    if (parts.units[static_cast<std::size_t>(k)]) u[static_cast<std::size_t>(k)] = *parts.units[static_cast<std::size_t>(k)];
  const BdsBroadcast broadcast = readBeidou(u, geo ? kBdsD2 : kBdsD1, eph);
  const int week13 = broadcast.week13, urai = broadcast.urai;
  const double toc_sow = broadcast.toc_sow;
  parts = BeidouFrame{};
  if (toc_sow != o.toe_sow) {
    problem(f, StreamProblemKind::InconsistentEphemeris,
            sat.toString() + " BeiDou toc " + std::to_string(static_cast<long>(toc_sow)) + " s differs from toe " +
                std::to_string(static_cast<long>(o.toe_sow)) + " s: not used");
    return;
  }
  if (const auto why = checkKeplerOrbit(o)) {
    problem(f, StreamProblemKind::MalformedMessage, sat.toString() + ": " + *why);
    return;
  }
  const int week = week_ ? resolveWeek(week13, 8192, *week_ - kBdtWeekZeroGpsWeek) : week13;
  eph.ura_m = beidouUra_m(urai);
  const double transmission_sow = static_cast<double>(sow1);
  const GnssTime transmission = fromBdtWeek(week, transmission_sow);
  o.toe = withinHalfWeek(transmission, fromBdtWeek(week, o.toe_sow));
  eph.clock.toc = withinHalfWeek(transmission, fromBdtWeek(week, toc_sow));
  eph.bdt_week = toBdtWeek(o.toe).week;
  eph.transmission_sow = transmission_sow;
  const auto last = last_beidou_.find(sat);
  if (last != last_beidou_.end() && last->second.first == eph.aode && last->second.second == o.toe) return;
  last_beidou_[sat] = {eph.aode, o.toe};
  ++statistics_.beidou_ephemerides;
  if (handlers.on_beidou) handlers.on_beidou(eph);
}

}  // namespace ppp
