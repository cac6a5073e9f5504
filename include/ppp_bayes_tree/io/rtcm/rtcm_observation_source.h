#pragma once
// RtcmObservationSource: an ObservationSource reading an RTCM 3 recording.
//
// The file is read twice. A first pass (scan) decodes everything to learn what a
// RINEX header must say before the first epoch: the signals observed per system
// (types C, L, D, S per signal, each only when some epoch has it), the station
// (1005/1006 ARP and antenna height, 1007/1008/1033 antenna and receiver), the
// GLONASS channels (MSM5/7, 1020), the first and last epoch, and the broadcast
// ephemerides (kept for navigation output). The second pass streams the epochs;
// it starts with the channels learned by the scan, so GLONASS phases are complete
// from the first epoch even when the first 1020 comes later.
//
// Both passes screen the epoch times with the streams' epoch-time policy
// (io/epoch_time_screen.h, as the live input does): an isolated epoch with a bad
// time (e.g. one MSM frame's time of week days ahead) is dropped and listed, and
// neither decides the header's time span nor stops the epochs after it.
//
// Problems of the stream (CRC errors, garbage, unknown types, unresolved time,
// epoch times refused) are listed by problems() with their byte offset and frame index.
#include <array>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/epoch_time_screen.h"
#include "ppp_bayes_tree/io/rinex/observation_source.h"
#include "ppp_bayes_tree/io/rinex/stream_epoch_layout.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/stream_pump.h"

namespace ppp {

/// Header fields from the station description (marker name = station id, 4 digits).
void fillStationHeader(const RtcmStationInfo& station, RinexObsHeader& header);

/// With a reference date given for MSM times (ppp_solve --ref-date), checks it
/// against what the stream itself says: the broadcast weeks of its GPS/QZSS,
/// Galileo and BeiDou ephemerides (Rtcm3Decoder::weekEvidence: each record's
/// toe in the week it was sent with, against the stream's time the date gave).
/// When most of them (of at least 3) disagree by more than a day, the sentence
/// naming the date, the epochs' times and the evidence (counts, median offset
/// in days, the date the stream gives); nullopt otherwise.
std::optional<std::string> referenceDateContradiction(const GnssTime& reference, const GnssTime& first,
                                                      const GnssTime& last, const BroadcastWeekEvidence& evidence);

class RtcmObservationSource : public ObservationSource {
 public:
  /// Scans the file (throws FileOpenError when it cannot be opened or read,
  /// ParseError when a reference date given contradicts the stream's
  /// ephemerides: referenceDateContradiction). A read error in the streaming
  /// pass after the scan is error(), naming the file and the byte offset.
  explicit RtcmObservationSource(const std::string& path, Rtcm3DecoderOptions options = {});
  ~RtcmObservationSource() override;

  const RinexObsHeader& header() const override { return header_; }
  ObservationRead next(ObsEpoch& epoch) override;
  std::optional<ObservationProblem> error() const override { return error_; }
  std::vector<ObservationProblem> problems() const override;
  double progress() const override;
  std::string name() const override { return name_; }

  /// What the scan found: counters, ephemerides (all records, in stream order), station.
  const StreamCounters& scanCounters() const { return scan_counters_; }
  const Rtcm3Output& scanNavigation() const { return scan_nav_; }
  const RtcmStationInfo& station() const { return station_; }
  std::size_t scanEpochs() const { return scan_epochs_; }
  /// The epochs the time policy dropped so far (streaming pass), with reasons and byte offsets.
  const StreamCounters& timeScreen() const { return screen_.counters(); }

 private:
  bool fill();

  std::string path_, name_;
  Rtcm3DecoderOptions options_;
  RinexObsHeader header_;
  StreamCounters scan_counters_;
  Rtcm3Output scan_nav_;
  RtcmStationInfo station_;
  std::size_t scan_epochs_ = 0;
  std::size_t size_bytes_ = 0, read_bytes_ = 0;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_{nullptr, &std::fclose};
  std::unique_ptr<Rtcm3Decoder> decoder_;
  EpochTimeScreen<StreamEpoch> screen_;
  std::vector<StreamEpoch> queue_;
  std::size_t queue_next_ = 0;
  std::unique_ptr<StreamPump> pump_;  // the streaming pass over file_
  std::optional<ObservationProblem> error_;
};

}  // namespace ppp
