#pragma once
// UbxObservationSource: the observation epochs of a u-blox UBX recording
// (RXM-RAWX, decoded by UbxDecoder) served as an ObservationSource, with the
// broadcast ephemerides its RXM-SFRBX messages carried.
//
// The file is decoded once when the source is opened (a header needs the list
// of observation types before the first epoch); epochs are then served in order.
// The header is that of a RINEX 3.04 mixed observation file as convbin writes
// it: per system, the signals seen, ordered by band then attribute, each with
// the types C, L, D, S (pseudorange m, phase cycles, Doppler Hz, C/N0 dB-Hz);
// GLONASS channels from RXM-RAWX freqId. The LLI of a signal goes with its
// phase observation. Satellites appear in the order of the receiver's RXM-RAWX.
//
// The ephemerides are in the io layer's record types; a caller adds them to a
// BroadcastEphemerisStore (models/broadcast_ephemeris_store.h) with add().
// The decoded epochs pass the streams' epoch-time policy (io/epoch_time_screen.h,
// as in the live input): an isolated epoch with a bad time (a week one too high)
// is dropped and listed, the epochs after it are served.
// Framing and decoding problems (byte offset, frame index) are listed by
// problems() as "<file>: byte N (frame K), type T: ..." (line 0).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/observation_source.h"
#include "ppp_bayes_tree/io/stream_epoch.h"
#include "ppp_bayes_tree/io/ubx/ubx_decoder.h"

namespace ppp {

/// Broadcast records decoded from RXM-SFRBX, in the order released.
struct UbxNavigationRecords {
  std::vector<GpsLnavEphemeris> gps;  // GPS and QZSS LNAV
  std::vector<GalileoEphemeris> galileo;
  std::vector<GlonassEphemeris> glonass;
  std::vector<BeidouEphemeris> beidou;  // D1 and D2 (GEO)
};

/// The header of the decoded epochs (see above), named after `file_name`.
RinexObsHeader ubxObservationHeader(const std::vector<UbxObservationEpoch>& epochs, const std::string& file_name);
/// A decoded UBX epoch as the stream epoch both receiver formats share (the
/// form the live input takes, io/transport/gnss_stream_decoder.h): satellites in RXM-RAWX
/// order, per signal its band/attribute, pseudorange and phase when valid,
/// Doppler, C/N0, LLI and lock time.
StreamEpoch toStreamEpoch(const UbxObservationEpoch& in);
/// One decoded epoch laid out along the header's type lists (signals the header
/// does not list are left out): toStreamEpoch, then streamEpochToObsEpoch
/// (io/rinex/stream_epoch_layout.h), the one conversion of both paths.
void toObsEpoch(const UbxObservationEpoch& in, const RinexObsHeader& header, ObsEpoch& out);

class UbxObservationSource : public ObservationSource {
 public:
  /// Reads and decodes the whole file (throws FileOpenError when it cannot be read).
  explicit UbxObservationSource(const std::string& path, UbxDecoderOptions options = {});

  const RinexObsHeader& header() const override { return header_; }
  ObservationRead next(ObsEpoch& epoch) override;
  std::optional<ObservationProblem> error() const override { return std::nullopt; }
  std::vector<ObservationProblem> problems() const override;
  double progress() const override;
  std::string name() const override { return name_; }

  const UbxNavigationRecords& navigation() const { return navigation_; }
  const std::vector<UbxObservationEpoch>& decodedEpochs() const { return epochs_; }
  /// Decoding problems and the epochs the time policy dropped (EpochTimeRefused).
  const StreamCounters& counters() const { return counters_; }
  /// The epochs the time policy dropped, each with its reason and byte offset.
  const StreamCounters& timeScreen() const { return time_screen_; }
  const UbxDecoderStatistics& statistics() const { return statistics_; }

 private:
  std::string path_, name_;
  RinexObsHeader header_;
  std::vector<UbxObservationEpoch> epochs_;
  UbxNavigationRecords navigation_;
  void screenEpochTimes();

  StreamCounters counters_;
  StreamCounters time_screen_;
  UbxDecoderStatistics statistics_;
  std::size_t next_ = 0;
};

}  // namespace ppp
