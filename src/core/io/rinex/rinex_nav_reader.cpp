#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

namespace {

constexpr std::size_t kMaxHeaderLines = 2000;
constexpr std::size_t kMaxTimeCorrections = 64;
/// The longest record (GPS, Galileo, BeiDou: 8 lines; RINEX 4 CNV2: 9 lines).
/// Continuation lines beyond this are reported, never stored.
constexpr std::size_t kMaxRecordLines = 10;
/// Numeric fields kept from a record: 3 on the first line, 4 per further line.
constexpr std::size_t kMaxFields = 3 + 4 * (kMaxRecordLines - 1);

std::string str(std::string_view v) { return std::string(v); }

std::string headerLabel(const std::string& line) { return str(trim(column(line, 60, 20))); }

// ---------------------------------------------------------------------------
// Header
// ---------------------------------------------------------------------------

class HeaderParser {
 public:
  HeaderParser(LineSource& src, RinexNavHeader& header) : src_(src), h_(header) {}

  void parse() {
    std::string line;
    if (!src_.next(line)) fail(0, "empty file: no RINEX VERSION / TYPE line");
    parseVersionLine(line);
    while (true) {
      if (!src_.next(line)) fail(src_.lineNumber(), "end of data before END OF HEADER");
      if (++h_.header_lines > kMaxHeaderLines) fail(src_.lineNumber(), "no END OF HEADER within 2000 lines");
      const std::string label = headerLabel(line);
      if (label == "END OF HEADER") return;
      if (label == "IONOSPHERIC CORR") {
        parseIonoCorr(line, str(trim(column(line, 0, 4))), 5);
      } else if (label == "ION ALPHA") {
        parseIonoCorr(line, "GPSA", 2);
      } else if (label == "ION BETA") {
        parseIonoCorr(line, "GPSB", 2);
      } else if (label == "TIME SYSTEM CORR") {
        parseTimeSystemCorr(line);
      } else if (label == "DELTA-UTC: A0,A1,T,W") {
        parseDeltaUtc(line);
      } else if (label == "LEAP SECONDS") {
        parseLeapSeconds(line);
      }
      // Other labels (PGM / RUN BY / DATE, COMMENT, MERGED FILE, DOI, LICENSE OF
      // USE, STATION INFORMATION, CORR TO SYSTEM TIME, ...) carry nothing we use.
    }
  }

 private:
  [[noreturn]] void fail(std::size_t line, const std::string& reason) {
    throw ParseError(src_.name(), line, reason);
  }

  double number(const std::string& line, std::size_t start, std::size_t width, const char* what) {
    double v = 0.0;
    if (parseDouble(column(line, start, width), v) != FieldStatus::Ok) {
      fail(src_.lineNumber(), std::string("malformed or missing ") + what);
    }
    return v;
  }

  std::optional<long long> optionalInt(const std::string& line, std::size_t start,
                                       std::size_t width, const char* what) {
    long long v = 0;
    const FieldStatus st = parseInt(column(line, start, width), v);
    if (st == FieldStatus::Malformed) fail(src_.lineNumber(), std::string("malformed ") + what);
    if (st == FieldStatus::Blank) return std::nullopt;
    return v;
  }

