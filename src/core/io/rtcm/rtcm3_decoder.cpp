#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"

#include <algorithm>

#include <array>
#include <cmath>
#include <iterator>
#include <string>

#include "ppp_bayes_tree/io/bit_reader.h"
#include "ppp_bayes_tree/types/broadcast_accuracy.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"
#include "rtcm3_ephemeris_layout.h"

namespace ppp {
namespace {

constexpr double kRangeMs_m = kSpeedOfLight_mps * 0.001;  // range of 1 ms of light time
constexpr std::int64_t kWeekMs = 604800LL * 1000;
constexpr std::int64_t kDayMs = 86400LL * 1000;

// RTCM 10403.3 MSM signal tables, id 1..32 -> RINEX band and attribute ("" reserved).
const std::array<const char*, 32> kGpsSignals = {
    "",   "1C", "1P", "1W", "",   "",   "",   "2C", "2P", "2W", "",   "",   "",   "",   "2S", "2L",
    "2X", "",   "",   "",   "",   "5I", "5Q", "5X", "",   "",   "",   "",   "",   "1S", "1L", "1X"};
const std::array<const char*, 32> kGlonassSignals = {
    "", "1C", "1P", "", "", "", "", "2C", "2P", "", "", "", "", "", "", "",
    "", "",   "",   "", "", "", "", "",   "",   "", "", "", "", "", "", ""};
const std::array<const char*, 32> kGalileoSignals = {
    "",   "1C", "1A", "1B", "1X", "1Z", "",   "6C", "6A", "6B", "6X", "6Z", "",   "7I", "7Q", "7X",
    "",   "8I", "8Q", "8X", "",   "5I", "5Q", "5X", "",   "",   "",   "",   "",   "",   "",   ""};
const std::array<const char*, 32> kSbasSignals = {
    "", "1C", "", "", "", "", "", "", "", "", "", "", "", "", "", "",
    "", "",   "", "", "", "5I", "5Q", "5X", "", "", "", "", "", "", "", ""};
const std::array<const char*, 32> kQzssSignals = {
    "",   "1C", "",   "",   "",   "",   "",   "",   "6S", "6L", "6X", "",   "",   "",   "2S", "2L",
    "2X", "",   "",   "",   "",   "5I", "5Q", "5X", "",   "",   "",   "",   "",   "1S", "1L", "1X"};
const std::array<const char*, 32> kBeidouSignals = {
    "",   "2I", "2Q", "2X", "",   "",   "",   "6I", "6Q", "6X", "",   "",   "",   "7I", "7Q", "7X",
    "",   "",   "",   "",   "",   "5D", "5P", "5X", "",   "",   "",   "",   "",   "1D", "1P", "1X"};

/// The MSM systems (RTCM 10403.3 3.5.12): one row each, in the order of their
/// message groups (1071-1077 GPS, 1081-1087 GLONASS, ... 1131-1137 NavIC).
struct MsmSystemRow {
  GnssSystem system;
  const std::array<const char*, 32>* signals;  // nullptr: no signal table here (not decoded)
  int prn_minus_id;                            // PRN = DF394 satellite id + this (SBAS: PRN 120 = id 1 = "S20")
};
const MsmSystemRow kMsmSystems[] = {
    {GnssSystem::GPS, &kGpsSignals, 0},    {GnssSystem::GLONASS, &kGlonassSignals, 0},
    {GnssSystem::Galileo, &kGalileoSignals, 0}, {GnssSystem::SBAS, &kSbasSignals, 19},
    {GnssSystem::QZSS, &kQzssSignals, 0},  {GnssSystem::BeiDou, &kBeidouSignals, 0},
    {GnssSystem::IRNSS, nullptr, 0},
};
constexpr int kFirstMsmGroup = 1070;

/// The row and group index of a system, nullptr when MSM has none.
const MsmSystemRow* msmRow(GnssSystem system, int* group = nullptr) {
  for (int k = 0; k < static_cast<int>(std::size(kMsmSystems)); ++k) {
    if (kMsmSystems[k].system != system) continue;
    if (group != nullptr) *group = k;
    return &kMsmSystems[k];
  }
  return nullptr;
}

const std::array<const char*, 32>* signalTable(GnssSystem system) {
  const MsmSystemRow* row = msmRow(system);
  return row != nullptr ? row->signals : nullptr;
}

std::int64_t timeMs(const GnssTime& t) {
  return t.wholeSeconds() * 1000 + static_cast<std::int64_t>(std::llround(t.fraction() * 1000.0));
}
GnssTime fromMs(std::int64_t ms) {
  const std::int64_t whole = ms >= 0 ? ms / 1000 : -((-ms + 999) / 1000);
  return GnssTime::fromGpsSeconds(whole, static_cast<double>(ms - whole * 1000) * 1e-3);
}
/// Places `value` (ms, modulo `period`) nearest to `reference` (ms).
std::int64_t nearest(std::int64_t reference, std::int64_t value_in_period, std::int64_t period) {
  const std::int64_t start = reference - (((reference % period) + period) % period);
  std::int64_t t = start + value_in_period;
  if (t < reference - period / 2) t += period;
  else if (t > reference + period / 2) t -= period;
  return t;
}

using rtcm_eph::p2;

/// The continuous week of a broadcast week number `truncated` (counted modulo
/// `modulus`) nearest to `week_now`, then moved by one where toe (`toe_at(week)`)
/// would lie more than half a week from `now` (the broadcast week may be that
/// of transmission).
template <class ToeAt>
int resolveBroadcastWeek(int truncated, int modulus, int week_now, const GnssTime& now, ToeAt toe_at) {
  int week = truncated + ((week_now - truncated + modulus / 2) / modulus) * modulus;
  const double dt = toe_at(week) - now;
  if (dt < -302400.0) ++week;
  else if (dt >= 302400.0) --week;
  return week;
}

/// The week a truncated broadcast week stands for, nearest to `week_now`,
/// without the half-week move (what the record itself says).
int broadcastWeekAsSent(int truncated, int modulus, int week_now) {
  return truncated + ((week_now - truncated + modulus / 2) / modulus) * modulus;
}

std::string readText(BitReader& r, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s.push_back(static_cast<char>(r.u(8)));
  return s;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  std::size_t b = 0;
  while (b < s.size() && s[b] == ' ') ++b;
  return s.substr(b);
}

}  // namespace

std::optional<std::pair<char, char>> msmSignalCode(GnssSystem system, int signal_id) {
  const auto* table = signalTable(system);
  if (!table || signal_id < 1 || signal_id > 32) return std::nullopt;
  const char* code = (*table)[signal_id - 1];
  if (code[0] == '\0') return std::nullopt;
  return std::make_pair(code[0], code[1]);
}

std::optional<int> msmSignalId(GnssSystem system, char band, char attribute) {
  const auto* table = signalTable(system);
  if (!table) return std::nullopt;
  for (int i = 0; i < 32; ++i) {
    const char* code = (*table)[i];
    if (code[0] == band && code[1] == attribute) return i + 1;
  }
  return std::nullopt;
}

std::uint32_t msmLockTimeDf402_ms(unsigned indicator) {
  return indicator == 0 ? 0u : (1u << (indicator + 4));
}

std::uint32_t msmLockTimeDf407_ms(unsigned i) {
  if (i < 64) return i;
  if (i > 704) return 67108864u;  // reserved values: treat as the maximum
  const unsigned n = (i - 32) / 32;
  return (1u << n) * (i - 32 * n);
}

std::optional<std::pair<GnssSystem, int>> msmTypeInfo(int type) {
  if (type < 1071 || type > 1137) return std::nullopt;
  const int msm = type % 10;
  if (msm < 1 || msm > 7) return std::nullopt;
  const int group = (type - kFirstMsmGroup) / 10;
  if (group >= static_cast<int>(std::size(kMsmSystems))) return std::nullopt;
  return std::make_pair(kMsmSystems[group].system, msm);
}

std::optional<int> msmMessageType(GnssSystem system, int msm) {
  int group = 0;
  const MsmSystemRow* row = msmRow(system, &group);
  if (row == nullptr || row->signals == nullptr || msm < 1 || msm > 7) return std::nullopt;
  return kFirstMsmGroup + 10 * group + msm;
}

int msmSatelliteId(const SatelliteId& sat) {
  const MsmSystemRow* row = msmRow(sat.system);
  return sat.prn - (row != nullptr ? row->prn_minus_id : 0);
}

Rtcm3Decoder::Rtcm3Decoder(Rtcm3DecoderOptions options) : options_(std::move(options)) {
  time_ = options_.reference_time;
}

void Rtcm3Decoder::feed(const std::uint8_t* data, std::size_t size) {
  framer_.feed(data, size, [this](const Rtcm3Frame& frame) {
    decodeFrame(frame);
    if (after_frame_) after_frame_();
  });
}

void Rtcm3Decoder::finish() {
  framer_.finish();
  finishing_ = true;
  std::vector<Rtcm3Frame> deferred;
  deferred.swap(deferred_glonass_);
  for (const auto& g : deferred) decodeMsm(g, GnssSystem::GLONASS, msmTypeInfo(g.message_type)->second);
  finishing_ = false;
  flushPendingEpoch();
  if (after_frame_) after_frame_();
}

void Rtcm3Decoder::problem(StreamProblemKind kind, const Rtcm3Frame& frame, std::string detail) {
  framer_.counters().add(
      StreamProblem{kind, frame.byte_offset, frame.frame_index, frame.message_type, std::move(detail)});
}

/// A non-MSM message the decoder reads, with its decoding step; nullptr: known and
/// skipped on purpose (counted in ignoredByType).
struct NonMsmMessage {
  int type;
  void (Rtcm3Decoder::*decode)(const Rtcm3Frame&);
};

const NonMsmMessage* Rtcm3Decoder::nonMsmMessage(int message_type) {
  static constexpr NonMsmMessage kMessages[] = {
      {1005, &Rtcm3Decoder::decodeStation},         {1006, &Rtcm3Decoder::decodeStation},
      {1007, &Rtcm3Decoder::decodeAntennaReceiver}, {1008, &Rtcm3Decoder::decodeAntennaReceiver},
      {1033, &Rtcm3Decoder::decodeAntennaReceiver}, {1019, &Rtcm3Decoder::decodeGpsQzss},
      {1044, &Rtcm3Decoder::decodeGpsQzss},         {1020, &Rtcm3Decoder::decodeGlonassEph},
      {1042, &Rtcm3Decoder::decodeBeidou},          {1045, &Rtcm3Decoder::decodeGalileo},
      {1046, &Rtcm3Decoder::decodeGalileo},
      {1230, nullptr},  // GLONASS code-phase biases: known, not used
      {1013, nullptr},  // system parameters
  };
  for (const NonMsmMessage& m : kMessages)
    if (m.type == message_type) return &m;
  return nullptr;
}

bool Rtcm3Decoder::readsMessageType(int message_type) {
  if (const auto msm = msmTypeInfo(message_type)) return msm->second >= 4 && msm->first != GnssSystem::IRNSS;
  return nonMsmMessage(message_type) != nullptr;
}

void Rtcm3Decoder::decodeFrame(const Rtcm3Frame& frame) {
  const int type = frame.message_type;
  if (const auto msm = msmTypeInfo(type)) {
    if (msm->second >= 4 && msm->first != GnssSystem::IRNSS) {
      decodeMsm(frame, msm->first, msm->second);
      return;
    }
  }
  if (const NonMsmMessage* m = nonMsmMessage(type)) {
    if (m->decode) (this->*m->decode)(frame);
    else ++ignored_by_type_[type];
    return;
  }
  if (foreign_ && foreign_(frame)) return;
  problem(StreamProblemKind::UnknownMessage, frame,
          "message type " + std::to_string(type) + " (" + std::to_string(frame.payload.size()) +
              " bytes) not decoded, skipped");
}

std::optional<int> Rtcm3Decoder::glonassChannel(int slot) const {
  if (const auto k = channels_.channel(slot)) return k;
  return options_.glonass_channels.channel(slot);
}

void Rtcm3Decoder::flushPendingEpoch() {
  if (!pending_) return;
  if (!pending_->satellites.empty()) output_.epochs.push_back(std::move(*pending_));
  pending_.reset();
}

/// The fields of one MSM message (RTCM 10403.3 3.5.12.3 to 3.5.12.5).
struct MsmFields {
  // Header.
  int station_id = 0;
  std::int64_t epoch_ms = 0;     // time of week (GLONASS: time of day)
  int glonass_dow = 0;           // DF416, 7 = unknown
  bool multiple = false;         // DF393: more messages of this epoch follow
  std::vector<int> sats, sigs;   // satellite and signal ids (from 1) of the masks
  std::vector<bool> cell;        // cell mask, satellite after satellite
  std::size_t ncell = 0;         // cells present
  // Satellite data.
  std::vector<std::optional<double>> rough_m, rate_mps;
  std::vector<int> ext;          // extended satellite information (15 when absent)
  // Signal data, one per cell present.
  std::vector<std::optional<double>> fine_pr_m, fine_cp_m, fine_rate_mps, cnr_dbhz;
  std::vector<std::uint32_t> lock_ms;
  std::vector<bool> half;
};

namespace {

bool msmExtended(int msm) { return msm == 5 || msm == 7; }  // MSM5/7: extended info and rates
bool msmHigh(int msm) { return msm == 6 || msm == 7; }      // MSM6/7: high resolution

/// The header up to the signal mask (the reader stands after DF002).
void readMsmHeader(BitReader& r, GnssSystem system, MsmFields& m) {
  m.station_id = static_cast<int>(r.u(12));
  if (system == GnssSystem::GLONASS) {
    m.glonass_dow = static_cast<int>(r.u(3));
    m.epoch_ms = static_cast<std::int64_t>(r.u(27));
  } else {
    m.epoch_ms = static_cast<std::int64_t>(r.u(30));
  }
  m.multiple = r.flag();
  r.skip(3 + 7 + 2 + 2 + 1 + 3);  // IODS, reserved, clock steering, external clock, smoothing
  const std::uint64_t sat_mask = r.u(64);
  const std::uint32_t sig_mask = static_cast<std::uint32_t>(r.u(32));
  for (int i = 0; i < 64; ++i)
    if (sat_mask & (1ULL << (63 - i))) m.sats.push_back(i + 1);
  for (int i = 0; i < 32; ++i)
    if (sig_mask & (1u << (31 - i))) m.sigs.push_back(i + 1);
}

void readMsmCellMask(BitReader& r, MsmFields& m) {
  m.cell.resize(m.sats.size() * m.sigs.size());
  for (std::size_t i = 0; i < m.cell.size(); ++i) {
    m.cell[i] = r.flag();
    m.ncell += m.cell[i] ? 1 : 0;
  }
}

/// Bits of the satellite and of the signal data the message must still hold.
std::size_t msmDataBits(int msm, const MsmFields& m) {
  const std::size_t sat_bits = msmExtended(msm) ? 36 : 18;
  const std::size_t cell_bits = msm == 4 ? 48 : msm == 5 ? 63 : msm == 6 ? 65 : 80;
  return m.sats.size() * sat_bits + m.ncell * cell_bits;
}

/// Satellite data: rough ranges (DF397, DF398), extended information, rough rates (DF399).
void readMsmSatellites(BitReader& r, bool extended, MsmFields& m) {
  const std::size_t nsat = m.sats.size();
  m.rough_m.resize(nsat);
  m.rate_mps.resize(nsat);
  m.ext.assign(nsat, 15);
  std::vector<unsigned> rough_int(nsat);
  for (std::size_t i = 0; i < nsat; ++i) rough_int[i] = static_cast<unsigned>(r.u(8));
  if (extended)
    for (std::size_t i = 0; i < nsat; ++i) m.ext[i] = static_cast<int>(r.u(4));
  for (std::size_t i = 0; i < nsat; ++i) {
    const unsigned mod = static_cast<unsigned>(r.u(10));
    if (rough_int[i] != 255) {
      double v = rough_int[i] * kRangeMs_m;
      v += mod * p2(-10) * kRangeMs_m;
      m.rough_m[i] = v;
    }
  }
  if (extended)
    for (std::size_t i = 0; i < nsat; ++i) {
      const std::int64_t v = r.s(14);
      if (v != -8192) m.rate_mps[i] = static_cast<double>(v);
    }
}

/// A fine range or phase field of `bits` bits scaled by 2^exponent ms; nullopt
/// for the invalid value (the most negative).
std::optional<double> fineRange_m(BitReader& r, int bits, int exponent) {
  const std::int64_t v = r.s(bits);
  if (v == -(std::int64_t{1} << (bits - 1))) return std::nullopt;
  return v * p2(exponent) * kRangeMs_m;
}

/// Signal data, one value per cell and field: fine ranges, fine phases, lock
/// times, half-cycle flags, CNR and (MSM5/7) fine rates.
void readMsmSignals(BitReader& r, int msm, MsmFields& m) {
  const bool high = msmHigh(msm);
  const std::size_t ncell = m.ncell;
  m.fine_pr_m.resize(ncell);
  m.fine_cp_m.resize(ncell);
  m.fine_rate_mps.resize(ncell);
  m.cnr_dbhz.resize(ncell);
  m.lock_ms.resize(ncell);
  m.half.resize(ncell);
  for (std::size_t j = 0; j < ncell; ++j) m.fine_pr_m[j] = high ? fineRange_m(r, 20, -29) : fineRange_m(r, 15, -24);
  for (std::size_t j = 0; j < ncell; ++j) m.fine_cp_m[j] = high ? fineRange_m(r, 24, -31) : fineRange_m(r, 22, -29);
  for (std::size_t j = 0; j < ncell; ++j)
    m.lock_ms[j] = high ? msmLockTimeDf407_ms(static_cast<unsigned>(r.u(10)))
                        : msmLockTimeDf402_ms(static_cast<unsigned>(r.u(4)));
  for (std::size_t j = 0; j < ncell; ++j) m.half[j] = r.flag();
  for (std::size_t j = 0; j < ncell; ++j) {
    const double v = high ? r.u(10) * 0.0625 : static_cast<double>(r.u(6));
    if (v > 0.0) m.cnr_dbhz[j] = v;
  }
  if (msmExtended(msm))
    for (std::size_t j = 0; j < ncell; ++j) {
      const std::int64_t v = r.s(15);
      if (v != -16384) m.fine_rate_mps[j] = v * 0.0001;
    }
}

}  // namespace

void Rtcm3Decoder::decodeMsm(const Rtcm3Frame& frame, GnssSystem system, int msm) {
  // 1. Header and masks; at most 64 cells.
  BitReader r(frame.payload.data(), frame.payload.size(), 12);
  MsmFields m;
  readMsmHeader(r, system, m);
  const std::size_t nsat = m.sats.size(), nsig = m.sigs.size();
  if (!r.ok() || nsat * nsig > 64) {
    problem(StreamProblemKind::MalformedMessage, frame,
            r.ok() ? std::to_string(nsat) + " satellites x " + std::to_string(nsig) +
                         " signals exceed the 64-cell limit"
                   : "MSM header truncated");
    return;
  }
  // 2. Cell mask; the message must hold the data of its satellites and cells.
  readMsmCellMask(r, m);
  if (!r.ok() || r.remainingBits() < msmDataBits(msm, m)) {
    problem(StreamProblemKind::MalformedMessage, frame,
            "MSM" + std::to_string(msm) + " shorter than its " + std::to_string(nsat) + " satellites and " +
                std::to_string(m.ncell) + " cells");
    return;
  }
  if (m.station_id != 0 || !station_.station_id) station_.station_id = m.station_id;
  // 3. Satellite and signal data.
  readMsmSatellites(r, msmExtended(msm), m);
  readMsmSignals(r, msm, m);
  ++decoded_by_type_[frame.message_type];
  // 4. GLONASS channels from the extended satellite information (MSM5/7).
  if (system == GnssSystem::GLONASS && msmExtended(msm)) {
    for (std::size_t i = 0; i < nsat; ++i)
      if (m.ext[i] <= 13 && !channels_.channel(m.sats[i])) channels_.set(m.sats[i], m.ext[i] - 7);
  }
  // 5. Epoch time (the message may be dropped, or held back for the day).
  const std::optional<GnssTime> t = msmEpochTime(frame, system, m);
  if (!t) return;
  takeStreamTime(*t);
  // 6. Observations into the open epoch, closed by the last message of the epoch.
  openEpoch(frame, *t);
  std::size_t cell = 0;
  for (std::size_t i = 0; i < nsat; ++i) addToOpenEpoch(msmSatellite(system, msm, m, i, cell));
  if (!m.multiple) flushPendingEpoch();
}

std::optional<GnssTime> Rtcm3Decoder::msmEpochTime(const Rtcm3Frame& frame, GnssSystem system,
                                                   const MsmFields& m) {
  if (!time_) {
    problem(StreamProblemKind::UnresolvedTime, frame,
            "MSM epoch dropped: the week is unknown (give a reference date, or wait for a Galileo/BeiDou "
            "ephemeris)");
    return std::nullopt;
  }
  // A GLONASS time of day without day of week, placed only by a reference date, may
  // be a day off (a date far in the day); wait for the other systems of the epoch.
  if (system == GnssSystem::GLONASS && m.glonass_dow >= 7 && !time_from_stream_ && !finishing_) {
    if (deferred_glonass_.size() < 64) deferred_glonass_.push_back(frame);
    return std::nullopt;
  }
  std::int64_t t_ms = 0;
  const std::int64_t ref_ms = timeMs(*time_);
  if (system == GnssSystem::GLONASS) {
    const double offset_s = time_->offsetToSystem_s(TimeSystem::GLONASS);  // GLONASST - GPST
    const std::int64_t offset_ms = static_cast<std::int64_t>(std::llround(offset_s * 1000.0));
    if (m.epoch_ms >= kDayMs) {
      problem(StreamProblemKind::MalformedMessage, frame, "GLONASS time of day beyond 24 h");
      return std::nullopt;
    }
    // With the day of week (DF416, 7 = unknown) the GLONASS time is placed within
    // the week, as a reference date far in the day cannot; otherwise by day.
    if (m.glonass_dow < 7) {
      t_ms = nearest(ref_ms + offset_ms, m.glonass_dow * kDayMs + m.epoch_ms, kWeekMs) - offset_ms;
    } else {
      t_ms = nearest(ref_ms + offset_ms, m.epoch_ms, kDayMs) - offset_ms;
    }
  } else {
    if (m.epoch_ms >= kWeekMs) {
      problem(StreamProblemKind::MalformedMessage, frame, "time of week beyond one week");
      return std::nullopt;
    }
    const std::int64_t shift_ms = std::llround(gpstMinusWeekTime_s(system).value_or(0.0) * 1000.0);  // BDT -> GPST
    std::int64_t tow = m.epoch_ms + shift_ms;
    if (tow >= kWeekMs) tow -= kWeekMs;
    t_ms = nearest(ref_ms, tow, kWeekMs);
  }
  GnssTime t = fromMs(t_ms);
  // Encoders of the RTCM 3.2 drafts (e.g. 2012 receiver firmware) wrote GPST in the
  // BeiDou MSM: within an open multiple-message epoch such a message reads exactly
  // 14 s late. It belongs to the open epoch.
  if (system == GnssSystem::BeiDou && pending_ && t - pending_->time == kGpstMinusBdt_s) {
    t = pending_->time;
    ++beidou_gpst_messages_;
  }
  return t;
}

void Rtcm3Decoder::takeStreamTime(const GnssTime& t) {
  time_ = t;
  if (time_from_stream_) return;
  // The first time from the stream: the GLONASS messages held back for it now decode.
  time_from_stream_ = true;
  std::vector<Rtcm3Frame> deferred;
  deferred.swap(deferred_glonass_);
  for (const auto& g : deferred) decodeMsm(g, GnssSystem::GLONASS, msmTypeInfo(g.message_type)->second);
}

void Rtcm3Decoder::openEpoch(const Rtcm3Frame& frame, const GnssTime& t) {
  if (pending_ && pending_->time != t) flushPendingEpoch();
  if (pending_) return;
  pending_ = StreamEpoch{};
  pending_->time = t;
  pending_->byte_offset = frame.byte_offset;
  pending_->frame_index = frame.frame_index;
}

StreamSatellite Rtcm3Decoder::msmSatellite(GnssSystem system, int msm, const MsmFields& m, std::size_t i,
                                           std::size_t& cell) {
  const SatelliteId sat{system, m.sats[i] + msmRow(system)->prn_minus_id};  // SBAS: PRN 120 + (id - 1) -> "S20"
  std::optional<int> channel;
  if (system == GnssSystem::GLONASS) {
    if (msmExtended(msm) && m.ext[i] <= 13) channel = m.ext[i] - 7;
    else channel = glonassChannel(m.sats[i]);
  }
  StreamSatellite out;
  out.satellite = sat;
  const std::size_t nsig = m.sigs.size();
  for (std::size_t k = 0; k < nsig; ++k) {
    if (!m.cell[i * nsig + k]) continue;
    const std::size_t c = cell++;
    const auto code = msmSignalCode(system, m.sigs[k]);
    if (!code) continue;
    StreamSignal s;
    s.band = code->first;
    s.attribute = code->second;
    const auto freq = carrierFrequency_hz(system, s.band, channel);
    const auto& rough_m = m.rough_m[i];
    const auto& rate_mps = m.rate_mps[i];
    if (rough_m && m.fine_pr_m[c]) s.pseudorange_m = *rough_m + *m.fine_pr_m[c];
    if (rough_m && m.fine_cp_m[c] && freq) s.carrier_phase_cycles = (*rough_m + *m.fine_cp_m[c]) * *freq / kSpeedOfLight_mps;
    if (rate_mps && m.fine_rate_mps[c] && freq) s.doppler_hz = -(*rate_mps + *m.fine_rate_mps[c]) * *freq / kSpeedOfLight_mps;
    s.cnr_dbhz = m.cnr_dbhz[c];
    // Loss of lock: indicator zero or lower than before (same satellite and signal).
    auto& previous = lock_ms_[{sat.index(), m.sigs[k]}];
    const bool lost = m.lock_ms[c] == 0 || m.lock_ms[c] < previous;
    previous = m.lock_ms[c];
    s.lli = static_cast<std::uint8_t>((lost ? 1 : 0) | (m.half[c] ? 2 : 0));
    s.lock_time_s = m.lock_ms[c] * 1e-3;
    if (!s.pseudorange_m && !s.carrier_phase_cycles && !s.doppler_hz && !s.cnr_dbhz) continue;
    out.signals.push_back(s);
  }
  return out;
}

void Rtcm3Decoder::addToOpenEpoch(StreamSatellite satellite) {
  if (satellite.signals.empty()) return;
  // Merge with signals of the same satellite from another message of the epoch.
  for (auto& existing : pending_->satellites) {
    if (existing.satellite == satellite.satellite) {
      existing.signals.insert(existing.signals.end(), satellite.signals.begin(), satellite.signals.end());
      return;
    }
  }
  pending_->satellites.push_back(std::move(satellite));
}

void Rtcm3Decoder::decodeStation(const Rtcm3Frame& frame) {
  const auto& p = frame.payload;
  BitReader r(p.data(), p.size(), 12);
  const int id = static_cast<int>(r.u(12));
  const int itrf = static_cast<int>(r.u(6));
  r.skip(4);
  Eigen::Vector3d arp;
  arp.x() = r.s(38) * 1e-4;
  r.skip(2);
  arp.y() = r.s(38) * 1e-4;
  r.skip(2);
  arp.z() = r.s(38) * 1e-4;
  std::optional<double> height;
  if (frame.message_type == 1006) height = r.u(16) * 1e-4;
  if (!r.ok()) {
    problem(StreamProblemKind::MalformedMessage, frame, "station message shorter than its fields");
    return;
  }
  ++decoded_by_type_[frame.message_type];
  station_.station_id = id;
  station_.itrf_realization_year = itrf;
  station_.arp_ecef_m = arp;
  if (height) station_.antenna_height_m = height;
}

void Rtcm3Decoder::decodeAntennaReceiver(const Rtcm3Frame& frame) {
  const auto& p = frame.payload;
  BitReader r(p.data(), p.size(), 12);
  const int id = static_cast<int>(r.u(12));
  const int n = static_cast<int>(r.u(8));
  const std::string descriptor = readText(r, n);
  const int setup = static_cast<int>(r.u(8));
  std::string serial, receiver, firmware, receiver_serial;
  if (frame.message_type != 1007) serial = readText(r, static_cast<int>(r.u(8)));
  if (frame.message_type == 1033) {
    receiver = readText(r, static_cast<int>(r.u(8)));
    firmware = readText(r, static_cast<int>(r.u(8)));
    receiver_serial = readText(r, static_cast<int>(r.u(8)));
  }
  if (!r.ok()) {
    problem(StreamProblemKind::MalformedMessage, frame, "antenna/receiver message shorter than its texts");
    return;
  }
  ++decoded_by_type_[frame.message_type];
  station_.station_id = id;
  station_.antenna_descriptor = descriptor;
  station_.antenna_setup_id = setup;
  station_.antenna_serial = trim(serial);
  if (frame.message_type == 1033) {
    station_.receiver_type = trim(receiver);
    station_.receiver_firmware = trim(firmware);
    station_.receiver_serial = trim(receiver_serial);
  }
}

void Rtcm3Decoder::setTimeFromEphemeris(const GnssTime& toe) {
  if (time_) return;
  time_ = toe;
  time_from_stream_ = true;
  for (auto& pending : pending_gps_) resolveGpsWeek(pending);
  pending_gps_.clear();
}

void Rtcm3Decoder::noteWeekEvidence(const GnssTime& toe_as_sent, double toe_sow) {
  // Agreement: toe within a day of the stream's time. A toe early in its week
  // may have been sent with the week before (the week of transmission): the
  // nearer of the two readings counts.
  double off_s = toe_as_sent - *time_;
  if (toe_sow < 86400.0 && std::fabs(off_s + 604800.0) < std::fabs(off_s)) off_s += 604800.0;
  ++week_evidence_.records;
  if (std::fabs(off_s) > 86400.0) week_evidence_.disagreement_s.push_back(off_s);
}

void Rtcm3Decoder::resolveGpsWeek(PendingGps& pending) {
  // The 10-bit week nearest to the current time; toe within half a week of it.
  GpsLnavEphemeris& eph = pending.eph;
  noteWeekEvidence(GnssTime::fromGpsWeek(broadcastWeekAsSent(pending.week10, 1024, time_->gpsWeek().week),
                                         eph.orbit.toe_sow),
                   eph.orbit.toe_sow);
  const int week = resolveBroadcastWeek(pending.week10, 1024, time_->gpsWeek().week, *time_,
                                        [&](int w) { return GnssTime::fromGpsWeek(w, eph.orbit.toe_sow); });
  eph.week = week;
  eph.orbit.toe = GnssTime::fromGpsWeek(week, eph.orbit.toe_sow);
  const double toc_sow = eph.clock.toc.toGpsSecondsDouble();  // held as seconds of week until now
  eph.clock.toc = withinHalfWeek(eph.orbit.toe, GnssTime::fromGpsWeek(week, toc_sow));
  output_.gps.push_back(eph);
}

namespace {

/// The fields of a GPS (1019) or QZSS (1044) ephemeris message, as read.
struct LnavMessage {
  GpsLnavEphemeris e;
  int prn = 0;
  int week10 = 0;        // broadcast week modulo 1024
  double toc_sow = 0.0;
};

LnavMessage readGps1019(BitReader& r) {
  LnavMessage m;
  GpsLnavEphemeris& e = m.e;
  m.prn = static_cast<int>(r.u(6));
  m.week10 = static_cast<int>(r.u(10));
  e.ura_m = gpsUra_m(static_cast<int>(r.u(4)));
  e.codes_on_l2 = static_cast<int>(r.u(2));
  e.orbit.idot_radps = r.s(14) * p2(-43) * kPi;
  e.iode = static_cast<int>(r.u(8));
  m.toc_sow = r.u(16) * 16.0;
  e.clock.af2_sps2 = r.s(8) * p2(-55);
  e.clock.af1_sps = r.s(16) * p2(-43);
  e.clock.af0_s = r.s(22) * p2(-31);
  e.iodc = static_cast<int>(r.u(10));
  rtcm_eph::readKepler(r, rtcm_eph::kKeplerLnav, e.orbit);
  e.tgd_s = r.s(8) * p2(-31);
  e.health = static_cast<int>(r.u(6));
  e.l2p_data_flag = static_cast<int>(r.u(1));
  e.fit_interval_h = r.u(1) ? 6.0 : 4.0;  // DF137: 0 = 4 h, 1 = more than 4 h
  return m;
}

LnavMessage readQzss1044(BitReader& r) {
  LnavMessage m;
  GpsLnavEphemeris& e = m.e;
  m.prn = static_cast<int>(r.u(4));
  m.toc_sow = r.u(16) * 16.0;
  e.clock.af2_sps2 = r.s(8) * p2(-55);
  e.clock.af1_sps = r.s(16) * p2(-43);
  e.clock.af0_s = r.s(22) * p2(-31);
  e.iode = static_cast<int>(r.u(8));
  rtcm_eph::readKepler(r, rtcm_eph::kKeplerLnav, e.orbit);
  e.orbit.idot_radps = r.s(14) * p2(-43) * kPi;
  e.codes_on_l2 = static_cast<int>(r.u(2));
  m.week10 = static_cast<int>(r.u(10));
  e.ura_m = gpsUra_m(static_cast<int>(r.u(4)));
  e.health = static_cast<int>(r.u(6));
  e.tgd_s = r.s(8) * p2(-31);
  e.iodc = static_cast<int>(r.u(10));
  e.fit_interval_h = r.u(1) ? 4.0 : 2.0;  // DF187: 0 = 2 h, 1 = more than 2 h
  // 1044 has no L2P data flag: QZSS broadcasts no L2 P-code navigation data, its
  // subframe 1 flag is fixed to 1 (IS-QZSS-PNT), and RINEX/convbin write 1.
  e.l2p_data_flag = 1;
  return m;
}

}  // namespace

void Rtcm3Decoder::decodeGpsQzss(const Rtcm3Frame& frame) {
  // 1. The fields.
  const auto& p = frame.payload;
  const bool qzss = frame.message_type == 1044;
  BitReader r(p.data(), p.size(), 12);
  LnavMessage m = qzss ? readQzss1044(r) : readGps1019(r);
  GpsLnavEphemeris& e = m.e;
  const int prn = m.prn;
  // 2. The whole message, a satellite number in range, one issue of data, a plausible orbit.
  if (!r.ok()) {
    problem(StreamProblemKind::MalformedMessage, frame, "ephemeris message shorter than its fields");
    return;
  }
  const bool valid_prn = qzss ? (prn >= 1 && prn <= 10) : (prn >= 1 && prn <= 32);
  if (!valid_prn) {
    problem(StreamProblemKind::MalformedMessage, frame, "satellite number " + std::to_string(prn) + " out of range");
    return;
  }
  e.satellite = SatelliteId{qzss ? GnssSystem::QZSS : GnssSystem::GPS, prn};
  if ((e.iodc & 0xFF) != e.iode) {
    problem(StreamProblemKind::InconsistentEphemeris, frame,
            e.satellite.toString() + ": IODE " + std::to_string(e.iode) + " differs from the low 8 bits of IODC " +
                std::to_string(e.iodc) + "; record dropped");
    return;
  }
  if (const auto why = checkKeplerOrbit(e.orbit)) {
    problem(StreamProblemKind::MalformedMessage, frame, e.satellite.toString() + ": " + *why);
    return;
  }
  // 3. The 10-bit week resolved now, or once the stream's time is known.
  ++decoded_by_type_[frame.message_type];
  e.clock.toc = GnssTime::fromGpsSeconds(0, 0.0) + m.toc_sow;  // seconds of week until resolved
  PendingGps pending{e, m.week10, frame.byte_offset, frame.frame_index, frame.message_type};
  if (time_) {
    resolveGpsWeek(pending);
  } else {
    if (pending_gps_.size() < 1000) pending_gps_.push_back(pending);
  }
}

namespace {

/// tb (index of 15 min) and tk [ms] are Moscow times (UTC + 3 h) of the current day:
/// g.tb placed nearest `now`, and the RINEX message frame time (seconds of the UTC week) from tk.
void placeGlonassTimes(GlonassEphemeris& g, int tb, std::int64_t tk_ms, const GnssTime& now) {
  const double offset_s = now.offsetToSystem_s(TimeSystem::GLONASS);
  const std::int64_t offset_ms = static_cast<std::int64_t>(std::llround(offset_s * 1000.0));
  const std::int64_t ref = timeMs(now) + offset_ms;
  g.tb = fromMs(nearest(ref, static_cast<std::int64_t>(tb) * 900 * 1000, kDayMs) - offset_ms);
  const GnssTime tk = fromMs(nearest(ref, tk_ms % kDayMs, kDayMs) - offset_ms);
  g.message_frame_time_s = (tk + now.offsetToSystem_s(TimeSystem::UTC)).gpsWeek().seconds_of_week;
}

}  // namespace

void Rtcm3Decoder::decodeGlonassEph(const Rtcm3Frame& frame) {
  const auto& p = frame.payload;
  BitReader r(p.data(), p.size(), 12);
  GlonassEphemeris g;
  const int slot = static_cast<int>(r.u(6));
  const int channel = static_cast<int>(r.u(5)) - 7;
  r.skip(1 + 1 + 2);  // almanac health, health availability, P1
  const int tk_h = static_cast<int>(r.u(5));
  const int tk_m = static_cast<int>(r.u(6));
  const int tk_s = static_cast<int>(r.u(1)) * 30;
  g.health = static_cast<int>(r.u(1));  // Bn MSB
  r.skip(1);                            // P2
  const int tb = static_cast<int>(r.u(7));
  for (int axis = 0; axis < 3; ++axis) {
    g.velocity_mps[axis] = r.sm(24) * p2(-20) * 1e3;
    g.position_m[axis] = r.sm(27) * p2(-11) * 1e3;
    g.acceleration_mps2[axis] = r.sm(5) * p2(-30) * 1e3;
  }
  r.skip(1);  // P3
  g.gamma_n = r.sm(11) * p2(-40);
  r.skip(2 + 1);  // P, ln
  const double tau_n = r.sm(22) * p2(-30);
  r.skip(5);  // delta tau
  g.age_days = static_cast<double>(r.u(5));
  if (!r.ok()) {
    problem(StreamProblemKind::MalformedMessage, frame, "GLONASS ephemeris shorter than its fields");
    return;
  }
  if (slot < 1 || slot > GlonassChannels::kMaxSlot || channel < -7 || channel > 13) {
    problem(StreamProblemKind::MalformedMessage, frame,
            "GLONASS slot " + std::to_string(slot) + " / channel " + std::to_string(channel) + " out of range");
    return;
  }
  g.satellite = SatelliteId{GnssSystem::GLONASS, slot};
  g.frequency_channel = channel;
  g.minus_tau_n_s = -tau_n;
  if (!channels_.channel(slot)) channels_.set(slot, channel);
  if (tb < 1 || tb > 96) {
    problem(StreamProblemKind::MalformedMessage, frame, g.satellite.toString() + ": tb index " + std::to_string(tb) + " outside 1..96");
    return;
  }
  if (!time_) {
    problem(StreamProblemKind::UnresolvedTime, frame, g.satellite.toString() + ": GLONASS ephemeris dropped, the day is unknown");
    return;
  }
  placeGlonassTimes(g, tb, (tk_h * 3600LL + tk_m * 60LL + tk_s) * 1000, *time_);
  if (const auto why = checkGlonassState(g)) {
    problem(StreamProblemKind::MalformedMessage, frame, g.satellite.toString() + ": " + *why);
    return;
  }
  ++decoded_by_type_[frame.message_type];
  output_.glonass.push_back(g);
}

namespace {

/// The fields of a Galileo F/NAV (1045) or I/NAV (1046) ephemeris message, as read.
struct GalileoMessage {
  GalileoEphemeris e;
  int prn = 0;
  int gst_week = 0;      // 12-bit GST week
  double toc_sow = 0.0;
};

GalileoMessage readGalileo(BitReader& r, bool fnav) {
  GalileoMessage m;
  GalileoEphemeris& e = m.e;
  KeplerOrbit& o = e.orbit;
  m.prn = static_cast<int>(r.u(6));
  m.gst_week = static_cast<int>(r.u(12));
  e.iod_nav = static_cast<int>(r.u(10));
  e.sisa_m = galileoSisa_m(static_cast<int>(r.u(8)));
  o.idot_radps = r.s(14) * p2(-43) * kPi;
  m.toc_sow = r.u(14) * 60.0;
  e.clock.af2_sps2 = r.s(6) * p2(-59);
  e.clock.af1_sps = r.s(21) * p2(-46);
  e.clock.af0_s = r.s(31) * p2(-34);
  rtcm_eph::readKepler(r, rtcm_eph::kKeplerGalileo, o);
  e.bgd_e5a_e1_s = r.s(10) * p2(-32);
  if (fnav) {
    const int hs = static_cast<int>(r.u(2));
    const int dvs = static_cast<int>(r.u(1));
    e.health = (hs << 4) | (dvs << 3);
    e.data_sources = (1 << 1) | (1 << 8);
    e.type = GalileoNavType::FNav;
  } else {
    e.bgd_e5b_e1_s = r.s(10) * p2(-32);
    const int e5b_hs = static_cast<int>(r.u(2));
    const int e5b_dvs = static_cast<int>(r.u(1));
    const int e1_hs = static_cast<int>(r.u(2));
    const int e1_dvs = static_cast<int>(r.u(1));
    e.health = (e5b_hs << 7) | (e5b_dvs << 6) | (e1_hs << 1) | e1_dvs;
    e.data_sources = (1 << 0) | (1 << 2) | (1 << 9);
    e.type = GalileoNavType::INav;
  }
  return m;
}

}  // namespace

void Rtcm3Decoder::decodeGalileo(const Rtcm3Frame& frame) {
  // 1. The fields.
  const auto& p = frame.payload;
  BitReader r(p.data(), p.size(), 12);
  GalileoMessage m = readGalileo(r, frame.message_type == 1045);
  GalileoEphemeris& e = m.e;
  KeplerOrbit& o = e.orbit;
  // 2. The whole message, a satellite number in range, a plausible orbit.
  if (!r.ok()) {
    problem(StreamProblemKind::MalformedMessage, frame, "Galileo ephemeris shorter than its fields");
    return;
  }
  if (m.prn < 1 || m.prn > 36) {
    problem(StreamProblemKind::MalformedMessage, frame, "Galileo satellite " + std::to_string(m.prn) + " out of range");
    return;
  }
  e.satellite = SatelliteId{GnssSystem::Galileo, m.prn};
  if (const auto why = checkKeplerOrbit(o)) {
    problem(StreamProblemKind::MalformedMessage, frame, e.satellite.toString() + ": " + *why);
    return;
  }
  // 3. The week: GST week 0 = GPS week 1024; the 12-bit week rolls over every 4096
  //    weeks: the one nearest the current time.
  int week = m.gst_week + 1024;
  if (time_) {
    noteWeekEvidence(GnssTime::fromGpsWeek(broadcastWeekAsSent(week, 4096, time_->gpsWeek().week), o.toe_sow),
                     o.toe_sow);
    week = resolveBroadcastWeek(week, 4096, time_->gpsWeek().week, *time_,
                                [&](int w) { return GnssTime::fromGpsWeek(w, o.toe_sow); });
  }
  e.week = week;
  o.toe = GnssTime::fromGpsWeek(week, o.toe_sow);
  // toc is within the week of toe, allowing for a week crossing between them.
  e.clock.toc = withinHalfWeek(o.toe, GnssTime::fromGpsWeek(week, m.toc_sow));
  ++decoded_by_type_[frame.message_type];
  setTimeFromEphemeris(o.toe);
  output_.galileo.push_back(e);
}

void Rtcm3Decoder::decodeBeidou(const Rtcm3Frame& frame) {
  const auto& p = frame.payload;
  BitReader r(p.data(), p.size(), 12);
  BeidouEphemeris e;
  KeplerOrbit& o = e.orbit;
  const int prn = static_cast<int>(r.u(6));
  const int week13 = static_cast<int>(r.u(13));
  e.ura_m = beidouUra_m(static_cast<int>(r.u(4)));
  o.idot_radps = r.s(14) * p2(-43) * kPi;
  e.aode = static_cast<int>(r.u(5));
  const double toc_sow = r.u(17) * 8.0;
  e.clock.af2_sps2 = r.s(11) * p2(-66);
  e.clock.af1_sps = r.s(22) * p2(-50);
  e.clock.af0_s = r.s(24) * p2(-33);
  e.aodc = static_cast<int>(r.u(5));
  rtcm_eph::readKepler(r, rtcm_eph::kKeplerBeidou, o);
  e.tgd1_s = r.s(10) * 1e-10;
  e.tgd2_s = r.s(10) * 1e-10;
  e.health = static_cast<int>(r.u(1));
  if (!r.ok()) {
    problem(StreamProblemKind::MalformedMessage, frame, "BeiDou ephemeris shorter than its fields");
    return;
  }
  if (prn < 1 || prn > 63) {
    problem(StreamProblemKind::MalformedMessage, frame, "BeiDou satellite " + std::to_string(prn) + " out of range");
    return;
  }
  e.satellite = SatelliteId{GnssSystem::BeiDou, prn};
  if (const auto why = checkKeplerOrbit(o)) {
    problem(StreamProblemKind::MalformedMessage, frame, e.satellite.toString() + ": " + *why);
    return;
  }
  int week = week13;
  if (time_) {
    noteWeekEvidence(
        fromBdtWeek(broadcastWeekAsSent(week13, 8192, time_->gpsWeek().week - kBdtWeekZeroGpsWeek), o.toe_sow),
        o.toe_sow);
    week = resolveBroadcastWeek(week13, 8192, time_->gpsWeek().week - kBdtWeekZeroGpsWeek, *time_,
                                [&](int w) { return fromBdtWeek(w, o.toe_sow); });
  }
  e.bdt_week = week;
  o.toe = fromBdtWeek(week, o.toe_sow);
  e.clock.toc = withinHalfWeek(o.toe, fromBdtWeek(week, toc_sow));
  ++decoded_by_type_[frame.message_type];
  setTimeFromEphemeris(o.toe);
  output_.beidou.push_back(e);
}

}  // namespace ppp
