// ANTEX 1.4 reader (format description: "ANTEX: The Antenna Exchange Format,
// Version 1.4", R. Schmid, IGS Antenna Working Group, 2010). Record labels are in
// columns 61-80; field positions below follow its format column.
#include "ppp_bayes_tree/io/products/antex_reader.h"

#include <algorithm>
#include <map>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "ppp_bayes_tree/io/fixed_width.h"

namespace ppp {

namespace {

std::string_view labelOf(std::string_view line) { return trim(column(line, 60, 20)); }

/// A satellite block whose code is well formed but outside the PRN range of its
/// system (e.g. the GIOVE test satellites E51, E52 of the IGS files): not an
/// input problem; the block is skipped and its code listed.
struct OutOfRangeSatellite {
  std::string code;
};

/// Aborts the antenna block being read; `line` and `reason` go to the report.
struct BlockError {
  std::size_t line;
  std::string reason;
  bool consumed_block_end = false;  // the END OF ANTENNA line was already read
};

bool isSatelliteCode(std::string_view s) {
  return s.size() == 3 && systemFromLetter(s[0]).has_value() && s[1] >= '0' && s[1] <= '9' &&
         s[2] >= '0' && s[2] <= '9';
}

/// Grid sizes derived from DAZI and ZEN1/ZEN2/DZEN, validated against the limits.
struct GridShape {
  std::size_t zenith_nodes = 0;
  std::size_t azimuth_rows = 0;  // 0: NOAZI only
};

std::optional<std::size_t> stepCount(double span, double step, std::size_t max_count) {
  if (!(step > 0.0) || !std::isfinite(span / step)) return std::nullopt;
  const double n = span / step;
  if (n < 0.0 || n > static_cast<double>(max_count)) return std::nullopt;
  const double rounded = std::round(n);
  if (std::fabs(n - rounded) > 1e-4) return std::nullopt;
  return static_cast<std::size_t>(rounded);
}

class AntexParser {
 public:
  AntexParser(LineSource& source, AntexFile& out) : src_(source), out_(out) {}

  void readHeader();
  void readBody();

 private:
  [[noreturn]] void headerError(std::size_t line, const std::string& reason) const {
    throw ParseError(src_.name(), line, reason);
  }
  AntennaCalibration readAntenna(std::size_t start_line);
  void skipBlock(const BlockError& error);
  void parseTypeSerial(const std::string& line, AntennaCalibration& a) const;
  GridShape checkGrid(const AntennaCalibration& a) const;
  FrequencyCalibration readFrequency(const std::string& start, const AntennaCalibration& a,
                                     const GridShape& shape);
  void skipRmsBlock();
  std::string nextBlockLine(const char* what);
  GnssTime parseEpoch(const std::string& line) const;
  std::vector<double> parseValues(const std::string& line, std::size_t count) const;
  BlockError error(std::string reason) const { return BlockError{src_.lineNumber(), std::move(reason)}; }