  void parseVersionLine(const std::string& line) {
    if (headerLabel(line) != "RINEX VERSION / TYPE") {
      fail(src_.lineNumber(), "first line is not RINEX VERSION / TYPE");
    }
    h_.version_text = str(trim(column(line, 0, 9)));
    if (parseDouble(h_.version_text, h_.version) != FieldStatus::Ok) {
      fail(src_.lineNumber(), "malformed RINEX version '" + h_.version_text + "'");
    }
    if (h_.version < 2.0 || h_.version >= 5.0) {
      fail(src_.lineNumber(), "unsupported RINEX version " + h_.version_text);
    }
    const std::string_view type = column(line, 20, 1);
    h_.file_type = type.empty() ? ' ' : type[0];
    if (h_.version < 3.0) {
      // RINEX 2.11 table A3/A10/A17: N = GPS nav, G = GLONASS nav, H = GEO (SBAS) nav.
      if (h_.file_type == 'N') {
        h_.system = 'G';
      } else if (h_.file_type == 'G') {
        h_.system = 'R';
      } else if (h_.file_type == 'H') {
        h_.system = 'S';
      } else {
        fail(src_.lineNumber(), "not a RINEX 2 navigation file (type '" + str(type) + "')");
      }
      return;
    }
    if (h_.file_type != 'N') {
      fail(src_.lineNumber(), "not a navigation file (type '" + str(type) + "')");
    }
    const std::string_view system = trim(column(line, 40, 1));
    h_.system = system.empty() ? 'G' : system[0];  // RINEX 3: blank means GPS
    if (h_.system != 'M' && !systemFromLetter(h_.system)) {
      fail(src_.lineNumber(), "unknown satellite system '" + str(system) + "'");
    }
  }

  void parseIonoCorr(const std::string& line, const std::string& type, std::size_t first) {
    if (type.empty()) fail(src_.lineNumber(), "IONOSPHERIC CORR without a correction type");
    std::vector<double> values;
    for (std::size_t j = 0; j < 4; ++j) {
      double v = 0.0;
      const FieldStatus st = parseDouble(column(line, first + 12 * j, 12), v);
      if (st == FieldStatus::Malformed) fail(src_.lineNumber(), "malformed " + type + " coefficient");
      if (st == FieldStatus::Ok) values.push_back(v);
    }
    if (values.empty()) fail(src_.lineNumber(), "IONOSPHERIC CORR " + type + " without values");
    h_.ionospheric_corrections[type] = std::move(values);
  }

  void parseTimeSystemCorr(const std::string& line) {
    // RINEX 3.05 table A5: A4,1X,D17.10,D16.9,1X,I6,1X,I4,1X,A5,1X,I2.
    TimeSystemCorrection c;
    c.type = str(trim(column(line, 0, 4)));
    if (c.type.empty()) fail(src_.lineNumber(), "TIME SYSTEM CORR without a type");
    c.a0_s = number(line, 5, 17, "TIME SYSTEM CORR a0");
    c.a1_sps = number(line, 22, 16, "TIME SYSTEM CORR a1");
    c.reference_sow = optionalInt(line, 38, 7, "TIME SYSTEM CORR reference time").value_or(0);
    c.reference_week = optionalInt(line, 45, 5, "TIME SYSTEM CORR week").value_or(0);
    // Source and UTC id: writers place them a column or two apart; read as words.
    std::istringstream words(str(column(line, 50, 10)));
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    if (!tokens.empty()) {
      if (auto id = toInt(tokens.back()); id && tokens.size() <= 2) {
        c.utc_id = static_cast<int>(*id);
        tokens.pop_back();
      }
      if (!tokens.empty()) c.source = tokens.front();
    }
    addTimeCorrection(std::move(c));
  }

  void parseDeltaUtc(const std::string& line) {
    // RINEX 2.11 table A4: 3X,2D19.12,2I9.
    TimeSystemCorrection c;
    c.type = "GPUT";
    c.a0_s = number(line, 3, 19, "DELTA-UTC A0");
    c.a1_sps = number(line, 22, 19, "DELTA-UTC A1");
    c.reference_sow = optionalInt(line, 41, 9, "DELTA-UTC T").value_or(0);
    c.reference_week = optionalInt(line, 50, 9, "DELTA-UTC W").value_or(0);
    addTimeCorrection(std::move(c));
  }

  void addTimeCorrection(TimeSystemCorrection c) {
    if (h_.time_system_corrections.size() >= kMaxTimeCorrections) {
      fail(src_.lineNumber(), "more than 64 TIME SYSTEM CORR lines");
    }
    h_.time_system_corrections.push_back(std::move(c));
  }

