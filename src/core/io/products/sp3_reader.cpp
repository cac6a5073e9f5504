// SP3-a/b/c/d reader. Column numbers below are the 1-based columns of the SP3-d
// document (Hilla 2016); the code uses 0-based offsets (column - 1).
#include "ppp_bayes_tree/io/products/sp3_reader.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/io/fixed_width.h"

namespace ppp {
namespace {

// SP3-d: "Bad or absent values are set to 0.000000" (positions, velocities) and
// "999999.999999" (clock, clock rate). Anything at or above 999999 is treated as
// the marker, whatever the number of 9s after the decimal point.
constexpr double kBadClockMarker = 999999.0;

bool startsWith(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && s.substr(0, prefix.size()) == prefix;
}

class Sp3Parser {
 public:
  Sp3Parser(LineSource& source, const Sp3ReadOptions& options) : src_(source), options_(options) {
    file_.report.setFile(source.name());
  }

  Sp3File run() {
    readHeader();
    setWindow();
    readRecords();
    return std::move(file_);
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const {
    throw ParseError(src_.name(), src_.lineNumber(), reason);
  }

  bool nextLine() { return src_.next(line_); }  // LineSource strips "\r\n"

  long long headerInt(std::size_t start, std::size_t width, const char* what) const {
    long long v = 0;
    if (parseInt(column(line_, start, width), v) != FieldStatus::Ok) {
      fail(std::string("malformed ") + what + " '" + std::string(column(line_, start, width)) + "'");
    }
    return v;
  }
  double headerDouble(std::size_t start, std::size_t width, const char* what) const {
    double v = 0;
    if (parseDouble(column(line_, start, width), v) != FieldStatus::Ok) {
      fail(std::string("malformed ") + what + " '" + std::string(column(line_, start, width)) + "'");
    }
    return v;
  }

  // Calendar date/time in columns 4-31 of line 1 and of "*" epoch lines
  // (I4, 4(1X,I2), 1X, F11.8). Returns nullopt when a field is malformed.
  static std::optional<CalendarTime> parseCalendar(std::string_view line) {
    long long y = 0, mo = 0, d = 0, h = 0, mi = 0;
    double s = 0;
    if (parseInt(column(line, 3, 4), y) != FieldStatus::Ok ||
        parseInt(column(line, 8, 2), mo) != FieldStatus::Ok ||
        parseInt(column(line, 11, 2), d) != FieldStatus::Ok ||
        parseInt(column(line, 14, 2), h) != FieldStatus::Ok ||
        parseInt(column(line, 17, 2), mi) != FieldStatus::Ok ||
        parseDouble(column(line, 20, 11), s) != FieldStatus::Ok) {
      return std::nullopt;
    }
    if (y < 1980 || y > 2200 || !isValidDate(static_cast<int>(y), static_cast<int>(mo), static_cast<int>(d)) ||
        h < 0 || h > 23 || mi < 0 || mi > 59 || !(s >= 0.0 && s < 61.0)) {
      return std::nullopt;
    }
    CalendarTime c;
    c.year = static_cast<int>(y);
    c.month = static_cast<int>(mo);
    c.day = static_cast<int>(d);
    c.hour = static_cast<int>(h);
    c.minute = static_cast<int>(mi);
    c.second = s;
    return c;
  }

  std::optional<GnssTime> toGpst(const CalendarTime& c) const {
    try {
      return GnssTime::fromCalendar(c, file_.header.time_system);
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
  }

  // ---------------------------------------------------------------- header
  void readHeader() {
    Sp3Header& h = file_.header;
    if (!nextLine()) fail("empty file: no SP3 header");
    readLine1();
    if (!nextLine() || !startsWith(line_, "##")) fail("line 2 must start with '##'");
    readLine2();
    readSatelliteList();
    readAccuracyLines();
    // %c, %f, %i and /* lines in any order; the header ends at the first other
    // line (normally the first "*" epoch line; anything else is then a record
    // problem, not a header error).
    int c_lines = 0, f_lines = 0;
    bool have_line = true;
    while (have_line) {
      if (startsWith(line_, "%c")) {
        if (c_lines++ == 0) readTimeSystemLine();
      } else if (startsWith(line_, "%f")) {
        if (f_lines++ == 0) readBaseLine();
      } else if (startsWith(line_, "%i") || startsWith(line_, "%/")) {
        // integer placeholders; nothing defined in SP3-d
      } else if (startsWith(line_, "/*")) {
        h.comments.emplace_back(trim(column(line_, 3, 80)));
      } else {
        break;
      }
      have_line = nextLine();
    }
    h.header_lines = have_line ? src_.lineNumber() - 1 : src_.lineNumber();
    const auto first = toGpst(h.first_epoch_calendar);
    if (!first) throw ParseError(src_.name(), 1, "first epoch does not exist in its time system");
    h.first_epoch = *first;
    checkWeekAgainstEpoch();
    if (have_line) src_.unread(line_);
  }

  void readLine1() {
    Sp3Header& h = file_.header;
    // Columns 1-2 "#a".."#d", column 3 P/V flag.
    if (line_.size() < 3 || line_[0] != '#' || line_[1] < 'a' || line_[1] > 'd') {
      fail("not an SP3 file: line 1 must start with '#a'..'#d'");
    }
    h.version = line_[1];
    h.pv_flag = line_[2];
    if (h.pv_flag != 'P' && h.pv_flag != 'V') fail("position/velocity flag must be 'P' or 'V'");
    const auto cal = parseCalendar(line_);
    if (!cal) fail("malformed first epoch in columns 4-31");
    h.first_epoch_calendar = *cal;
    h.epoch_count = headerInt(32, 7, "number of epochs (columns 33-39)");
    if (h.epoch_count < 0) fail("negative number of epochs");
    h.data_used = std::string(trim(column(line_, 40, 5)));
    h.coordinate_system = std::string(trim(column(line_, 46, 5)));
    h.orbit_type = std::string(trim(column(line_, 52, 3)));
    h.agency = std::string(trim(column(line_, 56, 4)));
  }

  void readLine2() {
    Sp3Header& h = file_.header;
    // Columns 4-7 GPS week, 9-23 seconds of week, 25-38 interval, 40-44 MJD,
    // 46-60 fractional day.
    const long long week = headerInt(3, 4, "GPS week (columns 4-7)");
    if (week < 0 || week > 100000) fail("GPS week out of range");
    h.gps_week = static_cast<int>(week);
    h.seconds_of_week = headerDouble(8, 15, "seconds of week (columns 9-23)");
    h.interval_s = headerDouble(24, 14, "epoch interval (columns 25-38)");
    if (!(h.interval_s > 0.0) || h.interval_s > 1e7) fail("epoch interval must be positive");
    h.mjd = headerInt(39, 5, "MJD (columns 40-44)");
    h.fractional_day = headerDouble(45, 15, "fractional day (columns 46-60)");
  }

  // "+" lines: number of satellites in columns 4-6 (SP3-d; SP3-c used 5-6 with
  // column 4 blank, so the same field reads both), then 17 identifiers (A1,I2)
  // per line in columns 10-60. SP3-d has as many "+" lines as needed (>= 5).
  void readSatelliteList() {
    Sp3Header& h = file_.header;
    if (!nextLine() || !startsWith(line_, "+") || startsWith(line_, "++")) {
      fail("line 3 must start the satellite list with '+'");
    }
    const long long count = headerInt(3, 3, "number of satellites (columns 4-6)");
    if (count < 0) fail("negative number of satellites");
    const std::size_t count_line = src_.lineNumber();
    do {
      for (int k = 0; k < 17; ++k) {
        const std::string_view field = column(line_, 9 + 3 * k, 3);
        const std::string_view t = trim(field);
        if (t.empty() || t.find_first_not_of('0') == std::string_view::npos) continue;  // "  0"
        const auto sat = SatelliteId::parse(field);
        if (!sat) fail("malformed satellite identifier '" + std::string(field) + "'");
        h.satellites.push_back(*sat);
        if (static_cast<long long>(h.satellites.size()) > count) {
          fail("more satellites listed than the " + std::to_string(count) + " announced");
        }
      }
      if (!nextLine()) fail("header ends inside the satellite list");
    } while (startsWith(line_, "+") && !startsWith(line_, "++"));
    if (static_cast<long long>(h.satellites.size()) != count) {
      throw ParseError(src_.name(), count_line,
                       "header announces " + std::to_string(count) + " satellites but lists " +
                           std::to_string(h.satellites.size()));
    }
  }

  // "++" lines: accuracy exponents (I3) in the same positions as the "+" list.
  // The current line is the first line after the satellite list.
  void readAccuracyLines() {
    Sp3Header& h = file_.header;
    h.accuracy_exponents.assign(h.satellites.size(), std::nullopt);
    std::size_t index = 0;
    while (startsWith(line_, "++")) {
      for (int k = 0; k < 17; ++k, ++index) {
        if (index >= h.satellites.size()) break;
        long long e = 0;
        const FieldStatus st = parseInt(column(line_, 9 + 3 * k, 3), e);
        if (st == FieldStatus::Malformed || e < 0 || e > 99) fail("malformed accuracy exponent");
        if (st == FieldStatus::Ok && e != 0) h.accuracy_exponents[index] = static_cast<int>(e);
      }
      if (!nextLine()) fail("header ends inside the accuracy lines");
    }
  }

  // First %c line: file type in column 4, time system in columns 10-12.
  void readTimeSystemLine() {
    Sp3Header& h = file_.header;
    const std::string_view type = trim(column(line_, 3, 2));
    h.file_type = (type.empty() || type.front() < 'A' || type.front() > 'Z') ? 'G' : type.front();
    const std::string code(trim(column(line_, 9, 3)));
    if (code.empty() || code == "ccc") {  // SP3-a/b placeholder: GPS time
      h.time_system = TimeSystem::GPS;
      h.time_system_code = "GPS";
      return;
    }
    const auto ts = parseTimeSystem(code);
    if (!ts) fail("unknown time system '" + code + "' in columns 10-12");
    h.time_system = *ts;
    h.time_system_code = code;
  }

  // First %f line: base for position/velocity (columns 4-13) and for
  // clock/clock-rate (columns 15-26) standard deviations.
  void readBaseLine() {
    Sp3Header& h = file_.header;
    double b = 0;
    if (parseDouble(column(line_, 3, 10), b) == FieldStatus::Malformed) fail("malformed %f position base");
    h.position_base = (b > 0.0 && b < 100.0) ? b : 0.0;
    b = 0;
    if (parseDouble(column(line_, 14, 12), b) == FieldStatus::Malformed) fail("malformed %f clock base");
    h.clock_base = (b > 0.0 && b < 100.0) ? b : 0.0;
  }

  void checkWeekAgainstEpoch() {
    const Sp3Header& h = file_.header;
    if (h.time_system != TimeSystem::GPS) return;
    const GnssTime from_week = GnssTime::fromGpsWeek(h.gps_week, h.seconds_of_week);
    if (std::abs(from_week - h.first_epoch) > 1e-3) {
      file_.report.addProblem(2, "GPS week/seconds of line 2 disagree with the first epoch of line 1");
    }
  }

  // ---------------------------------------------------------------- records
  // The filter's window widened by the margin (no time bound without a valid interval).
  void setWindow() {
    const RecordFilter& f = options_.filter;
    const double margin_s = options_.margin_epochs * file_.header.interval_s;
    if (!(file_.header.interval_s > 0.0) || !std::isfinite(margin_s)) return;
    if (f.first) first_ = *f.first - margin_s;
    if (f.last) last_ = *f.last + margin_s;
  }

  void readRecords() {
    bool epoch_ok = false;
    while (nextLine()) {
      if (startsWith(line_, "EOF")) {
        file_.complete = true;
        break;
      }
      if (startsWith(line_, "*")) {
        epoch_ok = readEpochLine();
        if (file_.stopped_after_window) break;
        continue;
      }
      if (startsWith(line_, "EP") || startsWith(line_, "EV")) {
        file_.report.count("correlation records (EP/EV) skipped");
        continue;
      }
      if (isBlank(line_)) {
        file_.report.count("blank lines skipped");
        continue;
      }
      if (line_[0] != 'P' && line_[0] != 'V') {
        file_.report.addProblem(src_.lineNumber(), "unrecognised record '" + std::string(column(line_, 0, 4)) + "'");
        continue;
      }
      if (!epoch_ok) {
        if (outside_window_) {
          file_.report.count("records before the time window skipped");
          continue;
        }
        file_.report.addProblem(src_.lineNumber(), "record without a valid epoch line: skipped");
        continue;
      }
      if (line_.size() > 1 && !options_.filter.systems.empty()) {
        const auto sys = systemFromLetter(line_[1] == ' ' ? 'G' : line_[1]);  // SP3-a/b/c: blank = GPS
        if (sys && !options_.filter.keepsSystem(*sys)) {
          file_.report.count("records of other systems skipped");
          continue;
        }
      }
      if (line_[0] == 'P') readPositionRecord();
      else readVelocityRecord();
    }
    if (src_.streamError()) {
      file_.report.addProblem(src_.lineNumber(), "compressed stream error: " + *src_.streamError());
    }
    if (src_.overlongLines() > 0) file_.report.count("overlong lines cut", src_.overlongLines());
    if (!file_.complete && !file_.stopped_after_window) {
      file_.report.addProblem(src_.lineNumber(), "file ends without the EOF line (truncated?)");
    }
    if (first_ || last_) {
      file_.report.count("epochs outside the time window skipped", skipped_epochs_);
    } else if (static_cast<long long>(file_.epochs.size()) != file_.header.epoch_count) {
      file_.report.count("epochs read differ from the header count (" +
                         std::to_string(file_.header.epoch_count) + " announced)");
    }
  }

  bool readEpochLine() {
    last_p_ = nullptr;
    outside_window_ = false;
    const auto cal = parseCalendar(line_);
    const auto t = cal ? toGpst(*cal) : std::nullopt;
    if (!t) {
      file_.report.addProblem(src_.lineNumber(), "malformed epoch line: its records are skipped");
      return false;
    }
    if (last_epoch_ && !(*t > *last_epoch_)) {
      file_.report.addProblem(src_.lineNumber(), "epoch " + t->toString() +
                                                     " not after the previous one: its records are skipped");
      return false;
    }
    last_epoch_ = *t;
    if (last_ && *last_ < *t) {  // strictly increasing epochs: nothing later is kept
      file_.stopped_after_window = true;
      return false;
    }
    if (first_ && *t < *first_) {
      outside_window_ = true;
      ++skipped_epochs_;
      return false;
    }
    file_.epochs.push_back(*t);
    return true;
  }

  // Columns 2-4 satellite, 5-18/19-32/33-46 x/y/z (F14.6), 47-60 clock (F14.6),
  // 62-63/65-66/68-69 x/y/z exponents (I2), 71-73 clock exponent (I3),
  // 75 clock event flag, 76 clock prediction flag, 79 maneuver flag, 80 orbit
  // prediction flag. V records use the same layout.
  struct RawRecord {
    SatelliteId sat;
    std::optional<Eigen::Vector3d> xyz;  // nullopt when a component carries the 0.000000 marker
    std::optional<double> clock;         // nullopt when blank or the 999999 marker
    bool xyz_marker = false, clock_marker = false;
  };

  std::optional<RawRecord> parseRaw() {
    RawRecord r;
    const std::string_view id = column(line_, 1, 3);
    const auto sat = SatelliteId::parse(id);
    if (!sat) {
      file_.report.addProblem(src_.lineNumber(), "malformed satellite identifier '" + std::string(id) + "'");
      return std::nullopt;
    }
    r.sat = *sat;
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) {
      if (parseDouble(column(line_, 4 + 14 * i, 14), v[i]) != FieldStatus::Ok) {
        file_.report.addProblem(src_.lineNumber(), "malformed coordinate in " + sat->toString() + " record");
        return std::nullopt;
      }
      if (v[i] == 0.0) r.xyz_marker = true;
    }
    if (!r.xyz_marker) r.xyz = v;
    double clk = 0;
    const FieldStatus st = parseDouble(column(line_, 46, 14), clk);
    if (st == FieldStatus::Malformed) {
      file_.report.addProblem(src_.lineNumber(), "malformed clock in " + sat->toString() + " record");
      return std::nullopt;
    }
    if (st == FieldStatus::Ok) {
      if (std::abs(clk) >= kBadClockMarker) r.clock_marker = true;
      else r.clock = clk;
    }
    return r;
  }

  std::optional<double> sigma(std::size_t start, std::size_t width, double base) const {
    long long n = 0;
    if (base <= 0.0 || parseInt(column(line_, start, width), n) != FieldStatus::Ok || n < 0 || n > 999) {
      return std::nullopt;
    }
    const double value = std::pow(base, static_cast<double>(n));
    return std::isfinite(value) ? std::optional<double>(value) : std::nullopt;
  }

  static bool flag(std::string_view line, std::size_t pos, char c) { return pos < line.size() && line[pos] == c; }

  void readPositionRecord() {
    last_p_ = nullptr;
    auto raw = parseRaw();
    if (!raw) return;
    if (listed_.empty()) {
      listed_.assign(static_cast<std::size_t>(kNumGnssSystems) * 100, false);
      for (const auto& s : file_.header.satellites) listed_[static_cast<std::size_t>(s.index())] = true;
    }
    if (!listed_[static_cast<std::size_t>(raw->sat.index())]) {
      file_.report.count("records of satellites missing from the header list (kept)");
    }
    auto& series = file_.satellites[raw->sat];
    const GnssTime t = file_.epochs.back();
    if (!series.empty() && series.back().time == t) {
      file_.report.addProblem(src_.lineNumber(), "second " + raw->sat.toString() + " record in one epoch: skipped");
      return;
    }
    Sp3Record rec;
    rec.time = t;
    if (raw->xyz) rec.position_ecef_m = *raw->xyz * 1000.0;  // km -> m
    if (raw->clock) rec.clock_bias_s = *raw->clock * 1e-6;   // microseconds -> s
    rec.position_marked_bad = raw->xyz_marker;
    rec.clock_marked_bad = raw->clock_marker;
    const Sp3Header& h = file_.header;
    for (int i = 0; i < 3; ++i) {
      if (auto s = sigma(61 + 3 * i, 2, h.position_base)) rec.position_sigma_m[i] = *s * 1e-3;  // mm -> m
    }
    if (auto s = sigma(70, 3, h.clock_base)) rec.clock_sigma_s = *s * 1e-12;  // ps -> s
    rec.clock_event = flag(line_, 74, 'E');
    rec.clock_predicted = flag(line_, 75, 'P');
    rec.maneuver = flag(line_, 78, 'M');
    rec.orbit_predicted = flag(line_, 79, 'P');
    if (raw->xyz_marker) file_.report.count("positions with the bad-value marker 0.000000");
    if (raw->clock_marker) file_.report.count("clocks with the bad-value marker 999999.999999");
    series.push_back(rec);
    last_p_ = &series.back();
    last_p_sat_ = raw->sat;
  }

  void readVelocityRecord() {
    auto raw = parseRaw();
    if (!raw) return;
    if (last_p_ == nullptr || raw->sat != last_p_sat_) {
      file_.report.addProblem(src_.lineNumber(), "V record not after the P record of " + raw->sat.toString());
      return;
    }
    if (raw->xyz) last_p_->velocity_ecef_mps = *raw->xyz * 0.1;       // dm/s -> m/s
    if (raw->clock) last_p_->clock_rate_s_per_s = *raw->clock * 1e-10;  // 1e-4 us/s -> s/s
    last_p_ = nullptr;
  }

  LineSource& src_;
  Sp3ReadOptions options_;
  std::optional<GnssTime> first_, last_;  // the widened window
  std::optional<GnssTime> last_epoch_;    // last valid epoch line, kept or not
  bool outside_window_ = false;           // the current epoch is before the window
  std::size_t skipped_epochs_ = 0;
  std::string line_;
  Sp3File file_;
  Sp3Record* last_p_ = nullptr;
  std::vector<bool> listed_;  // by SatelliteId::index(): satellites of the "+" lines
  SatelliteId last_p_sat_;
};

}  // namespace

Sp3File readSp3(LineSource& source, const Sp3ReadOptions& options) { return Sp3Parser(source, options).run(); }

Sp3File readSp3(const std::string& path, const Sp3ReadOptions& options) {
  auto source = openLineSource(path);
  return readSp3(*source, options);
}

FileSummary summarizeSp3(const Sp3File& file, const std::string& path) {
  const Sp3Header& h = file.header;
  FileSummary s;
  s.path = path;
  s.type = "SP3 orbit";
  s.version = std::string(1, h.version);
  if (!file.epochs.empty()) {
    s.first_epoch = file.epochs.front();
    s.last_epoch = file.epochs.back();
  }
  s.interval_s = h.interval_s;
  s.epoch_count = file.epochs.size();
  for (const auto& sat : h.satellites) s.satellites[sat.system].insert(sat);
  for (const auto& [sat, records] : file.satellites) s.satellites[sat.system].insert(sat);
  s.facts.push_back("agency " + h.agency);
  s.facts.push_back("coordinate system " + h.coordinate_system);
  s.facts.push_back("orbit type " + h.orbit_type);
  s.facts.push_back("time system " + h.time_system_code);
  s.facts.push_back(std::string("content ") + (h.pv_flag == 'V' ? "positions and velocities" : "positions"));
  s.facts.push_back("satellites in header " + std::to_string(h.satellites.size()));
  s.facts.push_back("epochs in header " + std::to_string(h.epoch_count));
  std::size_t bad_pos = 0, bad_clk = 0, predicted = 0;
  for (const auto& [sat, records] : file.satellites) {
    for (const auto& r : records) {
      bad_pos += r.position_marked_bad;
      bad_clk += r.clock_marked_bad;
      predicted += r.orbit_predicted;
    }
  }
  s.facts.push_back("positions marked bad " + std::to_string(bad_pos) + ", clocks marked bad " +
                    std::to_string(bad_clk) + ", predicted orbit records " + std::to_string(predicted));
  if (!file.complete) s.facts.push_back("no EOF line: file truncated?");
  s.report = file.report;
  return s;
}

FileSummary summarizeSp3File(const std::string& path) { return summarizeSp3(readSp3(path), path); }

}  // namespace ppp
