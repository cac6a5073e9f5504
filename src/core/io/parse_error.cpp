#include "ppp_bayes_tree/io/parse_error.h"

#include <sstream>

namespace ppp {

namespace {
std::string formatMessage(const std::string& file, std::size_t line, const std::string& reason) {
  std::ostringstream os;
  os << file;
  if (line > 0) os << ":" << line;
  os << ": " << reason;
  return os.str();
}
}  // namespace

ParseError::ParseError(std::string file, std::size_t line, std::string reason)
    : std::runtime_error(formatMessage(file, line, reason)),
      file_(std::move(file)),
      line_(line),
      reason_(std::move(reason)) {}

void ParseReport::addProblem(std::size_t line, std::string reason) {
  ++problem_count_;
  if (problems_.size() < kMaxStoredProblems) problems_.push_back({line, std::move(reason)});
}

std::string ParseReport::summary(std::size_t max_lines) const {
  std::ostringstream os;
  for (const auto& [what, n] : counters_) os << "  " << what << ": " << n << "\n";
  if (problem_count_ == 0) {
    os << "  no problems found\n";
    return os.str();
  }
  os << "  " << problem_count_ << " problem(s):\n";
  std::size_t shown = 0;
  for (const auto& p : problems_) {
    if (shown++ >= max_lines) break;
    os << "    " << file_;
    if (p.line > 0) os << ":" << p.line;
    os << ": " << p.reason << "\n";
  }
  if (problem_count_ > shown) os << "    ... and " << (problem_count_ - shown) << " more\n";
  return os.str();
}

std::string ParseReport::headline(const std::string& file) const {
  if (clean()) return {};
  std::string text = file + ": " + std::to_string(problem_count_) + " problem(s) while reading";
  if (!problems_.empty()) {
    const ParseProblem& first = problems_.front();
    text += ", first: " + (first.line > 0 ? "line " + std::to_string(first.line) + ": " : std::string()) + first.reason;
  }
  return text;
}

}  // namespace ppp