  LineSource& src_;
  AntexFile& out_;
};

void AntexParser::readHeader() {
  std::string line;
  if (!src_.next(line)) headerError(0, "empty file: no ANTEX VERSION / SYST line");
  if (labelOf(line) != "ANTEX VERSION / SYST") {
    headerError(src_.lineNumber(), "first line is not ANTEX VERSION / SYST");
  }
  double version = 0.0;
  if (parseDouble(column(line, 0, 8), version) != FieldStatus::Ok || version < 1.0 || version >= 2.0) {
    headerError(src_.lineNumber(), "unsupported ANTEX version '" + std::string(trim(column(line, 0, 8))) +
                                       "' (expected 1.x, written for 1.4)");
  }
  out_.header.version = std::string(trim(column(line, 0, 8)));
  const std::string_view sys = trim(column(line, 20, 1));
  out_.header.system = sys.empty() ? 'G' : sys[0];
  if (out_.header.system != 'M' && !systemFromLetter(out_.header.system)) {
    headerError(src_.lineNumber(), "unknown satellite system '" + std::string(sys) + "'");
  }
  bool have_pcv_type = false;
  while (src_.next(line)) {
    const std::string_view label = labelOf(line);
    if (label == "PCV TYPE / REFANT") {
      const std::string_view type = column(line, 0, 1);
      if (type != "A" && type != "R") {
        headerError(src_.lineNumber(), "PCV type must be A or R, found '" + std::string(type) + "'");
      }
      out_.header.pcv_type = type[0];
      out_.header.reference_antenna = std::string(trim(column(line, 20, 20)));
      out_.header.reference_serial = std::string(trim(column(line, 40, 20)));
      have_pcv_type = true;
    } else if (label == "COMMENT") {
      if (out_.header.comments.size() < 10000) out_.header.comments.emplace_back(trim(column(line, 0, 60)));
    } else if (label == "END OF HEADER") {
      if (!have_pcv_type) headerError(src_.lineNumber(), "header lacks PCV TYPE / REFANT");
      return;
    } else if (label == "START OF ANTENNA") {
      headerError(src_.lineNumber(), "START OF ANTENNA before END OF HEADER");
    } else if (!isBlank(line)) {
      out_.report.count("unknown header lines ignored");
    }
  }
  headerError(src_.lineNumber(), "file ends before END OF HEADER");
}

void AntexParser::readBody() {
  std::string line;
  while (src_.next(line)) {
    const std::string_view label = labelOf(line);
    if (label == "START OF ANTENNA") {
      const std::size_t start = src_.lineNumber();
      try {
        out_.antennas.push_back(readAntenna(start));
      } catch (const BlockError& e) {
        out_.report.addProblem(e.line, "antenna block starting at line " + std::to_string(start) +
                                           " skipped: " + e.reason);
        skipBlock(e);
      } catch (const OutOfRangeSatellite& s) {
        out_.report.count("satellite antenna blocks skipped (code outside the system's PRN range)");
        if (std::find(out_.skipped_satellite_codes.begin(), out_.skipped_satellite_codes.end(), s.code) ==
            out_.skipped_satellite_codes.end())
          out_.skipped_satellite_codes.push_back(s.code);
        skipBlock(BlockError{src_.lineNumber(), ""});
      }
    } else if (!isBlank(line)) {
      out_.report.addProblem(src_.lineNumber(), "line outside an antenna block ignored");
    }
  }
  if (src_.streamError()) out_.report.addProblem(src_.lineNumber(), "read stopped: " + *src_.streamError());
  if (src_.overlongLines() > 0)
    out_.report.addProblem(0, overlongLinesProblem(src_.overlongLines()));
}

void AntexParser::skipBlock(const BlockError& e) {
  if (e.consumed_block_end) return;
  std::string line;
  while (src_.next(line)) {
    const std::string_view label = labelOf(line);
    if (label == "END OF ANTENNA") return;
    if (label == "START OF ANTENNA") {
      src_.unread(line);
      return;
    }
  }
}

std::string AntexParser::nextBlockLine(const char* what) {
  std::string line;
  if (!src_.next(line)) throw error(std::string("file ends inside antenna block (expected ") + what + ")");
  if (labelOf(line) == "START OF ANTENNA") {
    const std::size_t at = src_.lineNumber();
    src_.unread(line);
    throw BlockError{at, std::string("START OF ANTENNA before END OF ANTENNA (expected ") +
                                            what + ")"};
  }
  return line;
}

void AntexParser::parseTypeSerial(const std::string& line, AntennaCalibration& a) const {
  // A20,A20,A10,A10: type (model A16 + radome A4), serial / satellite code, SVN, COSPAR ID.
  a.type = std::string(trim(column(line, 0, 20)));
  a.model = std::string(trim(column(line, 0, 16)));
  a.radome = std::string(trim(column(line, 16, 4)));
  const std::string_view serial = trim(column(line, 20, 20));
  const std::string_view svn = trim(column(line, 40, 10));
  if (a.model.empty()) throw error("empty antenna type");
  if (isSatelliteCode(serial) && !svn.empty()) {
    a.satellite = SatelliteId::parse(serial);
    if (!a.satellite) throw OutOfRangeSatellite{std::string(serial)};
    a.svn = std::string(svn);
    a.cospar_id = std::string(trim(column(line, 50, 10)));
  } else {
    a.serial = std::string(serial);
    if (a.radome.empty()) a.radome = "NONE";  // ANTEX 1.4: blank radome means none
  }
}

GnssTime AntexParser::parseEpoch(const std::string& line) const {
  // 5I6,F13.7: year, month, day, hour, minute, second (GPS time).
  long long f[5];
  for (int i = 0; i < 5; ++i) {
    if (parseInt(column(line, 6 * i, 6), f[i]) != FieldStatus::Ok) throw error("malformed validity epoch");
  }
  double sec = 0.0;
  if (parseDouble(column(line, 30, 13), sec) != FieldStatus::Ok) throw error("malformed validity epoch");
  if (f[0] < 1970 || f[0] > 2200 || f[3] < 0 || f[3] > 23 || f[4] < 0 || f[4] > 59 || sec < 0.0 ||
      sec >= 61.0 || !isValidDate(static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2]))) {
    throw error("validity epoch out of range");
  }
  CalendarTime c;
  c.year = static_cast<int>(f[0]);
  c.month = static_cast<int>(f[1]);
  c.day = static_cast<int>(f[2]);
  c.hour = static_cast<int>(f[3]);
  c.minute = static_cast<int>(f[4]);
  c.second = sec;
  try {
    return GnssTime::fromCalendar(c, TimeSystem::GPS);
  } catch (const std::invalid_argument&) {
    throw error("validity epoch out of range");
  }
}

