// BLQ ocean loading table reader (see blq_reader.h for the layout).
#include "ppp_bayes_tree/io/products/blq_reader.h"

#include <cctype>
#include <cmath>
#include <cstdio>

#include "ppp_bayes_tree/io/fixed_width.h"

namespace ppp {

namespace {

constexpr std::size_t kN = OceanLoadingCoefficients::kConstituentCount;

bool isComment(std::string_view line) { return line.size() >= 2 && line[0] == '$' && line[1] == '$'; }

std::vector<std::string_view> words(std::string_view s, std::size_t max_words) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size() && out.size() < max_words) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

/// The 11 numbers of a data line, or nullopt with the reason.
std::optional<std::array<double, kN>> parseRow(std::string_view line, std::string& reason) {
  const auto w = words(line, kN + 1);
  if (w.size() != kN) {
    reason = "expected " + std::to_string(kN) + " values, found " + (w.size() > kN ? "more" : std::to_string(w.size()));
    return std::nullopt;
  }
  std::array<double, kN> v{};
  for (std::size_t i = 0; i < kN; ++i) {
    if (parseDouble(w[i], v[i]) != FieldStatus::Ok) {
      reason = "value " + std::to_string(i + 1) + " '" + std::string(w[i].substr(0, 20)) + "' is not a number";
      return std::nullopt;
    }
  }
  return v;
}

/// A line made only of numbers (a data row rather than a station line).
bool looksNumeric(std::string_view line) {
  const auto w = words(line, 2);
  double value = 0.0;
  return !w.empty() && parseDouble(w[0], value) == FieldStatus::Ok;
}

/// "lon/lat:  LON  LAT [H]" inside a "$$" comment.
void readLonLat(std::string_view comment, OceanLoadingCoefficients& c) {
  const std::size_t at = comment.find("lon/lat:");
  if (at == std::string_view::npos) return;
  const auto w = words(comment.substr(at + 8), 2);
  double lon = 0.0, lat = 0.0;
  if (w.size() == 2 && parseDouble(w[0], lon) == FieldStatus::Ok && parseDouble(w[1], lat) == FieldStatus::Ok &&
      std::fabs(lat) <= 90.0 && lon >= -360.0 && lon <= 360.0) {
    c.longitude_deg = lon;
    c.latitude_deg = lat;
  }
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& ch : out) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return out;
}

class BlqParser {
 public:
  BlqParser(LineSource& src, BlqFile& out) : src_(src), out_(out) {}

  void run() {
    std::string line;
    while (src_.next(line)) {
      if (isComment(line) || isBlank(line)) continue;
      if (looksNumeric(line)) {
        out_.report.addProblem(src_.lineNumber(), "numeric line outside a station block ignored");
        continue;
      }
      readStation(line);
    }
    if (src_.streamError()) out_.report.addProblem(src_.lineNumber(), "read stopped: " + *src_.streamError());
    if (src_.overlongLines() > 0)
      out_.report.addProblem(0, overlongLinesProblem(src_.overlongLines()));
  }

 private:
  void readStation(const std::string& name_line) {
    OceanLoadingCoefficients c;
    c.line = src_.lineNumber();
    c.station = std::string(words(name_line, 1)[0].substr(0, 64));
    std::array<std::array<double, kN>*, 6> rows = {&c.amplitude_radial_m, &c.amplitude_west_m,
                                                    &c.amplitude_south_m, &c.phase_radial_deg,
                                                    &c.phase_west_deg,    &c.phase_south_deg};
    std::string line;
    for (std::size_t r = 0; r < rows.size();) {
      if (!src_.next(line)) return problem(src_.lineNumber(), c, "file ends after " + std::to_string(r) + " of 6 rows");
      if (isComment(line)) {
        if (r == 0) readLonLat(line, c);
        continue;
      }
      if (isBlank(line)) continue;
      std::string reason;
      const auto values = parseRow(line, reason);
      if (!values) {
        // A non-numeric line is probably the next station: the block was cut short.
        if (!looksNumeric(line)) {
          const std::size_t at = src_.lineNumber();
          src_.unread(line);
          return problem(at, c, "only " + std::to_string(r) + " of 6 rows before the next station");
        }
        problem(src_.lineNumber(), c, "row " + std::to_string(r + 1) + ": " + reason);
        return skipRestOfBlock();
      }
      for (double v : *values) {
        const char* bad = nullptr;
        if (r < 3 && v < 0.0) bad = "negative amplitude";
        else if (r < 3 && v > 1.0) bad = "amplitude above 1 m";
        else if (r >= 3 && std::fabs(v) > 360.0) bad = "phase beyond +-360 deg";
        if (bad != nullptr) {
          problem(src_.lineNumber(), c, std::string("row ") + std::to_string(r + 1) + ": " + bad);
          return skipRestOfBlock();
        }
      }
      *rows[r++] = *values;
    }
    out_.stations.push_back(std::move(c));
  }

