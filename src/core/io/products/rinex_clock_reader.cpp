// RINEX clock reader (2.0x, 3.00-3.04). Header labels sit in columns 61-80;
// in 3.04 the 9-character station name pushes the "SOLN STA NAME / NUM" label to
// columns 66-85, so the label is looked for at both places.
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "ppp_bayes_tree/io/fixed_width.h"

namespace ppp {
namespace {

constexpr std::array<std::string_view, 22> kKnownLabels{
    "RINEX VERSION / TYPE", "PGM / RUN BY / DATE", "COMMENT", "SYS / # / OBS TYPES",
    "TIME SYSTEM ID", "LEAP SECONDS", "LEAP SECONDS GNSS", "SYS / DCBS APPLIED",
    "SYS / PCVS APPLIED", "# / TYPES OF DATA", "STATION NAME / NUM", "STATION CLK REF",
    "ANALYSIS CENTER", "# OF CLK REF", "ANALYSIS CLK REF", "# OF SOLN STA / TRF",
    "SOLN STA NAME / NUM", "# OF SOLN SATS", "PRN LIST", "END OF HEADER",
    "DATA TYPES", "SYS / OBS TYPES"};

bool isKnownLabel(std::string_view label) {
  return std::find(kKnownLabels.begin(), kKnownLabels.end(), label) != kKnownLabels.end();
}

/// Splits text on blanks (at most `max_tokens`, so a line can never make it grow without bound).
std::vector<std::string_view> tokens(std::string_view text, std::size_t max_tokens = 32) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < text.size() && out.size() < max_tokens) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
    if (i > b) out.push_back(text.substr(b, i - b));
  }
  return out;
}

class ClockParser {
 public:
  ClockParser(LineSource& source, const RinexClockReadOptions& options) : src_(source), options_(options) {
    file_.report.setFile(source.name());
  }