GridShape AntexParser::checkGrid(const AntennaCalibration& a) const {
  const double z1 = a.zenith_first_deg, z2 = a.zenith_last_deg, dz = a.zenith_step_deg;
  if (!(z1 >= 0.0 && z1 <= z2 && z2 <= 180.0)) throw error("ZEN1/ZEN2 out of range (0 <= ZEN1 <= ZEN2 <= 180)");
  const auto nz = stepCount(z2 - z1, dz, kAntexMaxZenithNodes - 1);
  if (!nz) throw error("DZEN must be > 0 and divide ZEN2-ZEN1 into at most " +
                       std::to_string(kAntexMaxZenithNodes - 1) + " steps");
  GridShape shape;
  shape.zenith_nodes = *nz + 1;
  const double da = a.azimuth_step_deg;
  if (!(da >= 0.0 && da <= 360.0)) throw error("DAZI out of range [0, 360]");
  if (da > 0.0) {
    const auto na = stepCount(360.0, da, kAntexMaxAzimuthRows - 1);
    if (!na) throw error("DAZI must divide 360 into at most " + std::to_string(kAntexMaxAzimuthRows - 1) + " steps");
    shape.azimuth_rows = *na + 1;
  }
  if (shape.zenith_nodes * std::max<std::size_t>(shape.azimuth_rows, 1) > kAntexMaxGridValues) {
    throw error("PCV grid larger than " + std::to_string(kAntexMaxGridValues) + " values");
  }
  return shape;
}

std::vector<double> AntexParser::parseValues(const std::string& line, std::size_t count) const {
  // (3X,A5,mF8.2) for NOAZI and (F8.1,mF8.2) for azimuth rows: values from column 9.
  std::vector<double> values(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (parseDouble(column(line, 8 + 8 * i, 8), values[i]) != FieldStatus::Ok) {
      throw error("PCV value " + std::to_string(i + 1) + " of " + std::to_string(count) + " missing or malformed");
    }
    values[i] *= 1e-3;  // mm -> m
  }
  if (!isBlank(column(line, 8 + 8 * count, std::string::npos))) throw error("more PCV values than grid nodes");
  return values;
}

