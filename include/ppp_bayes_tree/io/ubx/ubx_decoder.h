#pragma once
// UbxDecoder: u-blox UBX receiver stream -> observation epochs and broadcast
// ephemerides. References: u-blox F9 HPG interface description (UBX-18010854;
// the X20 one, UBX-22004887, for the L5/E6/B1C/B2a signal ids), sections
// "UBX-RXM-RAWX", "UBX-RXM-SFRBX", "Signal identifiers" and "Navigation data
// subframes"; IS-GPS-200 (20.3.2-20.3.3: LNAV subframes 1-3); Galileo OS SIS ICD
// version 2.1 (4.3.2-4.3.5, 5.1: I/NAV pages and word types 1-5).
//
// RXM-RAWX (0x02 0x15). Time: GnssTime::fromGpsWeek(week, rcvTow) (rcvTow is
// "approximately aligned to GPS time": the receiver clock offset stays in it, as
// in RINEX); leapS is kept when recStat bit 0 says it is valid. An epoch with the
// time of the previous one is dropped (MalformedMessage); every other time order
// (a step back, a week one too high) is judged by the stream's epoch-time policy
// (io/epoch_time_screen.h), not here. Per measurement:
//  - pseudorange when trkStat bit 0 (prValid);
//  - carrier phase when trkStat bit 1 (cpValid), cpMes != -0.5 and cpStdev
//    (4 bits, 0.004 cycles each) <= options.max_phase_stdev_index (5 = RTKLIB's
//    CPSTD_VALID, so that our phases are those convbin writes);
//  - Doppler and C/N0 always; SNR in dB-Hz;
//  - LLI (RINEX 3.05 5.3): bit 0 (loss of lock) at the first sight of a
//    satellite's signal (a new arc: nothing vouches for the phase before it),
//    and when the lock time is 0 or lower than at the previous epoch of the same
//    satellite and signal, or the half-cycle-subtracted flag (trkStat bit 3)
//    changed. A loss of lock of the lock-time kind seen while the phase is not
//    output is held and reported with the next phase (else the slip would be
//    lost); the first-sight flag is not held (the receiver's lock time then
//    vouches for the phase). Bit 1 (half-cycle ambiguity) when trkStat bit 2
//    (half cycle valid) is clear. This is what convbin 2.4.3 b34 writes (checked
//    on gnss_1730.ubx) and follows the lock-time counter's meaning in the
//    interface description ("carrier phase locktime counter, max 64500 ms").
//  - GLONASS frequency channel = freqId - 7.
//
// Signal map (gnssId, sigId) -> RINEX 3 band/attribute, from the interface
// description's signal table and the RINEX 3.05 table 4-A; as RTKLIB 2.4.3 b34
// convbin maps the ones it knows (GPS 0/3, Galileo 0/1, SBAS 0, GLONASS 0/2),
// extended with the later RTKLIB (demo5) mapping for the rest:
//   GPS     0 L1C/A ->1C  3 L2CL ->2L  4 L2CM ->2S  6 L5I ->5I  7 L5Q ->5Q
//   SBAS    0 L1C/A ->1C
//   Galileo 0 E1C ->1C  1 E1B ->1B  3 E5aI ->5I  4 E5aQ ->5Q  5 E5bI ->7I  6 E5bQ ->7Q
//           8 E6B ->6B  9 E6C ->6C  10 E6A ->6A
//   BeiDou  0 B1I D1 ->2I  1 B1I D2 ->2I  2 B2I D1 ->7I  3 B2I D2 ->7I  4 B3I D1 ->6I
//           10 B3I D2 ->6I  5 B1Cp ->1P  6 B1Cd ->1D  7 B2ap ->5P  8 B2ad ->5D
//   QZSS    0 L1C/A ->1C  1 L1S ->1Z  4 L2CM ->2S  5 L2CL ->2L  8 L5I ->5I  9 L5Q ->5Q
//   GLONASS 0 L1OF ->1C  2 L2OF ->2C
//   NavIC   0 L5A ->5A
// Differences from Debian's convbin 2.4.3 b34 by design: it writes BeiDou B1I as
// "1I" (RINEX 3.02 naming; 3.04 says 2I) and drops every signal it has no
// entry for (all L5/E5a/E6/B1C/B2a/B3I). Other sigIds are counted as unmapped.
//
// RXM-SFRBX (0x02 0x13): navigation data words, decoded to records as below.
// A record is released only when all its parts agree on the issue of data:
//  - GPS / QZSS LNAV (sigId 0): ten 30-bit words (data bits 29..6, parity 5..0,
//    polarity already corrected by the receiver), subframes 1-3 of one 30-s
//    frame (consecutive HOW TOW counts); IODC (8 LSBs) = IODE of subframes 2
//    and 3, else InconsistentEphemeris. The 10-bit week is resolved with the
//    receiver week of RXM-RAWX (UnresolvedTime until one is seen).
//  - Galileo I/NAV (sigId 1 E1-B, 5 E5b-I): even/odd page pairs, CRC-24Q
//    checked (ChecksumError), alert pages skipped; words 1-4 kept per IODnav,
//    released with the latest word 5 (BGDs, health, week); word 4's SVID must be
//    the satellite's (InconsistentEphemeris).
//  - GLONASS L1OF/L2OF strings (sigId 0, 2; GLONASS ICD 5.1, 4.4 and 4.7): each
//    string's Hamming code is checked (ChecksumError: the string is dropped);
//    strings 1-4 of one frame (same frame id in SFRBX word 4) make a record,
//    released with string 4; string 4's slot n must be the satellite's
//    (InconsistentEphemeris). tb and tk (Moscow day) are placed on the day of
//    the latest RXM-RAWX (UnresolvedTime before one); the channel is freqId - 7.
//  - BeiDou D1 (MEO/IGSO) subframes 1-3 and D2 (GEO: C01-C05, C59-C63)
//    subframe 1 pages 1-10 (sigId 0-3: B1I and B2I, D1 or D2 by the
//    satellite; BDS-SIS-ICD-B1I 2.0/3.0, 5.2 and 5.3): every word's BCH(15,11)
//    parity is checked (ChecksumError: the subframe / page is dropped); the
//    parts make a record when their SOW are those of one frame (D1: 6 s
//    apart; D2: pages 3 s apart) and toc = toe (else InconsistentEphemeris).
//    The 13-bit BDT week is resolved with the receiver week. Bit layouts:
//    src/core/io/ubx/ubx_nav_layout.h.
//  - GPS/QZSS CNAV (L2C, L5), Galileo F/NAV and E6, BeiDou B1C/B2a/B3I and SBAS
//    messages are framed and counted (navigation_not_decoded) but not decoded.
// A record repeated with the same issue of data and toe is released once.
//
// Other messages: the classes NAV, RXM, INF, ACK, CFG, UPD, MON, AID, TIM, ESF,
// MGA, LOG, SEC, HNR are UBX classes this decoder knows and does not use
// (NAV-PVT etc.): counted in frames_by_type and known_not_used. Any other class
// is an UnknownMessage problem.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/navigation_records.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// The RINEX 3 signal (band, attribute; `type` is Pseudorange) of a u-blox
/// gnssId/sigId pair (table above), nullopt when not in the table.
std::optional<ObservationCode> ubxSignalCode(int gnss_id, int sig_id);
/// The satellite of a u-blox gnssId/svId pair, nullopt when out of range
/// (GLONASS svId 255 = unknown slot).
std::optional<SatelliteId> ubxSatellite(int gnss_id, int sv_id);