  void parseLeapSeconds(const std::string& line) {
    const auto leap = optionalInt(line, 0, 6, "LEAP SECONDS");
    if (!leap) return;  // written blank by some converters: unknown
    if (*leap < 0 || *leap > 100) fail(src_.lineNumber(), "LEAP SECONDS out of range");
    h_.leap_seconds = static_cast<int>(*leap);
  }

  LineSource& src_;
  RinexNavHeader& h_;
};

// ---------------------------------------------------------------------------
// Records
// ---------------------------------------------------------------------------

struct RawRecord {
  std::vector<std::string> lines;  // first line (satellite + epoch) then continuation lines
  std::size_t first_line = 0;      // line number of lines[0]
  std::string message;             // RINEX 4 message type ("LNAV", "INAV", ...); empty before v4
};

/// Numeric fields of a record: index 0-2 on the first line, then 4 per line
/// (RINEX 3.05 A6..A12: "BROADCAST ORBIT - n").
struct Fields {
  std::array<double, kMaxFields> value{};
  std::array<FieldStatus, kMaxFields> status{};
  std::size_t line_of[kMaxFields] = {};
};

class RecordError : public std::runtime_error {
 public:
  RecordError(std::size_t line, const std::string& what) : std::runtime_error(what), line_(line) {}
  std::size_t line() const { return line_; }

 private:
  std::size_t line_;
};

class BodyParser {
 public:
  BodyParser(LineSource& src, NavData& out) : src_(src), out_(out), v2_(out.header.version < 3.0) {}

  void parse() {
    if (out_.header.version >= 4.0) {
      parseV4();
    } else {
      parseV2V3();
    }
    if (src_.streamError()) out_.report.addProblem(src_.lineNumber(), *src_.streamError());
    if (src_.overlongLines() > 0) out_.report.count("overlong lines cut", src_.overlongLines());
  }

 private:
  bool startsRecord(const std::string& line) const {
    // RINEX 3: "G01 yyyy..." starts in column 1; continuation lines are indented
    // by 4 blanks. RINEX 2: PRN in I2 (columns 1-2), continuation indent 3.
    if (v2_) return !isBlank(column(line, 0, 2));
    return !line.empty() && line[0] != ' ';
  }

  // RINEX 2 and 3: a record is a first line and the indented lines after it.
  void parseV2V3() {
    std::string line;
    while (src_.next(line)) {
      if (isBlank(line)) continue;
      RawRecord rec;
      rec.first_line = src_.lineNumber();
      rec.lines.push_back(line);
      const bool orphan = !startsRecord(line);
      std::size_t extra = 0;
      while (src_.next(line)) {
        if (isBlank(line)) continue;
        if (startsRecord(line)) {
          src_.unread(line);
          break;
        }
        if (rec.lines.size() < kMaxRecordLines) {
          rec.lines.push_back(line);
        } else {
          ++extra;
        }
      }
      if (orphan) {
        out_.report.addProblem(rec.first_line, "continuation line(s) without a record header skipped");
        continue;
      }
      if (extra > 0) {
        out_.report.addProblem(rec.first_line, "record has more lines than any record type; skipped");
        continue;
      }
      decode(rec);
    }
  }

