#pragma once
// Raw numeric fields of RINEX 3 navigation records, as printed, for comparing
// two writers field by field "to the printed precision" (test helper).
//
// A record is its first line ("C01 2018 07 14 23 00 00" then 3 fields of 19
// characters) and the indented continuation lines (4 blanks, then up to 4
// fields of 19 characters), RINEX 3.04 section 6. Field k counts as in the
// RINEX tables: 0-2 clock, 3 IODE/AODE/IODnav, ... (a GLONASS record has 15).
// Two printed values agree when they are equal after rounding the more
// precise one to the digits of the less precise one (convbin prints 12
// significant digits ".ddddddddddddD+ee", we print 13 "d.ddddddddddddE+ee").
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ppp::test {

struct RawNavRecord {
  std::string satellite;  // "C01"
  std::string epoch;      // "2018 07 14 23 00 00"
  std::vector<std::optional<double>> fields;
  std::vector<std::string> text;  // the fields as printed (trimmed)
};

/// Every record of `path` whose satellite letter is in `systems` (e.g. "CR").
inline std::vector<RawNavRecord> readRawNavRecords(const std::string& path, const std::string& systems) {
  std::vector<RawNavRecord> out;
  std::ifstream in(path);
  std::string line;
  bool body = false;
  RawNavRecord* current = nullptr;
  auto field = [](const std::string& l, std::size_t start, RawNavRecord& r) {
    std::string f = start < l.size() ? l.substr(start, 19) : std::string();
    for (char& c : f)
      if (c == 'D' || c == 'd') c = 'E';
    const auto b = f.find_first_not_of(' ');
    f = b == std::string::npos ? std::string() : f.substr(b, f.find_last_not_of(' ') - b + 1);
    r.text.push_back(f);
    r.fields.push_back(f.empty() ? std::nullopt : std::optional<double>(std::strtod(f.c_str(), nullptr)));
  };
  while (std::getline(in, line)) {
    if (!body) {
      body = line.find("END OF HEADER") != std::string::npos;
      continue;
    }
    if (line.empty()) continue;
    if (line[0] != ' ') {
      current = nullptr;
      if (systems.find(line[0]) == std::string::npos) continue;
      out.push_back({line.substr(0, 3), line.substr(4, 19), {}, {}});
      current = &out.back();
      for (int j = 0; j < 3; ++j) field(line, 23 + 19 * static_cast<std::size_t>(j), *current);
    } else if (current != nullptr) {
      for (int j = 0; j < 4; ++j) field(line, 4 + 19 * static_cast<std::size_t>(j), *current);
    }
  }
  return out;
}

/// Significant digits of a printed number (".360000000000E+02" -> 12).
inline int printedDigits(const std::string& text) {
  std::size_t i = text.find_first_not_of("+-");
  if (i == std::string::npos) return 0;
  int digits = 0;
  if (text.compare(i, 2, "0.") == 0) ++i;  // "0.ddd": the leading zero is not significant
  for (; i < text.size() && text[i] != 'E' && text[i] != 'e'; ++i)
    if (text[i] >= '0' && text[i] <= '9') ++digits;
  return digits;
}

/// Half a unit in the last printed digit of `value` printed as `text`.
inline double halfUnit(double value, const std::string& text) {
  if (value == 0.0) return 0.0;
  const int digits = printedDigits(text);
  return 0.5 * std::pow(10.0, std::floor(std::log10(std::fabs(value))) - (digits - 1));
}

/// True when two printed values can be roundings of one number: they differ by at
/// most half a unit of the last digit of each (a 13-digit x...5 and its 12-digit
/// rounding differ by exactly half a unit of the coarser one plus the finer one's).
inline bool agreesToPrintedPrecision(double a, const std::string& a_text, double b, const std::string& b_text) {
  if (a == b) return true;
  const double tol = halfUnit(a, a_text) + halfUnit(b, b_text);
  return std::fabs(a - b) <= tol * (1.0 + 1e-9);
}

}  // namespace ppp::test
