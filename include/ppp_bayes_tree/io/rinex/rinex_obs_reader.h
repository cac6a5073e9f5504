#pragma once
// RinexObsReader: streams the epochs of a RINEX observation file (2.10/2.11,
// 3.02-3.05, 4.00), plain, gzip or Compact RINEX (Hatanaka), one at a time.
//
// Bad input: a malformed header throws ParseError from
// the constructor / open(). A malformed epoch or record is skipped with
// report().addProblem(line, reason) and reading resynchronises on the next
// epoch line. Special records (event flags 2-5) are skipped and counted. Time
// going backwards and duplicate epochs are kept but counted (the consumer
// decides). Line numbers are those of the (decompressed) RINEX text; problems
// found by the Compact RINEX decoder name the line of the .crx file.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

class RinexObsReader {
 public:
  /// Reads the header at once (throws ParseError). The source should come from
  /// observationSource()/openObservationSource() for Compact RINEX support.
  explicit RinexObsReader(std::unique_ptr<LineSource> source);
  /// Opens a file: plain, gzip, Compact RINEX and gzip Compact RINEX alike.
  /// Throws FileOpenError or ParseError.
  static RinexObsReader open(const std::string& path);

  RinexObsReader(RinexObsReader&&) noexcept;
  RinexObsReader& operator=(RinexObsReader&&) noexcept;
  ~RinexObsReader();

  const RinexObsHeader& header() const { return header_; }
  /// Reads the next observation epoch (flags 0, 1 and 6) into `epoch`, reusing
  /// its storage. Returns false at the end of the data.
  bool next(ObsEpoch& epoch);
  const ParseReport& report() const { return report_; }
  /// Counters also kept in report() under readable names.
  std::size_t specialRecordsSkipped() const { return special_records_; }
  std::size_t epochsBackwards() const { return backwards_; }
  std::size_t duplicateEpochs() const { return duplicates_; }
  /// True when the source is Compact RINEX.
  bool compactRinex() const { return compact_; }
  const LineSource& source() const { return *source_; }

 private:
  struct EpochHeader;
  bool readEpoch(ObsEpoch& epoch);
  bool parseEpochLine(const std::string& line, EpochHeader& out, std::string& reason);
  bool readSatelliteList(EpochHeader& eh, std::string& reason);
  bool readRinex3Records(const EpochHeader& eh, ObsEpoch& epoch);
  bool readRinex2Records(const EpochHeader& eh, ObsEpoch& epoch);
  void skipSpecialRecords(const EpochHeader& eh);
  void resynchronise();
  bool looksLikeEpochLine(const std::string& line) const;
  void drainSourceProblems();
  void checkOrder(const ObsEpoch& epoch);
  void parseObservation(std::string_view field, Observation& obs, double scale) const;

  std::unique_ptr<LineSource> source_;
  RinexObsHeader header_;
  ParseReport report_;
  std::string line_;
  std::vector<SatelliteId> sats_;
  std::optional<GnssTime> last_time_;
  std::size_t special_records_ = 0;
  std::size_t backwards_ = 0;
  std::size_t duplicates_ = 0;
  bool compact_ = false;
  bool stream_error_reported_ = false;
  bool ended_ = false;
};

}  // namespace ppp