  // RINEX 4: every record starts with "> TYPE SAT MESSAGE" (RINEX 4.00 section 5.4).
  void parseV4() {
    std::string line;
    bool warned_stray = false;
    while (src_.next(line)) {
      if (isBlank(line)) continue;
      if (line[0] != '>') {
        if (!warned_stray) {
          out_.report.addProblem(src_.lineNumber(), "line outside a '>' record skipped");
          warned_stray = true;
        }
        continue;
      }
      warned_stray = false;
      std::istringstream words(line.substr(1, 40));
      std::string type, sat, message;
      words >> type >> sat >> message;
      RawRecord rec;
      rec.first_line = src_.lineNumber() + 1;
      rec.message = message;
      std::size_t extra = 0;
      while (src_.next(line)) {
        if (!line.empty() && line[0] == '>') {
          src_.unread(line);
          break;
        }
        if (isBlank(line)) continue;
        if (rec.lines.size() < kMaxRecordLines) {
          rec.lines.push_back(line);
        } else {
          ++extra;
        }
      }
      if (type != "EPH") {
        out_.report.count("RINEX 4 " + (type.empty() ? std::string("untyped") : type) +
                          " records skipped");
        continue;
      }
      if (rec.lines.empty()) {
        out_.report.addProblem(rec.first_line - 1, "EPH record without data lines");
        continue;
      }
      if (extra > 0) {
        out_.report.addProblem(rec.first_line, "record has more lines than any record type; skipped");
        continue;
      }
      decode(rec);
    }
  }

  void decode(const RawRecord& rec) {
    try {
      decodeOrThrow(rec);
    } catch (const RecordError& e) {
      out_.report.addProblem(e.line(), e.what());
    }
  }

  SatelliteId satelliteOf(const RawRecord& rec) const {
    const std::string& first = rec.lines[0];
    std::optional<SatelliteId> sat;
    if (v2_) {
      long long prn = 0;
      if (parseInt(column(first, 0, 2), prn) == FieldStatus::Ok && prn > 0 && prn < 100) {
        const char letter = out_.header.system;
        sat = SatelliteId::parse(std::string(1, letter) + std::to_string(prn));
      }
    } else {
      sat = SatelliteId::parse(column(first, 0, 3));
    }
    if (!sat) throw RecordError(rec.first_line, "malformed satellite '" + str(column(first, 0, 3)) + "'");
    return *sat;
  }

  CalendarTime epochOf(const RawRecord& rec) const {
    const std::string& l = rec.lines[0];
    // RINEX 3: 1X,I4,4(1X,I2.2),1X,I2.2 from column 4; RINEX 2: 5(1X,I2),F5.1 from column 3.
    const std::size_t y0 = v2_ ? 2 : 3, step_y = v2_ ? 3 : 5;
    long long year = 0, month = 0, day = 0, hour = 0, minute = 0;
    double second = 0.0;
    const bool ok = parseInt(column(l, y0, step_y), year) == FieldStatus::Ok &&
                    parseInt(column(l, y0 + step_y, 3), month) == FieldStatus::Ok &&
                    parseInt(column(l, y0 + step_y + 3, 3), day) == FieldStatus::Ok &&
                    parseInt(column(l, y0 + step_y + 6, 3), hour) == FieldStatus::Ok &&
                    parseInt(column(l, y0 + step_y + 9, 3), minute) == FieldStatus::Ok &&
                    parseDouble(column(l, y0 + step_y + 12, v2_ ? 5 : 3), second) == FieldStatus::Ok;
    if (!ok) throw RecordError(rec.first_line, "malformed epoch");
    if (v2_ && year >= 0 && year < 100) year += year >= 80 ? 1900 : 2000;  // RINEX 2.11 6.5
    if (year < 1980 || year > 2200 || !isValidDate(static_cast<int>(year), static_cast<int>(month),
                                                   static_cast<int>(day)) ||
        hour < 0 || hour > 23 || minute < 0 || minute > 59 || second < 0.0 || second >= 61.0) {
      throw RecordError(rec.first_line, "epoch out of range");
    }
    CalendarTime c;
    c.year = static_cast<int>(year);
    c.month = static_cast<int>(month);
    c.day = static_cast<int>(day);
    c.hour = static_cast<int>(hour);
    c.minute = static_cast<int>(minute);
    c.second = second;
    return c;
  }

