#pragma once
// Typed errors and per-file problem reports shared by every reader.
//
// Policy: a malformed *header* throws ParseError
// naming the file, the line and the reason; a malformed *record* is skipped,
// counted in the file's ParseReport, and reading goes on.
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace ppp {

class ParseError : public std::runtime_error {
 public:
  ParseError(std::string file, std::size_t line, std::string reason);
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }  // 1-based; 0 when not tied to a line
  const std::string& reason() const { return reason_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string reason_;
};

/// The file could not be opened or read at all.
class FileOpenError : public std::runtime_error {
 public:
  explicit FileOpenError(const std::string& what) : std::runtime_error(what) {}
};

struct ParseProblem {
  std::size_t line = 0;
  std::string reason;
};

class ParseReport {
 public:
  static constexpr std::size_t kMaxStoredProblems = 200;

  explicit ParseReport(std::string file = {}) : file_(std::move(file)) {}

  /// Records a skipped / malformed record. All are counted; the first
  /// kMaxStoredProblems are kept with their line and reason.
  void addProblem(std::size_t line, std::string reason);
  /// Increments a named counter (e.g. "special event records skipped").
  void count(const std::string& what, std::size_t n = 1) { counters_[what] += n; }

  const std::string& file() const { return file_; }
  void setFile(std::string file) { file_ = std::move(file); }
  std::size_t problemCount() const { return problem_count_; }
  const std::vector<ParseProblem>& problems() const { return problems_; }
  const std::map<std::string, std::size_t>& counters() const { return counters_; }
  bool clean() const { return problem_count_ == 0; }
  /// Multi-line human-readable text: counters, then the stored problems.
  std::string summary(std::size_t max_lines = 20) const;
  /// One line for a file read with problems: "<file>: N problem(s) while reading,
  /// first: line L: reason" (empty when clean).
  std::string headline(const std::string& file) const;

 private:
  std::string file_;
  std::size_t problem_count_ = 0;
  std::vector<ParseProblem> problems_;
  std::map<std::string, std::size_t> counters_;
};

}  // namespace ppp
