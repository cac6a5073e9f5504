// RINEX observation header parsing (RINEX 2.11 table A1, RINEX 3.05 table A2,
// RINEX 4.00 table A2). Column numbers in comments are 1-based as in the specs.
#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"

#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/io/parse_error.h"

namespace ppp {

namespace {

constexpr std::size_t kMaxHeaderLines = 100000;
constexpr int kMaxTypes = 200;  // per system; RINEX 3.05 lists far fewer

std::string_view label(std::string_view line) { return trim(column(line, 60, 20)); }

std::string field(std::string_view line, std::size_t start, std::size_t width) {
  return std::string(trim(column(line, start, width)));
}

bool allSystems(char letter) { return letter == 'M' || letter == ' '; }

/// 3F14.4; when the columns are misaligned (some writers), three blank-separated
/// numbers in columns 1-60 are accepted too.
std::optional<Eigen::Vector3d> threeDoubles(std::string_view line) {
  double v[3];
  bool ok = true;
  for (int i = 0; i < 3 && ok; ++i) ok = parseDouble(column(line, 14 * i, 14), v[i]) == FieldStatus::Ok;
  if (ok) return Eigen::Vector3d(v[0], v[1], v[2]);
  std::string_view rest = column(line, 0, 60);
  for (int i = 0; i < 3; ++i) {
    rest = rest.substr(std::min(rest.size(), rest.find_first_not_of(' ')));
    const std::size_t end = std::min(rest.size(), rest.find(' '));
    if (parseDouble(rest.substr(0, end), v[i]) != FieldStatus::Ok) return std::nullopt;
    rest.remove_prefix(end);
  }
  if (!isBlank(rest)) return std::nullopt;
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

/// Default time system of the epochs of a file of the given system letter
/// (RINEX 3.05 sec. 6.2 and TIME OF FIRST OBS: GPS for GPS and mixed files).
TimeSystem defaultTimeSystem(char file_system) {
  switch (file_system) {
    case 'R': return TimeSystem::UTC;  // GLONASS time tags are UTC (sec. 6.2)
    case 'E': return TimeSystem::Galileo;
    case 'C': return TimeSystem::BeiDou;
    case 'J': return TimeSystem::QZSS;
    default: return TimeSystem::GPS;
  }
}

}  // namespace

std::string RinexObsHeader::antexAntennaName() const {
  std::string name = antenna_type;
  if (name.size() < 16) name.resize(16, ' ');
  return name + radomeOrNone();
}

std::optional<ObservationCode> mapRinex2ObsCode(GnssSystem system, std::string_view code) {
  code = trim(code);
  if (code.size() != 2) return std::nullopt;
  char type = code[0];
  const char band = code[1];
  if (band < '1' || band > '9') return std::nullopt;
  if (type != 'C' && type != 'P' && type != 'L' && type != 'D' && type != 'S') return std::nullopt;
  char attribute = 'X';
  const bool p_code = type == 'P';
  if (p_code) type = 'C';
  switch (system) {
    case GnssSystem::GPS:
      if (band == '1') attribute = p_code ? 'W' : 'C';
      else if (band == '2') attribute = (p_code || type != 'C') ? 'W' : 'X';
      else attribute = p_code ? 'P' : 'X';
      break;
    case GnssSystem::GLONASS:
      if (band == '1' || band == '2') attribute = p_code ? 'P' : ((band == '2' && type != 'C') ? 'P' : 'C');
      else attribute = p_code ? 'P' : 'X';
      break;
    case GnssSystem::SBAS:
      attribute = p_code ? 'P' : (band == '1' ? 'C' : 'X');
      break;
    default:
      attribute = p_code ? 'P' : 'X';
      break;
  }
  const char text[3] = {type, band, attribute};
  return ObservationCode::parse(std::string_view(text, 3));
}

void RinexObsHeaderParser::fail(std::size_t line, const std::string& reason) const {
  throw ParseError(file_, line, reason);
}

void RinexObsHeaderParser::versionLine(std::string_view text, std::size_t line_number) {
  if (label(text) != "RINEX VERSION / TYPE") {
    fail(line_number, "not a RINEX file: first line is not RINEX VERSION / TYPE");
  }
  header_.version_text = field(text, 0, 9);
  double version = 0;
  if (parseDouble(column(text, 0, 9), version) != FieldStatus::Ok) {
    fail(line_number, "bad RINEX version '" + header_.version_text + "'");
  }
  const int major = static_cast<int>(std::floor(version + 1e-9));
  if (major < 2 || major > 4) {
    fail(line_number, "unsupported RINEX version " + header_.version_text);
  }
  header_.version = version;
  header_.major_version = major;
  const char type = column(text, 20, 1).empty() ? ' ' : text[20];
  if (type != 'O' && type != 'o') {
    fail(line_number, std::string("not an observation file (file type '") + type + "')");
  }
  const std::string_view sys = column(text, 40, 1);
  char letter = sys.empty() ? ' ' : sys[0];
  if (letter == ' ') letter = 'G';  // RINEX 2.11: blank means GPS
  if (!allSystems(letter) && !systemFromLetter(letter)) {
    fail(line_number, std::string("unknown satellite system '") + letter + "' in RINEX VERSION / TYPE");
  }
  header_.file_system = letter;
  header_.epoch_time_system = defaultTimeSystem(letter);
}

void RinexObsHeaderParser::checkPending(std::string_view lab, std::size_t line_number) {
  // A continuation line carries the same label; any other label ends the list.
  if (pending_types_ > 0 && lab != "SYS / # / OBS TYPES" && lab != "# / TYPES OF OBSERV") {
    fail(pending_types_line_, "observation type list ends " + std::to_string(pending_types_) +
                                  " types short of its count");
  }
  if (pending_glonass_ > 0 && lab != "GLONASS SLOT / FRQ #") pending_glonass_ = 0;  // lenient
  if (pending_phase_sats_ > 0 && lab != "SYS / PHASE SHIFT") pending_phase_sats_ = 0;
  if (pending_scale_ > 0 && lab != "SYS / SCALE FACTOR") pending_scale_ = 0;
  (void)line_number;
}

void RinexObsHeaderParser::finish(std::size_t line_number) { checkPending("END OF HEADER", line_number); }

void RinexObsHeaderParser::obsTypesRinex3(std::string_view text, std::size_t line_number) {
  // A1, 2X, I3, 13(1X, A3); continuation lines: 6X, 13(1X, A3).
  const char letter = text.empty() ? ' ' : text[0];
  int sys_index = -1;
  int count = 0;
  if (letter != ' ') {
    if (pending_types_ > 0) fail(pending_types_line_, "observation type list ends " +
                                                           std::to_string(pending_types_) +
                                                           " types short of its count");
    const auto sys = systemFromLetter(letter);
    if (!sys) fail(line_number, std::string("unknown system '") + letter + "' in SYS / # / OBS TYPES");
    long long n = 0;
    if (parseInt(column(text, 3, 3), n) != FieldStatus::Ok || n < 1 || n > kMaxTypes) {
      fail(line_number, "bad observation type count '" + field(text, 3, 3) + "'");
    }
    sys_index = static_cast<int>(*sys);
    count = static_cast<int>(n);
    header_.obs_types[sys_index].clear();
    header_.scale_factors[sys_index].clear();
    pending_types_ = count;
    pending_types_system_ = sys_index;
    pending_types_line_ = line_number;
  } else {
    if (pending_types_ <= 0 || pending_types_system_ < 0) {
      fail(line_number, "SYS / # / OBS TYPES continuation line without a pending list");
    }
    sys_index = pending_types_system_;
  }
  for (int i = 0; i < 13 && pending_types_ > 0; ++i) {
    const std::string_view code_text = trim(column(text, 7 + 4 * i, 3));
    if (code_text.empty()) break;
    const auto code = ObservationCode::parse(code_text);
    if (!code || code_text.size() != 3) {
      fail(line_number, "bad observation code '" + std::string(code_text) + "'");
    }
    header_.obs_types[sys_index].push_back(*code);
    header_.scale_factors[sys_index].push_back(1.0);
    --pending_types_;
  }
}

void RinexObsHeaderParser::obsTypesRinex2(std::string_view text, std::size_t line_number) {
  // I6, 9(4X, A2); continuation lines: 6X, 9(4X, A2).
  if (!isBlank(column(text, 0, 6))) {
    if (pending_types_ > 0) fail(pending_types_line_, "observation type list ends " +
                                                           std::to_string(pending_types_) +
                                                           " types short of its count");
    long long n = 0;
    if (parseInt(column(text, 0, 6), n) != FieldStatus::Ok || n < 1 || n > kMaxTypes) {
      fail(line_number, "bad observation type count '" + field(text, 0, 6) + "'");
    }
    header_.rinex2_obs_types.clear();
    for (auto& types : header_.obs_types) types.clear();
    for (auto& scales : header_.scale_factors) scales.clear();
    pending_types_ = static_cast<int>(n);
    pending_types_system_ = -2;
    pending_types_line_ = line_number;
  } else if (pending_types_ <= 0 || pending_types_system_ != -2) {
    fail(line_number, "# / TYPES OF OBSERV continuation line without a pending list");
  }
  for (int i = 0; i < 9 && pending_types_ > 0; ++i) {
    const std::string_view code_text = trim(column(text, 6 + 6 * i, 6));
    if (code_text.empty()) break;
    if (!mapRinex2ObsCode(GnssSystem::GPS, code_text)) {
      fail(line_number, "bad RINEX 2 observation code '" + std::string(code_text) + "'");
    }
    header_.rinex2_obs_types.emplace_back(code_text);
    for (int s = 0; s < kNumGnssSystems; ++s) {
      header_.obs_types[s].push_back(*mapRinex2ObsCode(static_cast<GnssSystem>(s), code_text));
      header_.scale_factors[s].push_back(1.0);
    }
    --pending_types_;
  }
}

void RinexObsHeaderParser::phaseShift(std::string_view text, std::size_t line_number) {
  // A1, 1X, A3, 1X, F8.5, 2X, I2.2, 10(1X, A3); continuation: 18X, 10(1X, A3).
  const char letter = text.empty() ? ' ' : text[0];
  if (letter == ' ') {
    if (pending_phase_sats_ <= 0 || header_.phase_shifts.empty()) return;  // stray: ignore
  } else {
    const auto sys = systemFromLetter(letter);
    const auto code = ObservationCode::parse(trim(column(text, 2, 3)));
    if (!sys || !code) {
      fail(line_number, "bad SYS / PHASE SHIFT record '" + field(text, 0, 14) + "'");
    }
    PhaseShift shift;
    shift.system = *sys;
    shift.code = *code;
    double cycles = 0;
    const FieldStatus st = parseDouble(column(text, 6, 8), cycles);
    if (st == FieldStatus::Malformed) fail(line_number, "bad phase shift '" + field(text, 6, 8) + "'");
    if (st == FieldStatus::Ok) shift.shift_cycles = cycles;
    long long n = 0;
    const FieldStatus nst = parseInt(column(text, 16, 2), n);
    if (nst == FieldStatus::Malformed || n < 0) {
      fail(line_number, "bad satellite count in SYS / PHASE SHIFT '" + field(text, 16, 2) + "'");
    }
    pending_phase_sats_ = static_cast<int>(n);
    header_.phase_shifts.push_back(std::move(shift));
  }
  auto& sats = header_.phase_shifts.back().satellites;
  for (int i = 0; i < 10 && pending_phase_sats_ > 0; ++i) {
    const std::string_view sat_text = trim(column(text, 19 + 4 * i, 3));
    if (sat_text.empty()) break;
    const auto sat = SatelliteId::parse(sat_text);
    if (!sat) fail(line_number, "bad satellite '" + std::string(sat_text) + "' in SYS / PHASE SHIFT");
    sats.push_back(*sat);
    --pending_phase_sats_;
  }
}

void RinexObsHeaderParser::glonassSlots(std::string_view text, std::size_t line_number) {
  // I3, 1X, 8(A3, 1X, I2, 1X); continuation: 4X, 8(A3, 1X, I2, 1X).
  if (!isBlank(column(text, 0, 3))) {
    long long n = 0;
    if (parseInt(column(text, 0, 3), n) != FieldStatus::Ok || n < 0 || n > 99) {
      fail(line_number, "bad slot count in GLONASS SLOT / FRQ # '" + field(text, 0, 3) + "'");
    }
    pending_glonass_ = static_cast<int>(n);
  }
  for (int i = 0; i < 8 && pending_glonass_ > 0; ++i) {
    const std::string_view sat_text = trim(column(text, 4 + 7 * i, 3));
    if (sat_text.empty()) break;
    const auto sat = SatelliteId::parse(sat_text);
    long long k = 0;
    if (!sat || sat->system != GnssSystem::GLONASS || parseInt(column(text, 8 + 7 * i, 2), k) != FieldStatus::Ok ||
        sat->prn < 1 || sat->prn > GlonassChannels::kMaxSlot) {
      fail(line_number, "bad GLONASS SLOT / FRQ # entry '" + field(text, 4 + 7 * i, 7) + "'");
    }
    if (!header_.glonass_channels.set(sat->prn, static_cast<int>(k))) {
      fail(line_number, "GLONASS SLOT / FRQ # channel " + std::to_string(k) + " of " + sat->toString() +
                            " is outside -7..+6 (the channels in use since 2005, GLONASS ICD 5.1)");
    }
    ++header_.glonass_channel_entries;
    --pending_glonass_;
  }
}

void RinexObsHeaderParser::scaleFactor(std::string_view text, std::size_t line_number) {
  // A1, 1X, I4, 2X, I2, 12(1X, A3); continuation: 10X, 12(1X, A3).
  const char letter = text.empty() ? ' ' : text[0];
  if (letter != ' ') {
    const auto sys = systemFromLetter(letter);
    long long factor = 0, n = 0;
    if (!sys || parseInt(column(text, 2, 4), factor) != FieldStatus::Ok ||
        (factor != 1 && factor != 10 && factor != 100 && factor != 1000) ||
        parseInt(column(text, 8, 2), n) == FieldStatus::Malformed || n < 0) {
      fail(line_number, "bad SYS / SCALE FACTOR record");
    }
    pending_scale_system_ = static_cast<int>(*sys);
    pending_scale_factor_ = static_cast<double>(factor);
    pending_scale_ = static_cast<int>(n);
    if (n == 0) {  // all types of the system
      for (double& s : header_.scale_factors[pending_scale_system_]) s = pending_scale_factor_;
      return;
    }
  } else if (pending_scale_ <= 0) {
    return;
  }
  const auto& types = header_.obs_types[pending_scale_system_];
  for (int i = 0; i < 12 && pending_scale_ > 0; ++i) {
    const std::string_view code_text = trim(column(text, 11 + 4 * i, 3));
    if (code_text.empty()) break;
    const auto code = ObservationCode::parse(code_text);
    if (!code) fail(line_number, "bad code '" + std::string(code_text) + "' in SYS / SCALE FACTOR");
    for (std::size_t k = 0; k < types.size(); ++k) {
      if (types[k] == *code) header_.scale_factors[pending_scale_system_][k] = pending_scale_factor_;
    }
    --pending_scale_;
  }
}

RinexHeaderTime RinexObsHeaderParser::headerTime(std::string_view text, std::size_t line_number) {
  // 5I6, F13.7, 5X, A3.
  long long v[5];
  double sec = 0;
  for (int i = 0; i < 5; ++i) {
    if (parseInt(column(text, 6 * i, 6), v[i]) != FieldStatus::Ok) {
      fail(line_number, "bad date in " + std::string(label(text)));
    }
  }
  if (parseDouble(column(text, 30, 13), sec) != FieldStatus::Ok) {
    fail(line_number, "bad seconds in " + std::string(label(text)));
  }
  RinexHeaderTime t;
  t.calendar = CalendarTime{static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]),
                            static_cast<int>(v[3]), static_cast<int>(v[4]), sec};
  const std::string_view sys = trim(column(text, 48, 3));
  t.system = header_.epoch_time_system;
  if (!sys.empty()) {
    const auto parsed = parseTimeSystem(sys);
    if (!parsed) fail(line_number, "unknown time system '" + std::string(sys) + "'");
    // RINEX "GLO" time tags are UTC(SU) (RINEX 3.05 sec. 6.2), not GLONASST = UTC + 3 h.
    t.system = *parsed == TimeSystem::GLONASS ? TimeSystem::UTC : *parsed;
  }
  try {
    t.time = GnssTime::fromCalendar(t.calendar, t.system);
  } catch (const std::exception&) {
    fail(line_number, "invalid date in " + std::string(label(text)));
  }
  return t;
}