  Fields fieldsOf(const RawRecord& rec) const {
    Fields f;
    f.status.fill(FieldStatus::Blank);
    // RINEX 3: first-line fields from column 24 (index 23), continuation lines
    // 4X,4D19.12; RINEX 2: from column 23 and 3X,4D19.12.
    const std::size_t first_start = v2_ ? 22 : 23, indent = v2_ ? 3 : 4;
    std::size_t k = 0;
    for (std::size_t li = 0; li < rec.lines.size(); ++li) {
      const std::size_t count = li == 0 ? 3 : 4;
      const std::size_t start = li == 0 ? first_start : indent;
      for (std::size_t j = 0; j < count && k < kMaxFields; ++j, ++k) {
        f.status[k] = parseDouble(column(rec.lines[li], start + 19 * j, 19), f.value[k]);
        f.line_of[k] = rec.first_line + li;
        if (f.status[k] == FieldStatus::Malformed) {
          throw RecordError(f.line_of[k], "malformed number in record field " + std::to_string(k + 1));
        }
      }
    }
    return f;
  }

  static double required(const Fields& f, std::size_t k, std::size_t first_line, const char* what) {
    if (f.status[k] != FieldStatus::Ok) {
      throw RecordError(f.line_of[k] ? f.line_of[k] : first_line,
                        std::string("missing ") + what + " (record truncated or field blank)");
    }
    return f.value[k];
  }
  static std::optional<double> optional(const Fields& f, std::size_t k) {
    if (f.status[k] != FieldStatus::Ok) return std::nullopt;
    return f.value[k];
  }
  static int integer(double v, double lo, double hi, std::size_t line, const char* what) {
    if (!(v >= lo && v <= hi) || std::fabs(v - std::round(v)) > 1e-6) {
      throw RecordError(line, std::string(what) + " out of range or not an integer");
    }
    return static_cast<int>(std::lround(v));
  }

  void decodeOrThrow(const RawRecord& rec) {
    const SatelliteId sat = satelliteOf(rec);
    out_.satellites.insert(sat);
    const std::string& msg = rec.message;
    switch (sat.system) {
      case GnssSystem::GPS:
      case GnssSystem::QZSS:
        if (!msg.empty() && msg != "LNAV") return skip(sat, msg);
        return decodeLnav(rec, sat);
      case GnssSystem::Galileo:
        if (!msg.empty() && msg != "INAV" && msg != "FNAV") return skip(sat, msg);
        return decodeGalileo(rec, sat);
      case GnssSystem::GLONASS:
        if (!msg.empty() && msg != "FDMA") return skip(sat, msg);
        return decodeGlonass(rec, sat);
      case GnssSystem::BeiDou:
        if (!msg.empty() && msg != "D1" && msg != "D2") return skip(sat, msg);
        return decodeBeidou(rec, sat);
      default:
        return skip(sat, msg);
    }
  }

  void skip(const SatelliteId& sat, const std::string& msg) {
    std::string what(systemName(sat.system));
    if (!msg.empty()) what += " " + msg;
    out_.report.count(what + " records skipped (not modelled)");
  }

  void noteToc(const GnssTime& toc) {
    if (!out_.first_toc || toc < *out_.first_toc) out_.first_toc = toc;
    if (!out_.last_toc || toc > *out_.last_toc) out_.last_toc = toc;
  }

  GnssTime toGpst(const CalendarTime& c, TimeSystem system, std::size_t line) const {
    try {
      return GnssTime::fromCalendar(c, system);
    } catch (const std::invalid_argument&) {
      throw RecordError(line, "invalid epoch");
    }
  }