FrequencyCalibration AntexParser::readFrequency(const std::string& start, const AntennaCalibration& a,
                                                const GridShape& shape) {
  // 3X,A1,I2: system letter and frequency number, e.g. "G01".
  const std::string_view code = trim(column(start, 0, 60));
  FrequencyCalibration f;
  long long number = 0;
  const auto sys = code.size() == 3 ? systemFromLetter(code[0]) : std::nullopt;
  if (!sys || parseInt(code.substr(1), number) != FieldStatus::Ok || number < 1 || number > 99) {
    throw error("malformed frequency code '" + std::string(code) + "'");
  }
  f.system = *sys;
  f.frequency = static_cast<int>(number);
  if (a.frequency(f.system, f.frequency) != nullptr) throw error("frequency " + std::string(code) + " given twice");

  std::string line = nextBlockLine("NORTH / EAST / UP");
  if (labelOf(line) != "NORTH / EAST / UP") throw error("NORTH / EAST / UP missing after START OF FREQUENCY");
  for (int i = 0; i < 3; ++i) {  // 3F10.2 in mm
    double v = 0.0;
    if (parseDouble(column(line, 10 * i, 10), v) != FieldStatus::Ok) throw error("malformed PCO value");
    f.pco_m[i] = v * 1e-3;
  }
  f.pcv.zenith_first_deg = a.zenith_first_deg;
  f.pcv.zenith_last_deg = a.zenith_last_deg;
  f.pcv.zenith_step_deg = a.zenith_step_deg;
  f.pcv.azimuth_step_deg = a.azimuth_step_deg;

  line = nextBlockLine("NOAZI row");
  if (column(line, 3, 5) != "NOAZI") throw error("NOAZI row missing");
  f.pcv.noazi_m = parseValues(line, shape.zenith_nodes);
  f.pcv.azimuth_m.reserve(shape.azimuth_rows * shape.zenith_nodes);
  for (std::size_t row = 0; row < shape.azimuth_rows; ++row) {
    line = nextBlockLine("azimuth row");
    double azimuth = 0.0;
    if (!labelOf(line).empty() && labelOf(line) == "END OF FREQUENCY") {
      throw error("only " + std::to_string(row) + " of " + std::to_string(shape.azimuth_rows) + " azimuth rows");
    }
    if (parseDouble(column(line, 0, 8), azimuth) != FieldStatus::Ok ||
        std::fabs(azimuth - static_cast<double>(row) * a.azimuth_step_deg) > 0.05) {
      throw error("azimuth row " + std::to_string(row) + " does not start with azimuth " +
                  std::to_string(static_cast<double>(row) * a.azimuth_step_deg));
    }
    const auto values = parseValues(line, shape.zenith_nodes);
    f.pcv.azimuth_m.insert(f.pcv.azimuth_m.end(), values.begin(), values.end());
  }
  line = nextBlockLine("END OF FREQUENCY");
  if (labelOf(line) != "END OF FREQUENCY") throw error("END OF FREQUENCY expected");
  if (trim(column(line, 0, 60)) != code) throw error("END OF FREQUENCY does not match " + std::string(code));
  return f;
}

void AntexParser::skipRmsBlock() {
  while (true) {
    const std::string line = nextBlockLine("END OF FREQ RMS");
    const std::string_view label = labelOf(line);
    if (label == "END OF FREQ RMS") return;
    if (label == "END OF ANTENNA") throw error("END OF ANTENNA inside an RMS block");
  }
}

/// ZEN1 / ZEN2 / DZEN (2X,3F6.1) into the calibration; false when a field is malformed.
bool parseZenithGrid(const std::string& line, AntennaCalibration& a) {
  return parseDouble(column(line, 2, 6), a.zenith_first_deg) == FieldStatus::Ok &&
         parseDouble(column(line, 8, 6), a.zenith_last_deg) == FieldStatus::Ok &&
         parseDouble(column(line, 14, 6), a.zenith_step_deg) == FieldStatus::Ok;
}

