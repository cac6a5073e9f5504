#pragma once
// ImuLineScreen: the checks every IMU text reader applies to each line before a
// reading is kept: enough fields, every field a finite number, a time stamp
// (or sensor tick) that moves forward. Rejected lines and gaps are counted in
// the file's ParseReport by reason and stored with their line number; reading
// goes on.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"

namespace ppp {

enum class ImuLineProblem {
  ShortLine,      ///< fewer fields than the format has (e.g. a log cut mid-line)
  NotANumber,     ///< a field is empty, not numeric, NaN or infinite
  TimeBackwards,  ///< the stamp is earlier than the previous kept reading's
  DuplicateTime,  ///< the stamp equals the previous kept reading's
  Gap,            ///< the stamp jumps forward by more than the allowed gap (reading kept)
  TimeOutOfRange, ///< a time field outside its range (e.g. seconds of week >= 604800)
};
/// "short line", "not a number", "time going backwards", "duplicate time", "gap",
/// "time out of range".
std::string imuLineProblemText(ImuLineProblem problem);

class ImuLineScreen {
 public:
  /// `fields`: fields per line; `max_gap`: largest step of the stamp that is not a
  /// gap, in the stamp's unit.
  ImuLineScreen(ParseReport& report, std::size_t fields, double max_gap);

  /// The numbers of `line` (comma separated), or nothing when the line is
  /// rejected (counted, with `line_number`).
  std::optional<std::vector<double>> numbers(const std::string& line, std::size_t line_number);
  /// Whether the stamp `stamp` (same unit as max_gap) may follow the last kept one;
  /// counts backwards steps and duplicates (rejected) and gaps (kept).
  bool acceptStamp(double stamp, std::size_t line_number);
  /// Counts a rejected line with its reason.
  void reject(ImuLineProblem problem, std::size_t line_number, const std::string& detail);

 private:
  ParseReport& report_;
  std::size_t fields_;
  double max_gap_;
  std::optional<double> last_stamp_;
};

}  // namespace ppp