bool RinexObsHeaderParser::stationLine(std::string_view lab, std::string_view text, std::size_t n) {
  if (lab == "COMMENT") {
    if (header_.comments.size() < RinexObsHeader::kMaxComments) header_.comments.push_back(field(text, 0, 60));
  } else if (lab == "PGM / RUN BY / DATE") {
    header_.program = field(text, 0, 20);
    header_.run_by = field(text, 20, 20);
    header_.date = field(text, 40, 20);
  } else if (lab == "MARKER NAME") {
    header_.marker_name = field(text, 0, 60);
  } else if (lab == "MARKER NUMBER") {
    header_.marker_number = field(text, 0, 20);
  } else if (lab == "MARKER TYPE") {
    header_.marker_type = field(text, 0, 20);
  } else if (lab == "OBSERVER / AGENCY") {
    header_.observer = field(text, 0, 20);
    header_.agency = field(text, 20, 40);
  } else if (lab == "REC # / TYPE / VERS") {
    header_.receiver_number = field(text, 0, 20);
    header_.receiver_type = field(text, 20, 20);
    header_.receiver_version = field(text, 40, 20);
  } else if (lab == "ANT # / TYPE") {
    // A20, A20: the type is the 20-character IGS name, 16 model + 4 radome
    // (IGS rcvr_ant.tab, ANTEX 1.4 "TYPE / SERIAL NO").
    header_.antenna_number = field(text, 0, 20);
    header_.antenna_type = field(text, 20, 16);
    header_.antenna_radome = field(text, 36, 4);
  } else if (lab == "APPROX POSITION XYZ") {
    header_.approx_position_ecef_m = threeDoubles(text);
    if (!header_.approx_position_ecef_m) fail(n, "bad APPROX POSITION XYZ");
  } else if (lab == "ANTENNA: DELTA H/E/N") {
    header_.antenna_delta_hen_m = threeDoubles(text);
    if (!header_.antenna_delta_hen_m) fail(n, "bad ANTENNA: DELTA H/E/N");
  } else {
    return false;
  }
  return true;
}