  // Clock and the sixteen orbit elements shared by LNAV, Galileo and BeiDou
  // records (RINEX 3.05 tables A6, A8 and A14, fields 1-20). With `bdt_week`
  // (BeiDou), toe lies in the BDT week of field 21, which is returned there.
  void decodeKepler(const RawRecord& rec, const Fields& f, TimeSystem ts, ClockPolynomial& clock,
                    KeplerOrbit& o, int* bdt_week = nullptr) const {
    const std::size_t l0 = rec.first_line;
    clock.toc = toGpst(epochOf(rec), ts, l0);
    clock.af0_s = required(f, 0, l0, "af0");
    clock.af1_sps = required(f, 1, l0, "af1");
    clock.af2_sps2 = required(f, 2, l0, "af2");
    o.crs_m = required(f, 4, l0, "Crs");
    o.delta_n_radps = required(f, 5, l0, "Delta n");
    o.m0_rad = required(f, 6, l0, "M0");
    o.cuc_rad = required(f, 7, l0, "Cuc");
    o.eccentricity = required(f, 8, l0, "e");
    o.cus_rad = required(f, 9, l0, "Cus");
    o.sqrt_a_sqrtm = required(f, 10, l0, "sqrt(A)");
    o.toe_sow = required(f, 11, l0, "Toe");
    o.cic_rad = required(f, 12, l0, "Cic");
    o.omega0_rad = required(f, 13, l0, "OMEGA0");
    o.cis_rad = required(f, 14, l0, "Cis");
    o.i0_rad = required(f, 15, l0, "i0");
    o.crc_m = required(f, 16, l0, "Crc");
    o.omega_rad = required(f, 17, l0, "omega");
    o.omega_dot_radps = required(f, 18, l0, "OMEGA DOT");
    o.idot_radps = required(f, 19, l0, "IDOT");
    if (auto why = checkKeplerOrbit(o)) throw RecordError(l0, *why);
    // Full toe: the instant with the broadcast seconds of week nearest to toc
    // (IS-GPS-200 20.3.3.4.3: a difference beyond +-302400 s crosses a week);
    // BeiDou: from the BDT week as written.
    if (bdt_week) {
      *bdt_week = integer(required(f, 21, l0, "BDT week"), 0, 100000, f.line_of[21], "BDT week");
      o.toe = withinHalfWeek(clock.toc, fromBdtWeek(*bdt_week, o.toe_sow));
    } else {
      o.toe = nearestSecondsOfWeek(clock.toc, o.toe_sow);
    }
  }

  void decodeLnav(const RawRecord& rec, const SatelliteId& sat) {
    const Fields f = fieldsOf(rec);
    const std::size_t l0 = rec.first_line;
    GpsLnavEphemeris e;
    e.satellite = sat;
    decodeKepler(rec, f, sat.system == GnssSystem::QZSS ? TimeSystem::QZSS : TimeSystem::GPS,
                 e.clock, e.orbit);
    e.iode = integer(required(f, 3, l0, "IODE"), 0, 1023, f.line_of[3], "IODE");
    e.codes_on_l2 = integer(optional(f, 20).value_or(0), 0, 3, f.line_of[20], "codes on L2");
    e.week = integer(required(f, 21, l0, "week"), 0, 100000, f.line_of[21], "week");
    e.l2p_data_flag = integer(optional(f, 22).value_or(0), 0, 1, f.line_of[22], "L2 P flag");
    e.ura_m = required(f, 23, l0, "SV accuracy");
    e.health = integer(required(f, 24, l0, "SV health"), 0, 63, f.line_of[24], "SV health");
    e.tgd_s = required(f, 25, l0, "TGD");
    e.iodc = integer(required(f, 26, l0, "IODC"), 0, 1023, f.line_of[26], "IODC");
    e.transmission_sow = optional(f, 27);
    // Fit interval: GPS in hours, 0 meaning 4 h (RINEX 3.05 A6); QZSS writes the
    // fit interval flag, 0 meaning 2 h (IS-QZSS-PNT 4.1.2.4, RINEX 3.05 A12).
    const double fit = optional(f, 28).value_or(0.0);
    if (!(fit >= 0.0 && fit <= 200.0)) throw RecordError(f.line_of[28], "fit interval out of range");
    if (sat.system == GnssSystem::QZSS) {
      e.fit_interval_h = fit == 0.0 ? 2.0 : (fit == 1.0 ? 4.0 : fit);
    } else {
      e.fit_interval_h = fit == 0.0 ? 4.0 : fit;
    }
    noteToc(e.clock.toc);
    out_.gps.push_back(e);
  }