/// What is wrong with a complete antenna block at END OF ANTENNA ("" when nothing).
std::string antennaEndProblem(const AntennaCalibration& a, const std::optional<long long>& declared_frequencies) {
  if (a.frequencies.empty()) return "no frequency block";
  if (!declared_frequencies) return "# OF FREQUENCIES missing";
  if (static_cast<std::size_t>(*declared_frequencies) != a.frequencies.size())
    return "# OF FREQUENCIES says " + std::to_string(*declared_frequencies) + " but " +
           std::to_string(a.frequencies.size()) + " frequency blocks found";
  if (a.valid_from && a.valid_until && *a.valid_until < *a.valid_from) return "VALID UNTIL before VALID FROM";
  return {};
}

AntennaCalibration AntexParser::readAntenna(std::size_t start_line) {
  AntennaCalibration a;
  a.line = start_line;
  bool have_type = false, have_dazi = false, have_zen = false;
  std::optional<long long> declared_frequencies;
  std::optional<GridShape> shape;
  while (true) {
    const std::string line = nextBlockLine("END OF ANTENNA");
    const std::string_view label = labelOf(line);
    if (!have_type && label != "TYPE / SERIAL NO") throw error("TYPE / SERIAL NO must follow START OF ANTENNA");
    if (label == "TYPE / SERIAL NO") {
      if (have_type) throw error("TYPE / SERIAL NO given twice");
      parseTypeSerial(line, a);
      have_type = true;
    } else if (label == "METH / BY / # / DATE" || label == "COMMENT") {
      // Informative only.
    } else if (label == "DAZI") {
      if (parseDouble(column(line, 0, 8), a.azimuth_step_deg) != FieldStatus::Ok) throw error("malformed DAZI");
      have_dazi = true;
    } else if (label == "ZEN1 / ZEN2 / DZEN") {
      if (!parseZenithGrid(line, a)) throw error("malformed ZEN1 / ZEN2 / DZEN");
      have_zen = true;
    } else if (label == "# OF FREQUENCIES") {
      long long n = 0;
      if (parseInt(column(line, 0, 6), n) != FieldStatus::Ok || n < 1 ||
          n > static_cast<long long>(kAntexMaxFrequencies)) {
        throw error("malformed # OF FREQUENCIES");
      }
      declared_frequencies = n;
    } else if (label == "VALID FROM") {
      a.valid_from = parseEpoch(line);
    } else if (label == "VALID UNTIL") {
      a.valid_until = parseEpoch(line);
    } else if (label == "SINEX CODE") {
      a.sinex_code = std::string(trim(column(line, 0, 10)));
    } else if (label == "START OF FREQUENCY") {
      if (!have_dazi || !have_zen) throw error("START OF FREQUENCY before DAZI and ZEN1 / ZEN2 / DZEN");
      if (!shape) shape = checkGrid(a);
      if (a.frequencies.size() >= kAntexMaxFrequencies) throw error("too many frequencies");
      a.frequencies.push_back(readFrequency(line, a, *shape));
    } else if (label == "START OF FREQ RMS") {
      skipRmsBlock();
      ++a.rms_blocks_skipped;
      out_.report.count("RMS blocks skipped");
    } else if (label == "END OF ANTENNA") {
      BlockError e = error(antennaEndProblem(a, declared_frequencies));
      e.consumed_block_end = true;
      if (!e.reason.empty()) throw e;
      return a;
    } else {
      throw error("unexpected line in antenna block" + (label.empty() ? std::string() : ": '" + std::string(label) + "'"));
    }
  }
}

bool equalsNoCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto up = [](char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; };
    if (up(a[i]) != up(b[i])) return false;
  }
  return true;
}

}  // namespace