bool RinexObsHeaderParser::layoutLine(std::string_view lab, std::string_view text, std::size_t n) {
  if (lab == "SYS / # / OBS TYPES") {
    if (header_.isRinex2()) fail(n, "SYS / # / OBS TYPES in a RINEX 2 file");
    obsTypesRinex3(text, n);
  } else if (lab == "# / TYPES OF OBSERV") {
    if (!header_.isRinex2()) fail(n, "# / TYPES OF OBSERV in a RINEX 3/4 file");
    obsTypesRinex2(text, n);
  } else if (lab == "SYS / SCALE FACTOR") {
    scaleFactor(text, n);
  } else if (lab == "SYS / PHASE SHIFT") {
    phaseShift(text, n);
  } else if (lab == "GLONASS SLOT / FRQ #") {
    glonassSlots(text, n);
  } else if (lab == "INTERVAL") {
    double v = 0;
    if (parseDouble(column(text, 0, 10), v) == FieldStatus::Ok && v > 0) header_.interval_s = v;
  } else if (lab == "TIME OF FIRST OBS") {
    header_.time_of_first_obs = headerTime(text, n);
    header_.epoch_time_system = header_.time_of_first_obs->system;
  } else if (lab == "TIME OF LAST OBS") {
    header_.time_of_last_obs = headerTime(text, n);
  } else if (lab == "RCV CLOCK OFFS APPL") {
    if (auto v = toInt(column(text, 0, 6))) header_.receiver_clock_offset_applied = static_cast<int>(*v);
  } else if (lab == "LEAP SECONDS") {
    if (auto v = toInt(column(text, 0, 6))) header_.leap_seconds = static_cast<int>(*v);
  } else if (lab == "SIGNAL STRENGTH UNIT") {
    header_.signal_strength_unit = field(text, 0, 20);
  } else {
    return false;
  }
  return true;
}

