// RINEX observation records (RINEX 2.11 sec. 5 and table A2; RINEX 3.05 sec. 5
// and table A3; RINEX 4.00 table A3). Column numbers in comments are 1-based.
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"

#include <cstring>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"

namespace ppp {

namespace {

constexpr int kMaxSatellitesPerEpoch = 999;  // I3 field

constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,
                             1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18};

/// Fast path for the F14.3-like fields of the data records: blanks, optional
/// sign, digits, optional point and digits. Returns Malformed for anything
/// else, so that the caller can fall back to the general parser.
inline FieldStatus fastDecimal(std::string_view f, double& value) {
  std::size_t i = 0, n = f.size();
  while (i < n && f[i] == ' ') ++i;
  while (n > i && f[n - 1] == ' ') --n;
  if (i == n) return FieldStatus::Blank;
  bool negative = false;
  if (f[i] == '-' || f[i] == '+') {
    negative = f[i] == '-';
    ++i;
  }
  std::int64_t mantissa = 0;
  int digits = 0, decimals = 0;
  bool point = false;
  for (; i < n; ++i) {
    const char c = f[i];
    if (c >= '0' && c <= '9') {
      if (++digits > 18) return FieldStatus::Malformed;
      mantissa = mantissa * 10 + (c - '0');
      if (point) ++decimals;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      return FieldStatus::Malformed;
    }
  }
  if (digits == 0) return FieldStatus::Malformed;
  value = static_cast<double>(mantissa) / kPow10[decimals];
  if (negative) value = -value;
  return FieldStatus::Ok;
}

inline std::optional<std::uint8_t> digitFlag(std::string_view line, std::size_t pos) {
  if (pos >= line.size()) return std::nullopt;
  const char c = line[pos];
  if (c >= '0' && c <= '9') return static_cast<std::uint8_t>(c - '0');
  return std::nullopt;
}

inline bool isDigit(char c) { return c >= '0' && c <= '9'; }

bool intField(std::string_view line, std::size_t start, std::size_t width, int& out) {
  long long v = 0;
  if (parseInt(column(line, start, width), v) != FieldStatus::Ok || v < -1000000 || v > 1000000) {
    return false;
  }
  out = static_cast<int>(v);
  return true;
}

}  // namespace

struct RinexObsReader::EpochHeader {
  CalendarTime calendar;
  bool time_valid = false;
  int flag = 0;
  int count = 0;  // satellites, or special records for flags 2-5
  std::optional<double> clock_s;
  std::size_t line = 0;
};

RinexObsReader::RinexObsReader(std::unique_ptr<LineSource> source)
    : source_(std::move(source)), report_(source_->name()) {
  compact_ = dynamic_cast<HatanakaDecoder*>(source_.get()) != nullptr;
  header_ = readRinexObsHeader(*source_);
  drainSourceProblems();
}

RinexObsReader RinexObsReader::open(const std::string& path) {
  return RinexObsReader(openObservationSource(path));
}

RinexObsReader::RinexObsReader(RinexObsReader&&) noexcept = default;
RinexObsReader& RinexObsReader::operator=(RinexObsReader&&) noexcept = default;
RinexObsReader::~RinexObsReader() = default;

void RinexObsReader::drainSourceProblems() {
  if (!compact_) return;
  auto* crx = static_cast<HatanakaDecoder*>(source_.get());
  for (auto& p : crx->takeProblems()) {
    report_.addProblem(p.line, "Compact RINEX line " + std::to_string(p.line) + ": " + p.reason);
  }
}

bool RinexObsReader::looksLikeEpochLine(const std::string& line) const {
  if (!header_.isRinex2()) return !line.empty() && line[0] == '>';
  // RINEX 2.11 table A2: 1X,I2.2,4(1X,I2),F11.7,2X,I1,I3 (time blank allowed for flags 2-5).
  if (line.size() < 29 || line[0] != ' ' || line[26] != ' ' || line[27] != ' ' || !isDigit(line[28])) {
    return false;
  }
  if (isBlank(column(line, 0, 26))) return line[28] >= '2' && line[28] <= '5';
  for (std::size_t p : {3u, 6u, 9u, 12u}) {
    if (line[p] != ' ') return false;
  }
  for (std::size_t p : {2u, 5u, 8u, 11u, 14u, 17u}) {
    if (!isDigit(line[p])) return false;
  }
  return line[18] == '.';
}