/// RINEX loss-of-lock indicator bits.
constexpr std::uint8_t kLliLossOfLock = 0x01;
constexpr std::uint8_t kLliHalfCycle = 0x02;

struct UbxSignalMeasurement {
  SatelliteId satellite;
  ObservationCode signal;  // band and attribute (type Pseudorange)
  int gnss_id = 0, sv_id = 0, sig_id = 0;
  std::optional<double> pseudorange_m;
  std::optional<double> carrier_phase_cycles;
  double doppler_hz = 0.0;
  double cn0_dbhz = 0.0;
  std::uint8_t lli = 0;                 // kLliLossOfLock | kLliHalfCycle
  double lock_time_s = 0.0;
  std::uint8_t tracking_status = 0;     // trkStat as received
  std::optional<int> glonass_channel;   // GLONASS only: freqId - 7
};

struct UbxObservationEpoch {
  GnssTime time;                        // rcvTow/week (GPST, receiver clock included)
  std::optional<int> leap_seconds;      // GPS-UTC when the receiver says it is known
  bool clock_reset = false;             // recStat bit 1
  std::vector<UbxSignalMeasurement> measurements;
  std::uint64_t byte_offset = 0;        // of the RXM-RAWX frame
  std::uint64_t frame_index = 0;
};

struct UbxDecoderOptions {
  /// Carrier phases with a cpStdev index above this are dropped (0..15; 15 keeps all
  /// valid ones). 5 = RTKLIB's CPSTD_VALID (0.020 cycles).
  int max_phase_stdev_index = 5;
};