  void decodeGalileo(const RawRecord& rec, const SatelliteId& sat) {
    const Fields f = fieldsOf(rec);
    const std::size_t l0 = rec.first_line;
    GalileoEphemeris e;
    e.satellite = sat;
    decodeKepler(rec, f, TimeSystem::Galileo, e.clock, e.orbit);
    e.iod_nav = integer(required(f, 3, l0, "IODnav"), 0, 1023, f.line_of[3], "IODnav");
    e.data_sources = integer(required(f, 20, l0, "data sources"), 0, 1023, f.line_of[20], "data sources");
    e.week = integer(required(f, 21, l0, "GAL week"), 0, 100000, f.line_of[21], "GAL week");
    const double sisa = required(f, 23, l0, "SISA");
    if (sisa >= 0.0) e.sisa_m = sisa;  // -1: no accuracy prediction available (NAPA)
    e.health = integer(required(f, 24, l0, "SV health"), 0, 511, f.line_of[24], "SV health");
    e.bgd_e5a_e1_s = required(f, 25, l0, "BGD E5a/E1");
    e.bgd_e5b_e1_s = optional(f, 26);
    e.transmission_sow = optional(f, 27);
    // Message type: the RINEX 4 record label, else the data-source bits
    // (RINEX 3.05 A8: bit 0 I/NAV E1-B, bit 1 F/NAV E5a-I, bit 2 I/NAV E5b-I).
    if (rec.message == "INAV" || rec.message == "FNAV") {
      e.type = rec.message == "FNAV" ? GalileoNavType::FNav : GalileoNavType::INav;
    } else {
      const bool inav = (e.data_sources & 0x5) != 0, fnav = (e.data_sources & 0x2) != 0;
      if (inav == fnav) {
        throw RecordError(f.line_of[20], "Galileo data sources " + std::to_string(e.data_sources) +
                                             " name neither or both of I/NAV and F/NAV");
      }
      e.type = fnav ? GalileoNavType::FNav : GalileoNavType::INav;
    }
    noteToc(e.clock.toc);
    out_.galileo.push_back(e);
  }

  // RINEX 3.05 table A14: toc in BDT, toe as BDT seconds of the BDT week (field 21).
  void decodeBeidou(const RawRecord& rec, const SatelliteId& sat) {
    const Fields f = fieldsOf(rec);
    const std::size_t l0 = rec.first_line;
    BeidouEphemeris e;
    e.satellite = sat;
    decodeKepler(rec, f, TimeSystem::BeiDou, e.clock, e.orbit, &e.bdt_week);
    e.aode = integer(required(f, 3, l0, "AODE"), 0, 255, f.line_of[3], "AODE");
    e.ura_m = required(f, 23, l0, "SV accuracy");
    e.health = integer(required(f, 24, l0, "SatH1"), 0, 511, f.line_of[24], "SatH1");
    e.tgd1_s = required(f, 25, l0, "TGD1");
    e.tgd2_s = required(f, 26, l0, "TGD2");
    e.transmission_sow = optional(f, 27);
    e.aodc = integer(optional(f, 28).value_or(0), 0, 255, f.line_of[28], "AODC");
    noteToc(e.clock.toc);
    out_.beidou.push_back(e);
  }