void RinexObsReader::resynchronise() {
  while (source_->next(line_)) {
    if (looksLikeEpochLine(line_)) {
      source_->unread(line_);
      return;
    }
  }
}

bool RinexObsReader::parseEpochLine(const std::string& line, EpochHeader& eh, std::string& reason) {
  eh.line = source_->lineNumber();
  const bool v2 = header_.isRinex2();
  if (!looksLikeEpochLine(line)) {
    reason = v2 ? "expected an epoch line" : "expected an epoch line starting with '>'";
    return false;
  }
  const std::size_t flag_col = v2 ? 28 : 31;
  if (flag_col >= line.size() || !isDigit(line[flag_col]) || line[flag_col] > '6') {
    reason = "bad epoch flag";
    return false;
  }
  eh.flag = line[flag_col] - '0';
  long long count = 0;
  const FieldStatus cs = parseInt(column(line, flag_col + 1, 3), count);
  if (cs == FieldStatus::Malformed || count < 0 || count > kMaxSatellitesPerEpoch) {
    reason = "bad satellite/record count '" + std::string(column(line, flag_col + 1, 3)) + "'";
    return false;
  }
  eh.count = static_cast<int>(count);
  // Time: RINEX 2 year I3 (2 digits, 80-99 -> 19xx), RINEX 3 I4.
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double s = 0;
  const std::size_t o = v2 ? 0 : 1;
  bool ok = v2 ? intField(line, 0, 3, y) : intField(line, 1, 5, y);
  ok = ok && intField(line, o + 3 + (v2 ? 0 : 2), 3, mo) && intField(line, o + 6 + (v2 ? 0 : 2), 3, d) &&
       intField(line, o + 9 + (v2 ? 0 : 2), 3, h) && intField(line, o + 12 + (v2 ? 0 : 2), 3, mi) &&
       parseDouble(column(line, v2 ? 15 : 18, 11), s) == FieldStatus::Ok;
  if (ok && v2) y += y < 80 ? 2000 : 1900;
  if (ok) {
    eh.calendar = CalendarTime{y, mo, d, h, mi, s};
    eh.time_valid = isValidDate(y, mo, d) && h >= 0 && h < 24 && mi >= 0 && mi < 60 && s >= 0 && s < 61;
  }
  if (!eh.time_valid && (eh.flag <= 1 || eh.flag == 6)) {
    reason = "bad epoch time";
    return false;
  }
  // Receiver clock offset: RINEX 2 F12.9 in columns 69-80, RINEX 3 F15.12 in 42-56.
  double clock = 0;
  const FieldStatus st = parseDouble(v2 ? column(line, 68, 12) : column(line, 41, 15), clock);
  if (st == FieldStatus::Malformed) {
    reason = "bad receiver clock offset";
    return false;
  }
  if (st == FieldStatus::Ok) eh.clock_s = clock;
  return true;
}

void RinexObsReader::skipSpecialRecords(const EpochHeader& eh) {
  // Event flags 2-5: `count` header-type lines follow (RINEX 3.05 table A3). New
  // observation types in a flag-4 record apply to the epochs that follow.
  ++special_records_;
  report_.count("special event records skipped");
  RinexObsHeader updated = header_;
  RinexObsHeaderParser parser(updated, source_->name());
  bool types_changed = false;
  try {
    for (int i = 0; i < eh.count; ++i) {
      if (!source_->next(line_)) break;
      if (looksLikeEpochLine(line_) && !header_.isRinex2()) {
        report_.addProblem(source_->lineNumber(), "special record shorter than its count");
        source_->unread(line_);
        return;
      }
      const std::string_view lab = trim(column(line_, 60, 20));
      if (lab == "SYS / # / OBS TYPES" || lab == "# / TYPES OF OBSERV") types_changed = true;
      if (eh.flag == 4) parser.line(line_, source_->lineNumber());
    }
    if (eh.flag == 4) {
      parser.finish(source_->lineNumber());
      if (types_changed) report_.count("observation types redefined by event records");
      header_ = std::move(updated);
    }
  } catch (const ParseError& e) {
    report_.addProblem(e.line(), "bad header line in special record: " + e.reason());
  }
}