  /// After a bad row: drops the remaining data / comment lines of the block.
  void skipRestOfBlock() {
    std::string line;
    while (src_.next(line)) {
      if (isComment(line) || isBlank(line) || looksNumeric(line)) continue;
      src_.unread(line);
      return;
    }
  }

  void problem(std::size_t line, const OceanLoadingCoefficients& c, const std::string& reason) {
    out_.report.addProblem(line, "station " + c.station + " (line " + std::to_string(c.line) + ") skipped: " + reason);
  }

  LineSource& src_;
  BlqFile& out_;
};

}  // namespace

BlqLookup BlqFile::find(std::string_view station) const {
  BlqLookup out;
  const std::string wanted = upper(trim(station));
  if (wanted.size() < 4) {
    out.note = "station name '" + wanted + "' shorter than 4 characters";
    return out;
  }
  for (const auto& s : stations) {
    if (upper(s.station) == wanted) {
      out.coefficients = &s;
      return out;
    }
  }
  // Marker match: a 4-character name against the first 4 characters of a long
  // (9-character RINEX 3) name, in either direction.
  const OceanLoadingCoefficients* match = nullptr;
  std::size_t matches = 0;
  for (const auto& s : stations) {
    const std::string name = upper(s.station);
    const bool short_long = wanted.size() == 4 && name.size() == 9 && name.compare(0, 4, wanted) == 0;
    const bool long_short = name.size() == 4 && wanted.size() == 9 && wanted.compare(0, 4, name) == 0;
    if (short_long || long_short) {
      match = &s;
      ++matches;
    }
  }
  if (matches == 1) {
    out.coefficients = match;
    out.matched_by_marker = true;
    out.note = wanted + " not found, using " + match->station + " (same 4-character marker)";
  } else if (matches > 1) {
    out.note = wanted + " not found; its marker matches " + std::to_string(matches) + " stations";
  } else {
    out.note = wanted + " not found";
  }
  return out;
}

BlqFile readBlq(LineSource& source) {
  BlqFile out;
  out.report.setFile(source.name());
  BlqParser(source, out).run();
  out.report.count("stations read", out.stations.size());
  return out;
}

BlqFile readBlqFile(const std::string& path) {
  auto source = openLineSource(path);
  return readBlq(*source);
}

FileSummary summarizeBlqFile(const std::string& path) {
  const BlqFile f = readBlqFile(path);
  FileSummary s;
  s.path = path;
  s.type = "BLQ ocean loading";
  s.epoch_count = f.stations.size();
  s.count_label = "stations";
  s.facts.push_back(std::to_string(f.stations.size()) + " stations");
  std::size_t listed = 0;
  for (const auto& st : f.stations) {
    if (listed++ == 20) {
      s.facts.push_back("... more stations");
      break;
    }
    std::string fact = "station " + st.station;
    if (st.latitude_deg) {
      char buf[64];
      std::snprintf(buf, sizeof(buf), " lon %.4f lat %.4f", *st.longitude_deg, *st.latitude_deg);
      fact += buf;
    }
    char m2[48];
    std::snprintf(m2, sizeof(m2), ", M2 radial %.1f mm", st.amplitude_radial_m[0] * 1e3);
    s.facts.push_back(fact + m2);
  }
  s.report = f.report;
  return s;
}

}  // namespace ppp