  void decodeGlonass(const RawRecord& rec, const SatelliteId& sat) {
    const Fields f = fieldsOf(rec);
    const std::size_t l0 = rec.first_line;
    GlonassEphemeris e;
    e.satellite = sat;
    e.tb = toGpst(epochOf(rec), TimeSystem::UTC, l0);  // RINEX 3.05 A10: toc in UTC
    e.minus_tau_n_s = required(f, 0, l0, "-TauN");
    e.gamma_n = required(f, 1, l0, "GammaN");
    e.message_frame_time_s = required(f, 2, l0, "message frame time");
    for (int axis = 0; axis < 3; ++axis) {
      const std::size_t k = 3 + 4 * static_cast<std::size_t>(axis);
      e.position_m[axis] = 1e3 * required(f, k, l0, "position");       // km -> m
      e.velocity_mps[axis] = 1e3 * required(f, k + 1, l0, "velocity");  // km/s -> m/s
      e.acceleration_mps2[axis] = 1e3 * required(f, k + 2, l0, "acceleration");
    }
    e.health = integer(required(f, 6, l0, "health"), 0, 15, f.line_of[6], "health");
    // Channels are -7..+6 since 2005 (GlonassChannels); the format allows -7..+13 and
    // earlier files (e.g. the RINEX 2.11 example) carry the historic 0..24.
    e.frequency_channel = integer(required(f, 10, l0, "frequency number"), -7, 24, f.line_of[10],
                                  "frequency number");
    e.age_days = required(f, 14, l0, "age of operation information");
    if (auto why = checkGlonassState(e)) throw RecordError(l0, *why);
    if (!out_.glonass_channels.set(sat.prn, e.frequency_channel)) {
      out_.report.count("GLONASS channels not recorded (slot above 30 or channel outside -7..+6)");
    }
    noteToc(e.tb);
    out_.glonass.push_back(e);
  }

  LineSource& src_;
  NavData& out_;
  bool v2_;
};

}  // namespace

NavData readRinexNav(LineSource& source) {
  NavData out;
  out.report.setFile(source.name());
  HeaderParser(source, out.header).parse();
  BodyParser(source, out).parse();
  return out;
}

NavData readRinexNav(const std::string& path) {
  auto source = openLineSource(path);
  return readRinexNav(*source);
}

FileSummary summarizeNavFile(const std::string& path) {
  const NavData nav = readRinexNav(path);
  FileSummary s;
  s.path = path;
  s.type = "RINEX navigation";
  s.version = nav.header.version_text;
  s.first_epoch = nav.first_toc;
  s.last_epoch = nav.last_toc;
  s.epoch_count = nav.recordCount();
  s.count_label = "navigation records";
  for (const SatelliteId& sat : nav.satellites) s.satellites[sat.system].insert(sat);

  std::size_t gps = 0, qzss = 0, inav = 0, fnav = 0;
  for (const auto& e : nav.gps) (e.satellite.system == GnssSystem::QZSS ? qzss : gps)++;
  for (const auto& e : nav.galileo) (e.type == GalileoNavType::FNav ? fnav : inav)++;
  std::ostringstream records;
  records << "records: GPS LNAV " << gps << ", QZSS LNAV " << qzss << ", Galileo I/NAV " << inav
          << ", Galileo F/NAV " << fnav << ", GLONASS " << nav.glonass.size() << ", BeiDou "
          << nav.beidou.size();
  s.facts.push_back(records.str());
  if (!nav.header.ionospheric_corrections.empty()) {
    std::string f = "ionospheric corrections:";
    for (const auto& [type, values] : nav.header.ionospheric_corrections) f += " " + type;
    s.facts.push_back(f);
  } else {
    s.facts.push_back("no ionospheric corrections in the header");
  }
  if (!nav.header.time_system_corrections.empty()) {
    std::string f = "time system corrections:";
    for (const auto& c : nav.header.time_system_corrections) f += " " + c.type;
    s.facts.push_back(f);
  }
  if (nav.header.leap_seconds) {
    s.facts.push_back("leap seconds " + std::to_string(*nav.header.leap_seconds));
  }
  if (nav.glonass_channels.size() > 0) {
    s.facts.push_back("GLONASS FDMA channels known for " +
                      std::to_string(nav.glonass_channels.size()) + " slots");
  }
  s.report = nav.report;
  return s;
}

}  // namespace ppp