  RinexClockFile run() {
    readHeader();
    readRecords();
    finish();
    return std::move(file_);
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const {
    throw ParseError(src_.name(), src_.lineNumber(), reason);
  }

  bool nextLine() { return src_.next(line_); }  // LineSource strips "\r\n"

  // ---------------------------------------------------------------- header
  void readHeader() {
    if (!nextLine()) fail("empty file: no RINEX clock header");
    bool first = true;
    for (;;) {
      std::string_view content, label;
      splitLabel(content, label);
      if (first) {
        if (label != "RINEX VERSION / TYPE") fail("first line must be 'RINEX VERSION / TYPE'");
        readVersionLine(content);
        first = false;
      } else if (label == "END OF HEADER") {
        break;
      } else {
        readHeaderLine(content, label);
      }
      if (!nextLine()) fail("file ends before 'END OF HEADER'");
    }
    file_.header.header_lines = src_.lineNumber();
    const auto& h = file_.header;
    if (h.station_count && *h.station_count != static_cast<int>(h.stations.size())) {
      file_.report.count("'# OF SOLN STA / TRF' differs from the SOLN STA NAME lines");
    }
    if (h.satellite_count && *h.satellite_count != static_cast<int>(h.prn_list.size())) {
      file_.report.count("'# OF SOLN SATS' differs from the PRN LIST");
    }
  }

  // The label is the known label the line ends with (the longest one, so that
  // "LEAP SECONDS GNSS" wins over "LEAP SECONDS"), starting at column 61 or
  // later; 3.04 lines with 9-character names put it at column 66.
  void splitLabel(std::string_view& content, std::string_view& label) const {
    std::string_view line(line_);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    std::string_view best;
    for (std::string_view known : kKnownLabels) {
      if (known.size() > best.size() && line.size() >= known.size() &&
          line.substr(line.size() - known.size()) == known && line.size() - known.size() >= 55) {
        best = known;
      }
    }
    if (!best.empty()) {
      content = column(line_, 0, line.size() - best.size());
      label = best;
      return;
    }
    if (isBlank(line_)) {
      content = {};
      label = {};
      return;
    }
    if (line_.size() <= 60) fail("header line without a label in columns 61-80");
    content = column(line_, 0, 60);
    label = trim(column(line_, 60, 40));
  }

  void readVersionLine(std::string_view content) {
    RinexClockHeader& h = file_.header;
    // F9.2,11X,A1 ('C'),19X,A1 (satellite system, 3.x)
    h.version_text = std::string(trim(column(content, 0, 9)));
    if (parseDouble(column(content, 0, 9), h.version) != FieldStatus::Ok) fail("malformed format version");
    if (h.version < 2.0 || h.version >= 4.0) fail("unsupported RINEX clock version " + h.version_text);
    if (trim(column(content, 20, 1)) != "C") fail("file type in column 21 is not 'C' (clock data)");
    const std::string_view sys = column(content, 40, 1);
    h.satellite_system = sys.empty() ? ' ' : sys.front();
  }

  static long long requireInt(std::string_view field, const ClockParser& p, const char* what) {
    long long v = 0;
    if (parseInt(field, v) != FieldStatus::Ok) p.fail(std::string("malformed ") + what);
    return v;
  }

  void readHeaderLine(std::string_view content, std::string_view label) {
    RinexClockHeader& h = file_.header;
    if (label.empty()) {
      file_.report.count("blank header lines");
    } else if (label == "PGM / RUN BY / DATE") {
      h.program = std::string(trim(column(content, 0, 20)));
      h.run_by = std::string(trim(column(content, 20, 20)));
      h.date = std::string(trim(column(content, 40, 20)));
    } else if (label == "COMMENT") {
      h.comments.emplace_back(trim(content));
      h.comment_lines.push_back(src_.lineNumber());
    } else if (label == "SYS / PCVS APPLIED") {
      // A1,1X,A17,1X,A40: system, program, source (the ANTEX file name).
      std::string source(trim(column(content, 20, 40)));
      const auto dot = source.find_last_of('.');
      if (dot != std::string::npos) source = source.substr(0, dot);
      if (!source.empty() && h.pcvs_applied.empty()) h.pcvs_applied = source;
    } else if (label == "TIME SYSTEM ID") {
      const std::string code(trim(content));
      const auto ts = parseTimeSystem(code);
      if (!ts) fail("unknown time system '" + code + "'");
      h.time_system = *ts;
    } else if (label == "LEAP SECONDS") {
      const long long n = requireInt(column(content, 0, 6), *this, "LEAP SECONDS");
      if (n < 0 || n > 100) fail("LEAP SECONDS out of range");
      h.leap_seconds = static_cast<int>(n);
    } else if (label == "# / TYPES OF DATA") {
      const auto t = tokens(content, 12);
      if (t.empty()) fail("malformed '# / TYPES OF DATA'");
      for (std::size_t i = 1; i < t.size(); ++i) h.data_types.emplace_back(t[i]);
    } else if (label == "ANALYSIS CENTER") {
      h.analysis_center_id = std::string(trim(column(content, 0, 3)));
      h.analysis_center_name = std::string(trim(column(content, 5, 55)));
    } else if (label == "# OF SOLN STA / TRF") {
      const long long n = requireInt(column(content, 0, 6), *this, "'# OF SOLN STA / TRF'");
      if (n < 0) fail("negative number of stations");
      h.station_count = static_cast<int>(std::min<long long>(n, 1000000));
      h.reference_frame = std::string(trim(column(content, 10, 50)));
    } else if (label == "SOLN STA NAME / NUM") {
      readStation(content);
    } else if (label == "# OF SOLN SATS") {
      const long long n = requireInt(column(content, 0, 6), *this, "'# OF SOLN SATS'");
      if (n < 0) fail("negative number of satellites");
      h.satellite_count = static_cast<int>(std::min<long long>(n, 1000000));
    } else if (label == "PRN LIST") {
      // 15(A3,1X)
      for (int k = 0; k < 15; ++k) {
        const std::string_view field = column(content, 4 * k, 3);
        if (isBlank(field)) continue;
        const auto sat = SatelliteId::parse(field);
        if (!sat) fail("malformed satellite '" + std::string(field) + "' in PRN LIST");
        h.prn_list.push_back(*sat);
      }
    } else if (!isKnownLabel(label)) {
      file_.report.count("unknown header labels ignored");
    }
  }

  // A4,1X,A20,3(I11,1X) in 2.x/3.00-3.02; A9,1X,A20,... in 3.04. Read by tokens:
  // name first, the three coordinates (integer mm) last, the identifier between.
  void readStation(std::string_view content) {
    const auto t = tokens(content, 16);
    if (t.size() < 4) fail("malformed 'SOLN STA NAME / NUM': needs a name and X, Y, Z");
    ClockStation st;
    st.name = std::string(t.front());
    for (int i = 0; i < 3; ++i) {
      long long mm = 0;
      if (parseInt(t[t.size() - 3 + i], mm) != FieldStatus::Ok || std::llabs(mm) > 100000000000LL) {
        fail("malformed coordinate in 'SOLN STA NAME / NUM' for " + st.name);
      }
      st.position_ecef_m[i] = static_cast<double>(mm) * 1e-3;  // mm -> m
    }
    for (std::size_t i = 1; i + 3 < t.size(); ++i) {
      if (!st.domes.empty()) st.domes += ' ';
      st.domes += std::string(t[i]);
    }
    file_.header.stations.push_back(std::move(st));
  }

  // ---------------------------------------------------------------- records
  void readRecords() {
    while (nextLine()) {
      if (isBlank(line_)) {
        file_.report.count("blank lines skipped");
        continue;
      }
      const std::string_view type = column(line_, 0, 2);
      if (type == "AS" || type == "AR") {
        readClockRecord(type == "AS");
      } else if (type == "CR" || type == "DR" || type == "MS") {
        file_.report.count(std::string(type) + " records skipped");
        skipContinuation();
      } else {
        file_.report.addProblem(src_.lineNumber(), "unrecognised record '" + std::string(column(line_, 0, 8)) + "'");
      }
    }
    if (src_.streamError()) {
      file_.report.addProblem(src_.lineNumber(), "compressed stream error: " + *src_.streamError());
    }
    if (src_.overlongLines() > 0) file_.report.count("overlong lines cut", src_.overlongLines());
  }

  // Continuation lines of skipped records start with a blank or a number.
  void skipContinuation() {
    while (nextLine()) {
      const char c = line_.empty() ? ' ' : line_[0];
      if (!(c == ' ' || c == '-' || c == '+' || (c >= '0' && c <= '9')) || isBlank(line_)) {
        src_.unread(line_);
        return;
      }
    }
  }

  // A2,1X,A4,1X,I4,4(1X,I2),1X,F9.6,1X,I2,3X,2(1X,E19.12)   (2.x, 3.00-3.02)
  // A2,1X,A9,1X,I4,4(1X,I2),1X,F9.6,1X,I2,3X,2(1X,E19.12)   (3.04)
  // The layout is told apart by the year: columns 9-12 in the old one.
  void readClockRecord(bool satellite) {
    const std::size_t line_no = src_.lineNumber();
    // 1. The layout and the name; records of systems or kinds not kept are skipped.
    long long year_probe = 0;
    const bool old_layout = parseInt(column(line_, 8, 4), year_probe) == FieldStatus::Ok;
    const std::string_view name_text = trim(column(line_, 3, old_layout ? 4 : 9));
    if (!keepsRecordKind(satellite, name_text)) return;
    const std::string name(name_text);
    // 2. The epoch and the number of values.
    const auto t = tokens(column(line_, old_layout ? 8 : 13, std::string::npos), 12);
    ClockEpochFields e;
    if (!parseEpochFields(t, e) || e.n < 1 || e.n > 6) {
      file_.report.addProblem(line_no, "malformed clock record: skipped");
      if (e.ok && e.n > 2) skipContinuation();
      return;
    }
    if (satellite && (options_.filter.first || options_.filter.last)) {
      const auto time = toGpst(e.y, e.mo, e.d, e.h, e.mi, e.s);
      if (time && !options_.filter.keepsTime(*time)) {
        file_.report.count("AS records outside the time window skipped");
        if (e.n > 2) skipContinuation();
        return;
      }
    }
    // 3. The values: two on the line, the others on a continuation line.
    std::array<double, 6> v{};
    std::size_t have = 0;
    if (!readLineValues(t, e.n, line_no, v, have)) return;
    if (e.n > 2 && !readContinuation(static_cast<std::size_t>(e.n), v, have)) {
      file_.report.addProblem(line_no, "clock record continuation line missing or malformed: skipped");
      return;
    }
    // 4. The record.
    const auto time = toGpst(e.y, e.mo, e.d, e.h, e.mi, e.s);
    if (!time) {
      file_.report.addProblem(line_no, "invalid epoch in clock record: skipped");
      return;
    }
    store(satellite, name, clockRecord(*time, v, e.n), line_no);
  }

  /// False (counted, continuation skipped) for AS records of systems not kept and,
  /// unless asked for, AR records.
  bool keepsRecordKind(bool satellite, std::string_view name_text) {
    if (satellite && !name_text.empty() && !options_.filter.systems.empty()) {
      const auto sys = systemFromLetter(name_text[0]);
      if (sys && !options_.filter.keepsSystem(*sys)) {
        file_.report.count("AS records of other systems skipped");
        skipContinuation();
        return false;
      }
    }
    if (!satellite && !options_.keep_receiver_clocks) {
      file_.report.count("AR records skipped");
      skipContinuation();
      return false;
    }
    return true;
  }

  /// The epoch and value count of a clock record (tokens after the name).
  struct ClockEpochFields {
    long long y = 0, mo = 0, d = 0, h = 0, mi = 0, n = 0;
    double s = 0;
    bool ok = false;
  };
  static bool parseEpochFields(const std::vector<std::string_view>& t, ClockEpochFields& e) {
    e.ok = t.size() >= 8 && parseInt(t[0], e.y) == FieldStatus::Ok && parseInt(t[1], e.mo) == FieldStatus::Ok &&
           parseInt(t[2], e.d) == FieldStatus::Ok && parseInt(t[3], e.h) == FieldStatus::Ok &&
           parseInt(t[4], e.mi) == FieldStatus::Ok && parseDouble(t[5], e.s) == FieldStatus::Ok &&
           parseInt(t[6], e.n) == FieldStatus::Ok;
    return e.ok;
  }

  /// The (up to two) values on the record line; false (a problem) when one is
  /// malformed or fewer than announced.
  bool readLineValues(const std::vector<std::string_view>& t, long long n, std::size_t line_no,
                      std::array<double, 6>& v, std::size_t& have) {
    for (std::size_t i = 7; i < t.size() && have < 2; ++i) {
      if (parseDouble(t[i], v[have]) != FieldStatus::Ok) {
        file_.report.addProblem(line_no, "malformed value in clock record: skipped");
        if (n > 2) skipContinuation();
        return false;
      }
      ++have;
    }
    if (static_cast<long long>(have) < std::min<long long>(n, 2)) {
      file_.report.addProblem(line_no, "clock record has fewer values than announced: skipped");
      if (n > 2) skipContinuation();
      return false;
    }
    return true;
  }

  static ClockRecord clockRecord(const GnssTime& time, const std::array<double, 6>& v, long long n) {
    ClockRecord rec;
    rec.time = time;
    rec.clock_bias_s = v[0];
    if (n >= 2) rec.clock_bias_sigma_s = v[1];
    if (n >= 3) rec.clock_rate_s_per_s = v[2];
    if (n >= 4) rec.clock_rate_sigma_s_per_s = v[3];
    if (n >= 5) rec.clock_acceleration_per_s = v[4];
    if (n >= 6) rec.clock_acceleration_sigma_per_s = v[5];
    return rec;
  }

  bool readContinuation(std::size_t n, std::array<double, 6>& v, std::size_t& have) {
    if (!nextLine()) return false;
    const auto t = tokens(line_, 8);
    const char c = line_.empty() ? ' ' : line_[0];
    const bool looks_numeric = c == ' ' || c == '-' || c == '+' || (c >= '0' && c <= '9');
    if (!looks_numeric || t.size() < n - have) {
      if (!looks_numeric) src_.unread(line_);
      return false;
    }
    for (std::size_t i = 0; have < n; ++i) {
      if (parseDouble(t[i], v[have]) != FieldStatus::Ok) return false;
      ++have;
    }
    return true;
  }

  std::optional<GnssTime> toGpst(long long y, long long mo, long long d, long long h, long long mi,
                                 double s) const {
    if (y < 1980 || y > 2200 || !isValidDate(static_cast<int>(y), static_cast<int>(mo), static_cast<int>(d)) ||
        h < 0 || h > 23 || mi < 0 || mi > 59 || !(s >= 0.0 && s < 61.0)) {
      return std::nullopt;
    }
    CalendarTime c{static_cast<int>(y), static_cast<int>(mo), static_cast<int>(d),
                   static_cast<int>(h), static_cast<int>(mi), s};
    try {
      return GnssTime::fromCalendar(c, file_.header.time_system);
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
  }

  void store(bool satellite, const std::string& name, const ClockRecord& rec, std::size_t line_no) {
    if (satellite) {
      const auto sat = SatelliteId::parse(name);
      if (!sat) {
        file_.report.addProblem(line_no, "malformed satellite '" + name + "' in AS record: skipped");
        return;
      }
      file_.satellite_clocks[*sat].push_back(rec);
    } else if (options_.keep_receiver_clocks) {
      if (name.empty()) {
        file_.report.addProblem(line_no, "AR record without a receiver name: skipped");
        return;
      }
      file_.receiver_clocks[name].push_back(rec);
    } else {
      file_.report.count("AR records skipped");
    }
  }

  // Sorts each series by time (files are normally already in order) and drops
  // repeated epochs, keeping the first.
  template <class Map>
  void sortSeries(Map& map) {
    for (auto& [key, series] : map) {
      const auto by_time = [](const ClockRecord& a, const ClockRecord& b) { return a.time < b.time; };
      if (!std::is_sorted(series.begin(), series.end(), by_time)) {
        std::stable_sort(series.begin(), series.end(), by_time);
      }
      const auto same = [](const ClockRecord& a, const ClockRecord& b) { return a.time == b.time; };
      const auto end = std::unique(series.begin(), series.end(), same);
      const auto dropped = static_cast<std::size_t>(series.end() - end);
      if (dropped > 0) file_.report.count("repeated clock epochs dropped", dropped);
      series.erase(end, series.end());
    }
  }

  void finish() {
    sortSeries(file_.satellite_clocks);
    sortSeries(file_.receiver_clocks);
  }

  LineSource& src_;
  RinexClockReadOptions options_;
  std::string line_;
  RinexClockFile file_;
};

/// Most common spacing between consecutive distinct epochs.
std::optional<double> modalSpacing(const std::vector<GnssTime>& sorted_epochs) {
  std::map<long long, std::size_t> hist;  // in ms
  for (std::size_t i = 1; i < sorted_epochs.size(); ++i) {
    ++hist[std::llround((sorted_epochs[i] - sorted_epochs[i - 1]) * 1000.0)];
  }
  if (hist.empty()) return std::nullopt;
  const auto best = std::max_element(hist.begin(), hist.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  return static_cast<double>(best->first) * 1e-3;
}

}  // namespace

RinexClockFile readRinexClock(LineSource& source, const RinexClockReadOptions& options) {
  return ClockParser(source, options).run();
}

RinexClockFile readRinexClock(const std::string& path, const RinexClockReadOptions& options) {
  auto source = openLineSource(path);
  return readRinexClock(*source, options);
}

RinexClockHeader readRinexClockHeader(const std::string& path) {
  auto source = openLineSource(path);
  std::string text, line;
  while (source->next(line)) {
    text += line;
    text += '\n';
    if (line.size() >= 60 && trim(column(line, 60, 20)) == "END OF HEADER") break;
  }
  auto header_only = memoryLineSource(std::move(text), source->name());
  RinexClockReadOptions options;
  options.keep_receiver_clocks = false;
  return readRinexClock(*header_only, options).header;
}

FileSummary summarizeClock(const RinexClockFile& file, const std::string& path) {
  const RinexClockHeader& h = file.header;
  FileSummary s;
  s.path = path;
  s.type = "RINEX clock";
  s.version = h.version_text;
  std::vector<GnssTime> epochs;
  for (const auto& [sat, series] : file.satellite_clocks) {
    s.satellites[sat.system].insert(sat);
    for (const auto& r : series) epochs.push_back(r.time);
  }
  if (epochs.empty()) {
    for (const auto& [name, series] : file.receiver_clocks) {
      for (const auto& r : series) epochs.push_back(r.time);
    }
  }
  std::sort(epochs.begin(), epochs.end());
  epochs.erase(std::unique(epochs.begin(), epochs.end()), epochs.end());
  if (!epochs.empty()) {
    s.first_epoch = epochs.front();
    s.last_epoch = epochs.back();
  }
  s.interval_s = modalSpacing(epochs);
  s.epoch_count = epochs.size();
  s.facts.push_back("analysis center " + h.analysis_center_id + " (" + h.analysis_center_name + ")");
  s.facts.push_back("time system " + std::string(timeSystemCode(h.time_system)));
  if (h.leap_seconds) s.facts.push_back("leap seconds " + std::to_string(*h.leap_seconds));
  s.facts.push_back("stations with coordinates " + std::to_string(h.stations.size()) +
                    (h.reference_frame.empty() ? "" : " (" + h.reference_frame + ")"));
  s.facts.push_back("satellites in PRN LIST " + std::to_string(h.prn_list.size()));
  std::size_t as = 0, ar = 0;
  for (const auto& [k, v] : file.satellite_clocks) as += v.size();
  for (const auto& [k, v] : file.receiver_clocks) ar += v.size();
  s.facts.push_back("AS records " + std::to_string(as) + ", AR records " + std::to_string(ar) + " (" +
                    std::to_string(file.receiver_clocks.size()) + " receivers)");
  s.report = file.report;
  return s;
}

FileSummary summarizeClockFile(const std::string& path) { return summarizeClock(readRinexClock(path), path); }

}  // namespace ppp
