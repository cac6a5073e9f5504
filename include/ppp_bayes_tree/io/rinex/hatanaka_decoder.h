#pragma once
// Compact RINEX (Hatanaka) decoder: CRINEX 1.0 (over RINEX 2) and CRINEX 3.0
// (over RINEX 3 and 4), written after Hatanaka (2008), "A Compression Format and
// Tools for GNSS Observation Data", Bull. GSI 55, 21-30, and the RNXCMP 4.1
// documentation.
//
// The decoder is a LineSource that wraps another LineSource (plain or gzip) and
// yields the restored RINEX lines, so every RINEX reader can read .crx, .YYd and
// .crx.gz files unchanged. Restored lines carry no trailing blanks (as CRX2RNX
// writes them). Line numbers are those of the restored text.
//
// Corrupt compact data: the epoch in error is dropped, the problem recorded
// (takeProblems(), with the .crx line number) and decoding resumes at the next
// epoch whose arcs are all re-initialised, as CRX2RNX -s does. Huge difference
// orders, numbers beyond 18 digits, sums that overflow 64 bits and absurd
// satellite or type counts are rejected, never allocated.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"

namespace ppp {

class HatanakaDecoder final : public LineSource {
 public:
  static constexpr int kMaxDifferenceOrder = 9;   // one digit in "n&"
  static constexpr int kMaxTypesPerSystem = 200;
  static constexpr int kMaxSatellites = 999;       // three digits in the epoch line

  /// Reads the two CRINEX header lines at once; throws ParseError when they are
  /// not a CRINEX 1.0 / 3.0 header.
  explicit HatanakaDecoder(std::unique_ptr<LineSource> inner);
  ~HatanakaDecoder() override;

  std::size_t bytesRead() const override { return inner_->bytesRead(); }
  bool compressed() const override { return inner_->compressed(); }
  int crinexVersion() const { return crinex_major_; }
  const LineSource& inner() const { return *inner_; }

  /// Problems found since the last call (corrupt epochs skipped), then cleared.
  std::vector<ParseProblem> takeProblems();
  std::size_t problemCount() const { return problem_count_; }

 protected:
  std::size_t readBytes(char* buffer, std::size_t capacity) override;

 private:
  struct Series;
  struct SatState;
  void decodeMore();
  void headerLine(std::string& line);
  bool dataEpoch();
  bool decodeEpoch(const std::string& first_line);
  int restoreEpochLine(const std::string& diff_line);  // satellite count, -1 on a problem
  std::size_t listColumn() const;                      // of the satellite list in the epoch line
  bool decodeClock(bool& has_clock);
  bool writeEpochLines(int nsat, bool has_clock);
  bool decodeSatellite(int i);
  const SatState* previousState(int i, const SatState& sat) const;
  bool readSatelliteFields(SatState& sat, bool has_previous);
  bool writeSatelliteRecord(SatState& sat);
  bool eventRecord();
  void problem(const std::string& reason);
  bool nextInner(std::string& line);
  void emit(std::string_view line);

  std::unique_ptr<LineSource> inner_;
  int crinex_major_ = 3;   // 1 or 3
  int rinex_major_ = 3;    // 2, 3 or 4
  bool in_header_ = true;
  bool need_init_ = true;  // the next epoch line must be an initialisation
  bool finished_ = false;
  std::string out_;        // restored text waiting to be read
  std::size_t out_pos_ = 0;
  std::string in_line_, epoch_line_, work_, epoch_out_;
  std::vector<int> ntype_by_letter_;  // 256 entries, -1 unknown
  int rinex2_ntype_ = -1;
  std::vector<SatState> prev_, cur_;
  std::unique_ptr<Series> clock_;
  std::vector<ParseProblem> problems_;
  std::size_t problem_count_ = 0;
};

/// True when the line is a CRINEX first line ("COMPACT RINEX FORMAT").
bool isCompactRinexFirstLine(std::string_view line);
/// Wraps `source` in a HatanakaDecoder when its content is Compact RINEX (first
/// line), otherwise returns it unchanged. Throws ParseError on a bad CRINEX header.
std::unique_ptr<LineSource> observationSource(std::unique_ptr<LineSource> source);
/// openLineSource(path) (plain or gzip) then observationSource().
std::unique_ptr<LineSource> openObservationSource(const std::string& path);

}  // namespace ppp