/// What was decoded, beyond the framer's counts.
struct UbxDecoderStatistics {
  std::uint64_t observation_epochs = 0;
  std::uint64_t measurements = 0;                            // of mapped signals
  std::map<std::pair<int, int>, std::uint64_t> unmapped_signals;   // (gnssId, sigId)
  std::map<std::pair<int, int>, std::uint64_t> navigation_words;   // SFRBX per (gnssId, sigId)
  std::map<std::pair<int, int>, std::uint64_t> navigation_not_decoded;
  std::uint64_t gps_ephemerides = 0, galileo_ephemerides = 0, glonass_ephemerides = 0, beidou_ephemerides = 0;
  std::uint64_t known_not_used = 0;                          // frames of known, unused types
};

class UbxDecoder {
 public:
  struct Handlers {
    std::function<void(const UbxObservationEpoch&)> on_epoch;
    std::function<void(const GpsLnavEphemeris&)> on_gps;      // GPS and QZSS LNAV
    std::function<void(const GalileoEphemeris&)> on_galileo;
    std::function<void(const GlonassEphemeris&)> on_glonass;
    std::function<void(const BeidouEphemeris&)> on_beidou;
  };

  explicit UbxDecoder(UbxDecoderOptions options = {}) : options_(options) {}

  /// Feeds bytes (any chunking); calls the handlers as results complete.
  void feed(const std::uint8_t* data, std::size_t size, const Handlers& handlers);
  /// The stream ended (counts a truncated last frame).
  void finish() { framer_.finish(); }

  /// Frames per type, problems (framing and decoding) with byte offset and frame index.
  const StreamCounters& counters() const { return framer_.counters(); }
  const UbxDecoderStatistics& statistics() const { return statistics_; }
  /// The receiver's GPS week from the last RXM-RAWX, nullopt before the first.
  std::optional<int> receiverWeek() const { return week_; }

 private:
  struct LockState {
    double lock_time_s = 0.0;
    bool half_cycle_subtracted = false;
    bool pending_loss_of_lock = false;  // a lock-time slip not yet reported with a phase
  };
  struct LnavFrame {
    std::optional<std::uint32_t> words[3][10];  // subframes 1-3
    int tow_count[3] = {-1, -1, -1};            // HOW TOW count of each
  };
  struct InavState {
    std::map<int, std::map<int, std::vector<std::uint8_t>>> words_by_iod;  // iod -> type -> 16 bytes
    std::optional<std::vector<std::uint8_t>> word5;
  };
  struct GlonassFrame {
    std::uint32_t frame_id = 0;
    std::array<std::optional<std::array<std::uint8_t, 38>>, 4> strings;  // strings 1-4
  };
  struct BeidouFrame {
    std::array<std::optional<std::array<std::uint8_t, 38>>, 10> units;  // D1 subframes 1-3 / D2 pages 1-10
    std::array<long, 10> sow{};
  };

  void frame(const UbxFrame& frame, const Handlers& handlers);
  void rawx(const UbxFrame& frame, const Handlers& handlers);
  /// One RXM-RAWX measurement block (32 bytes); nullopt for a signal without a RINEX code.
  std::optional<UbxSignalMeasurement> rawxMeasurement(const std::uint8_t* block);
  void sfrbx(const UbxFrame& frame, const Handlers& handlers);
  void lnav(const UbxFrame& frame, const SatelliteId& sat, const Handlers& handlers);
  void inav(const UbxFrame& frame, const SatelliteId& sat, const Handlers& handlers);
  void glonassString(const UbxFrame& frame, const SatelliteId& sat, const Handlers& handlers);
  void beidouSubframe(const UbxFrame& frame, const SatelliteId& sat, const Handlers& handlers);
  void releaseBeidou(const UbxFrame& frame, const SatelliteId& sat, BeidouFrame& parts, bool geo,
                     const Handlers& handlers);
  void problem(const UbxFrame& frame, StreamProblemKind kind, std::string detail);

  UbxDecoderOptions options_;
  UbxFramer framer_;
  UbxDecoderStatistics statistics_;
  std::optional<int> week_;
  std::optional<GnssTime> last_time_;
  std::map<std::pair<SatelliteId, int>, LockState> lock_;  // (sat, sigId)
  std::map<SatelliteId, LnavFrame> lnav_;
  std::map<SatelliteId, InavState> inav_;
  std::map<SatelliteId, std::pair<int, GnssTime>> last_gps_;      // iodc, toe released
  std::map<SatelliteId, std::pair<int, GnssTime>> last_galileo_;  // iod, toe released
  std::map<SatelliteId, GlonassFrame> glonass_;
  std::map<SatelliteId, GnssTime> last_glonass_;                   // tb released
  std::map<SatelliteId, BeidouFrame> beidou_;
  std::map<SatelliteId, std::pair<int, GnssTime>> last_beidou_;   // aode, toe released
};

}  // namespace ppp
