#include "ppp_bayes_tree/io/imu/imu_line_screen.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ppp {
namespace {

std::vector<std::string> splitCommas(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();  // a trailing empty field
  return fields;
}

/// The finite number a whole field (surrounding blanks allowed) holds.
std::optional<double> finiteNumber(const std::string& field) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(begin, &end);
  if (end == begin || errno == ERANGE || !std::isfinite(value)) return std::nullopt;
  while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
  if (*end != '\0') return std::nullopt;
  return value;
}

}  // namespace

std::string imuLineProblemText(ImuLineProblem problem) {
  switch (problem) {
    case ImuLineProblem::ShortLine: return "short line";
    case ImuLineProblem::NotANumber: return "not a number";
    case ImuLineProblem::TimeBackwards: return "time going backwards";
    case ImuLineProblem::DuplicateTime: return "duplicate time";
    case ImuLineProblem::Gap: return "gap";
    case ImuLineProblem::TimeOutOfRange: return "time out of range";
  }
  return "unknown problem";
}

ImuLineScreen::ImuLineScreen(ParseReport& report, std::size_t fields, double max_gap)
    : report_(report), fields_(fields), max_gap_(max_gap) {}

void ImuLineScreen::reject(ImuLineProblem problem, std::size_t line_number, const std::string& detail) {
  report_.count(imuLineProblemText(problem));
  report_.addProblem(line_number, imuLineProblemText(problem) + ": " + detail);
}

std::optional<std::vector<double>> ImuLineScreen::numbers(const std::string& line, std::size_t line_number) {
  const std::vector<std::string> fields = splitCommas(line);
  if (fields.size() < fields_) {
    reject(ImuLineProblem::ShortLine, line_number,
           std::to_string(fields.size()) + " of " + std::to_string(fields_) + " fields");
    return std::nullopt;
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < fields_; ++i) {
    const auto v = finiteNumber(fields[i]);
    if (!v) {
      reject(ImuLineProblem::NotANumber, line_number, "field " + std::to_string(i + 1) + " '" + fields[i] + "'");
      return std::nullopt;
    }
    values.push_back(*v);
  }
  return values;
}

bool ImuLineScreen::acceptStamp(double stamp, std::size_t line_number) {
  if (last_stamp_) {
    const double step = stamp - *last_stamp_;
    const std::string detail = "step " + std::to_string(step) + " after " + std::to_string(*last_stamp_);
    if (step < 0.0) {
      reject(ImuLineProblem::TimeBackwards, line_number, detail);
      return false;
    }
    if (step == 0.0) {
      reject(ImuLineProblem::DuplicateTime, line_number, detail);
      return false;
    }
    if (step > max_gap_) {
      report_.count(imuLineProblemText(ImuLineProblem::Gap));
      report_.addProblem(line_number, imuLineProblemText(ImuLineProblem::Gap) + " (reading kept): " + detail);
    }
  }
  last_stamp_ = stamp;
  return true;
}

}  // namespace ppp