const AntennaCalibration* AntexFile::satellite(const SatelliteId& sat, const GnssTime& t) const {
  const AntennaCalibration* best = nullptr;
  for (const auto& a : antennas) {
    if (!a.satellite || *a.satellite != sat || !a.validAt(t)) continue;
    if (best == nullptr || (a.valid_from && (!best->valid_from || *best->valid_from < *a.valid_from))) best = &a;
  }
  return best;
}

ReceiverAntennaLookup AntexFile::receiver(std::string_view model, std::string_view radome) const {
  model = trim(model);
  radome = trim(radome);
  const auto find = [&](std::string_view r) -> const AntennaCalibration* {
    const AntennaCalibration* found = nullptr;
    for (const auto& a : antennas) {
      if (a.satellite || !equalsNoCase(a.model, model) || !equalsNoCase(a.radome, r)) continue;
      if (a.serial.empty()) return &a;  // type mean preferred
      if (found == nullptr) found = &a;
    }
    return found;
  };
  ReceiverAntennaLookup out;
  const std::string asked = std::string(model) + " " + (radome.empty() ? "(no radome)" : std::string(radome));
  if (!radome.empty()) out.antenna = find(radome);
  if (out.antenna != nullptr) return out;
  if (!equalsNoCase(radome, "NONE")) {
    out.antenna = find("NONE");
    if (out.antenna != nullptr) {
      out.radome_substituted = true;
      out.note = asked + " not found, using " + out.antenna->model + " NONE";
      return out;
    }
  }
  out.note = asked + " not found";
  return out;
}

ReceiverAntennaLookup AntexFile::receiver(std::string_view antenna_type) const {
  std::vector<std::string_view> tokens;
  std::string_view rest = trim(antenna_type);
  while (!rest.empty() && tokens.size() < 3) {
    const std::size_t end = rest.find_first_of(" \t");
    tokens.push_back(rest.substr(0, end));
    rest = end == std::string_view::npos ? std::string_view() : trim(rest.substr(end));
  }
  if (tokens.size() == 1) return receiver(tokens[0], "");
  if (tokens.size() == 2) return receiver(tokens[0], tokens[1]);
  // Fixed columns as in RINEX ANT # / TYPE (model A16, radome A4).
  return receiver(column(antenna_type, 0, 16), column(antenna_type, 16, 4));
}

std::size_t AntexFile::receiverCount() const {
  std::size_t n = 0;
  for (const auto& a : antennas) n += a.satellite ? 0 : 1;
  return n;
}

std::size_t AntexFile::satelliteCount() const { return antennas.size() - receiverCount(); }

namespace {

bool sameFrequency(const FrequencyCalibration& a, const FrequencyCalibration& b) {
  return a.system == b.system && a.frequency == b.frequency && a.pco_m == b.pco_m &&
         a.pcv.zenith_first_deg == b.pcv.zenith_first_deg && a.pcv.zenith_last_deg == b.pcv.zenith_last_deg &&
         a.pcv.zenith_step_deg == b.pcv.zenith_step_deg && a.pcv.azimuth_step_deg == b.pcv.azimuth_step_deg &&
         a.pcv.noazi_m == b.pcv.noazi_m && a.pcv.azimuth_m == b.pcv.azimuth_m;
}

bool sameValues(const AntennaCalibration& a, const AntennaCalibration& b) {
  if (a.frequencies.size() != b.frequencies.size()) return false;
  for (std::size_t i = 0; i < a.frequencies.size(); ++i)
    if (!sameFrequency(a.frequencies[i], b.frequencies[i])) return false;
  return true;
}

/// One antenna: a satellite (PRN and SVN) or a receiver type and serial.
std::string antennaKey(const AntennaCalibration& a) {
  return a.satellite ? a.satellite->toString() + " " + a.svn : a.type + "|" + a.serial;
}

bool validitiesOverlap(const AntennaCalibration& a, const AntennaCalibration& b) {
  const bool a_before_b = a.valid_until && b.valid_from && !(*b.valid_from < *a.valid_until);
  const bool b_before_a = b.valid_until && a.valid_from && !(*a.valid_from < *b.valid_until);
  return !a_before_b && !b_before_a;
}

/// Two blocks of one antenna valid at the same time with different values: which
/// one applies is unknown, so the file is refused (ParseError at the later block).
void refuseConflictingBlocks(const AntexFile& file, const std::string& name) {
  std::map<std::string, std::vector<const AntennaCalibration*>> by_antenna;
  for (const auto& a : file.antennas) by_antenna[antennaKey(a)].push_back(&a);
  for (const auto& [key, blocks] : by_antenna)
    for (std::size_t i = 0; i < blocks.size(); ++i)
      for (std::size_t j = i + 1; j < blocks.size(); ++j) {
        const AntennaCalibration& a = *blocks[i];
        const AntennaCalibration& b = *blocks[j];
        if (!validitiesOverlap(a, b) || sameValues(a, b)) continue;
        throw ParseError(name, b.line,
                         "antenna block of " + b.label() + " conflicts with the block at line " +
                             std::to_string(a.line) +
                             ": the same antenna, overlapping validity, different offsets or variations "
                             "(which one is right is unknown: remove one)");
      }
}

}  // namespace