bool RinexObsReader::readSatelliteList(EpochHeader& eh, std::string& reason) {
  // RINEX 2: 12 satellites per line in columns 33-68, continuation lines after.
  sats_.clear();
  std::string_view text = line_;
  for (int i = 0; i < eh.count; ++i) {
    if (i > 0 && i % 12 == 0) {
      if (!source_->next(line_)) {
        reason = "satellite list truncated";
        return false;
      }
      text = line_;
    }
    const std::string_view id = column(text, 32 + 3 * (i % 12), 3);
    auto sat = SatelliteId::parse(id);
    if (!sat) {
      reason = "bad satellite '" + std::string(id) + "' in epoch line";
      return false;
    }
    sats_.push_back(*sat);
  }
  return true;
}

void RinexObsReader::parseObservation(std::string_view f, Observation& obs, double scale) const {
  double v = 0;
  FieldStatus st = fastDecimal(column(f, 0, 14), v);
  if (st == FieldStatus::Malformed) st = parseDouble(column(f, 0, 14), v);
  if (st == FieldStatus::Ok) {
    obs.value = scale == 1.0 ? v : v / scale;
  } else {
    obs.value.reset();  // blank; a malformed value is reported by the caller
  }
  obs.lli = digitFlag(f, 14);
  obs.ssi = digitFlag(f, 15);
}

bool RinexObsReader::readRinex3Records(const EpochHeader& eh, ObsEpoch& epoch) {
  for (int i = 0; i < eh.count; ++i) {
    if (!source_->next(line_)) {
      report_.addProblem(eh.line, "epoch truncated at end of data (" + std::to_string(i) + " of " +
                                      std::to_string(eh.count) + " satellite records)");
      return false;
    }
    if (!line_.empty() && line_[0] == '>') {
      report_.addProblem(source_->lineNumber(), "epoch of line " + std::to_string(eh.line) + " has " +
                                                    std::to_string(i) + " satellite records, expected " +
                                                    std::to_string(eh.count));
      source_->unread(line_);
      return false;
    }
    const auto sat = SatelliteId::parse(column(line_, 0, 3));
    if (!sat) {
      report_.addProblem(source_->lineNumber(), "bad satellite '" + std::string(column(line_, 0, 3)) + "'");
      continue;
    }
    const int s = static_cast<int>(sat->system);
    const auto& types = header_.obs_types[s];
    if (types.empty()) {
      report_.addProblem(source_->lineNumber(), "satellite " + sat->toString() +
                                                    " of a system without observation types");
      continue;
    }
    const auto& scales = header_.scale_factors[s];
    SatelliteObservations so;
    so.satellite = *sat;
    so.first = static_cast<std::uint32_t>(epoch.observations.size());
    so.count = static_cast<std::uint32_t>(types.size());
    epoch.observations.resize(epoch.observations.size() + types.size());
    Observation* out = epoch.observations.data() + so.first;
    bool bad = false;
    for (std::size_t k = 0; k < types.size(); ++k) {
      out[k].code = types[k];
      const std::string_view f = column(line_, 3 + 16 * k, 16);
      parseObservation(f, out[k], scales[k]);
      bad = bad || (!out[k].value && !isBlank(column(f, 0, 14)));
    }
    if (bad) {
      report_.addProblem(source_->lineNumber(), "malformed observation value for " + sat->toString());
      epoch.observations.resize(so.first);
      continue;
    }
    epoch.satellites.push_back(so);
  }
  return true;
}