bool RinexObsHeaderParser::line(std::string_view text, std::size_t n) {
  const std::string_view lab = label(text);
  checkPending(lab, n);
  if (lab == "END OF HEADER") return true;
  if (!stationLine(lab, text, n)) layoutLine(lab, text, n);
  // Other labels (WAVELENGTH FACT L1/2, # OF SATELLITES, PRN / # OF OBS, SYS / DCBS
  // APPLIED, GLONASS COD/PHS/BIS, RINEX 4 DOI / LICENSE ...) are not needed.
  return false;
}

RinexObsHeader readRinexObsHeader(LineSource& source) {
  RinexObsHeader header;
  RinexObsHeaderParser parser(header, source.name());
  std::string text;
  if (!source.next(text)) {
    throw ParseError(source.name(), 0, source.streamError() ? *source.streamError() : "empty file");
  }
  parser.versionLine(text, source.lineNumber());
  bool ended = false;
  while (source.next(text)) {
    if (source.lineNumber() > kMaxHeaderLines) {
      throw ParseError(source.name(), source.lineNumber(), "header longer than 100000 lines");
    }
    if (parser.line(text, source.lineNumber())) {
      ended = true;
      break;
    }
  }
  const std::size_t last = source.lineNumber();
  if (!ended) {
    std::string reason = "missing END OF HEADER";
    if (source.streamError()) reason += " (" + *source.streamError() + ")";
    throw ParseError(source.name(), last, reason);
  }
  parser.finish(last);
  header.header_lines = last;
  bool any = false;
  for (const auto& types : header.obs_types) any = any || !types.empty();
  if (!any) throw ParseError(source.name(), last, "no observation types in the header");
  return header;
}

}  // namespace ppp