AntexFile readAntex(LineSource& source) {
  AntexFile out;
  out.report.setFile(source.name());
  AntexParser parser(source, out);
  parser.readHeader();
  parser.readBody();
  refuseConflictingBlocks(out, source.name());
  out.report.count("antennas read", out.antennas.size());
  return out;
}

AntexFile readAntexFile(const std::string& path) {
  auto source = openLineSource(path);
  return readAntex(*source);
}

FileSummary summarizeAntexFile(const std::string& path) {
  const AntexFile file = readAntexFile(path);
  FileSummary s;
  s.path = path;
  s.type = "ANTEX";
  s.version = file.header.version;
  s.epoch_count = file.antennas.size();
  s.count_label = "antenna blocks";
  std::map<GnssSystem, std::size_t> blocks_per_system;
  for (const auto& a : file.antennas) {
    if (a.satellite) {
      s.satellites[a.satellite->system].insert(*a.satellite);
      ++blocks_per_system[a.satellite->system];
      if (a.valid_from && (!s.first_epoch || *a.valid_from < *s.first_epoch)) s.first_epoch = a.valid_from;
      if (a.valid_until && (!s.last_epoch || *s.last_epoch < *a.valid_until)) s.last_epoch = a.valid_until;
    }
    for (const auto& f : a.frequencies) s.signals[f.system].insert(f.code());
  }
  s.facts.push_back(std::string("PCV type ") + file.header.pcv_type +
                    (file.header.pcv_type == 'A' ? " (absolute)" : " (relative)") +
                    (file.header.reference_antenna.empty() ? "" : ", reference " + file.header.reference_antenna));
  s.facts.push_back(std::string("system ") + file.header.system);
  s.facts.push_back(std::to_string(file.antennas.size()) + " antenna blocks: " +
                    std::to_string(file.receiverCount()) + " receiver, " +
                    std::to_string(file.satelliteCount()) + " satellite");
  for (const auto& [sys, n] : blocks_per_system) {
    s.facts.push_back(std::string(systemName(sys)) + ": " + std::to_string(n) + " satellite blocks, " +
                      std::to_string(s.satellites[sys].size()) + " PRNs");
  }
  std::size_t listed = 0;
  for (const auto& a : file.antennas) {
    if (a.satellite) continue;
    if (listed++ == 20) {
      s.facts.push_back("... more receiver antennas");
      break;
    }
    s.facts.push_back("receiver antenna " + a.model + " " + a.radome + (a.serial.empty() ? "" : " #" + a.serial) +
                      " (" + std::to_string(a.frequencies.size()) + " frequencies)");
  }
  s.report = file.report;
  return s;
}

}  // namespace ppp