bool RinexObsReader::readRinex2Records(const EpochHeader& eh, ObsEpoch& epoch) {
  // RINEX 2.11 table A2: 5 observations (A14.3,I1,I1) per 80-column line.
  for (int i = 0; i < eh.count; ++i) {
    const SatelliteId sat = sats_[i];
    const int s = static_cast<int>(sat.system);
    const auto& types = header_.obs_types[s];
    const auto& scales = header_.scale_factors[s];
    SatelliteObservations so;
    so.satellite = sat;
    so.first = static_cast<std::uint32_t>(epoch.observations.size());
    so.count = static_cast<std::uint32_t>(types.size());
    epoch.observations.resize(epoch.observations.size() + types.size());
    bool bad = false;
    for (std::size_t k = 0; k < types.size(); ++k) {
      if (k % 5 == 0) {
        if (!source_->next(line_)) {
          report_.addProblem(eh.line, "epoch truncated at end of data");
          return false;
        }
        if (looksLikeEpochLine(line_)) {
          report_.addProblem(source_->lineNumber(), "epoch of line " + std::to_string(eh.line) +
                                                        " has fewer observation lines than expected");
          source_->unread(line_);
          return false;
        }
      }
      Observation& o = epoch.observations[so.first + k];
      o.code = types[k];
      const std::string_view f = column(line_, 16 * (k % 5), 16);
      parseObservation(f, o, scales[k]);
      bad = bad || (!o.value && !isBlank(column(f, 0, 14)));
    }
    if (bad) {
      report_.addProblem(source_->lineNumber(), "malformed observation value for " + sat.toString());
      epoch.observations.resize(so.first);
      continue;
    }
    epoch.satellites.push_back(so);
  }
  return true;
}

void RinexObsReader::checkOrder(const ObsEpoch& epoch) {
  if (epoch.flag == EpochFlag::CycleSlipRecords) return;
  if (last_time_) {
    if (epoch.time < *last_time_) {
      ++backwards_;
      report_.count("epochs going back in time");
    } else if (epoch.time == *last_time_) {
      ++duplicates_;
      report_.count("duplicate epochs");
    }
  }
  last_time_ = epoch.time;
}

bool RinexObsReader::next(ObsEpoch& epoch) {
  while (!ended_) {
    epoch.clear();
    if (!source_->next(line_)) {
      ended_ = true;
      break;
    }
    drainSourceProblems();
    if (isBlank(line_)) continue;
    EpochHeader eh;
    std::string reason;
    if (!parseEpochLine(line_, eh, reason)) {
      report_.addProblem(source_->lineNumber(), reason);
      resynchronise();
      continue;
    }
    if (eh.flag >= 2 && eh.flag <= 5) {
      skipSpecialRecords(eh);
      continue;
    }
    if (header_.isRinex2() && !readSatelliteList(eh, reason)) {
      report_.addProblem(eh.line, reason);
      resynchronise();
      continue;
    }
    const bool ok = header_.isRinex2() ? readRinex2Records(eh, epoch) : readRinex3Records(eh, epoch);
    if (!ok) continue;
    try {
      epoch.time = GnssTime::fromCalendar(eh.calendar, header_.epoch_time_system);
    } catch (const std::exception&) {
      report_.addProblem(eh.line, "bad epoch time");
      continue;
    }
    epoch.flag = static_cast<EpochFlag>(eh.flag);
    epoch.receiver_clock_offset_s = eh.clock_s;
    epoch.line = eh.line;
    if (epoch.flag == EpochFlag::PowerFailure) report_.count("power failure epochs (flag 1)");
    if (epoch.flag == EpochFlag::CycleSlipRecords) report_.count("cycle slip records (flag 6)");
    checkOrder(epoch);
    drainSourceProblems();
    return true;
  }
  drainSourceProblems();
  if (source_->streamError() && !stream_error_reported_) {
    stream_error_reported_ = true;
    report_.addProblem(source_->lineNumber(), *source_->streamError());
  }
  if (source_->overlongLines() > 0 && !report_.counters().count("overlong lines cut")) {
    report_.count("overlong lines cut", source_->overlongLines());
  }
  return false;
}

}  // namespace ppp
