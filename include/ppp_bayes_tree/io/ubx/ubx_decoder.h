#pragma once
// UbxDecoder: u-blox UBX receiver stream -> observation epochs (RXM-RAWX) and
// broadcast ephemerides (RXM-SFRBX: GPS/QZSS LNAV, Galileo I/NAV, GLONASS L1OF/L2OF,
// BeiDou D1/D2). Its output matches what convbin writes from the same stream,
// except where noted. Malformed, unknown or inconsistent messages are counted as
// problems with their byte offset, never thrown. The epoch-time policy is not
// applied here but by the stream's screen (io/epoch_time_screen.h).
//
// Which fields it takes, the loss-of-lock rules, the signal map, the
// navigation-record assembly and the classes it knows: doc/ubx_decoding.md.
//
// References: u-blox F9 HPG interface description (UBX-18010854; the X20 one,
// UBX-22004887, for the L5/E6/B1C/B2a signal ids), "UBX-RXM-RAWX",
// "UBX-RXM-SFRBX", "Signal identifiers", "Navigation data subframes";
// IS-GPS-200 (20.3.2-20.3.3); Galileo OS SIS ICD 2.1 (4.3.2-4.3.5, 5.1);
// GLONASS ICD 5.1 (4.4, 4.7); BDS-SIS-ICD-B1I 2.0/3.0 (5.2, 5.3); RINEX 3.05
// (5.3, table 4-A).
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
