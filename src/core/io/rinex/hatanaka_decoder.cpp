// Compact RINEX decoder (Hatanaka 2008, Bull. GSI 55; RNXCMP 4.1 documentation).
//
// Format summary, as implemented here:
// - Two CRINEX header lines ("CRINEX VERS   / TYPE" with 1.0 or 3.0, "CRINEX
//   PROG / DATE"), then the RINEX header lines unchanged.
// - Per epoch: the epoch line, text-differenced against the previous one (a blank
//   keeps the old character, '&' makes it a blank, any other character replaces
//   it); an initialised epoch line starts with '&' (CRINEX 1) or '>' (CRINEX 3)
//   and resets every data arc. The satellite list follows the epoch fields in the
//   same line (from column 33 / 42), never split. Event records (flags 2-6) are
//   initialised lines followed by their lines as they are in the RINEX file.
// - Then the receiver clock line: empty (no clock), "n&value" (arc of difference
//   order n initialised with the value) or the n-th difference; the value is the
//   clock in units of the last digit of the RINEX field (1e-9 s RINEX 2, 1e-12 s RINEX 3).
// - Then one line per satellite: one space-separated field per observation type
//   (empty when blank), each "n&value" or the difference, in units of 0.001; then,
//   after the last separator, the LLI/SSI characters of all types, text-differenced
//   like the epoch line against the satellite's previous flags.
// - CRINEX 3 lines starting with '&' outside an epoch are escape (comment) lines.
#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"

#include <algorithm>
#include <cstring>

#include "ppp_bayes_tree/io/fixed_width.h"

namespace ppp {

struct HatanakaDecoder::Series {
  std::int8_t arc_order = -1;  // -1: the field is blank
  std::int8_t count = 0;       // differences accumulated so far (saturates at arc_order)
  std::int64_t d[kMaxDifferenceOrder + 1] = {};  // d[j]: latest j-th difference; d[0] is the value

  /// Adds the next input (the `count`-th difference while the arc builds up, then
  /// the arc_order-th). False on 64-bit overflow.
  bool push(std::int64_t v) {
    const int k = std::min<int>(count, arc_order);
    d[k] = v;
    for (int j = k - 1; j >= 0; --j) {
      if (__builtin_add_overflow(d[j], d[j + 1], &d[j])) return false;
    }
    if (count < arc_order) ++count;
    return true;
  }
};

struct HatanakaDecoder::SatState {
  char id[3] = {' ', ' ', ' '};
  int ntype = 0;
  std::vector<Series> series;
  std::string flags;  // 2 * ntype characters: LLI, SSI per type
};

namespace {

void chopBlanks(std::string& s) {
  std::size_t n = s.size();
  while (n > 0 && s[n - 1] == ' ') --n;
  s.resize(n);
}

/// Text-difference repair (used for the epoch line and the flags).
void repair(std::string& old_text, std::string_view diff) {
  if (old_text.size() < diff.size()) old_text.resize(diff.size(), ' ');
  for (std::size_t i = 0; i < diff.size(); ++i) {
    const char c = diff[i];
    if (c == ' ') continue;
    old_text[i] = c == '&' ? ' ' : c;
  }
}

/// [-]digits, 1..18 digits, nothing else.
bool parseInteger(std::string_view s, std::int64_t& out) {
  bool negative = false;
  std::size_t i = 0;
  if (!s.empty() && s[0] == '-') {
    negative = true;
    i = 1;
  }
  if (i == s.size() || s.size() - i > 18) return false;
  std::int64_t v = 0;
  for (; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    v = v * 10 + (s[i] - '0');
  }
  out = negative ? -v : v;
  return true;
}

/// Parses "n&value" (initialisation, order n) or "value". `order` = -1 when not init.
bool parseToken(std::string_view s, int& order, std::int64_t& value) {
  order = -1;
  if (s.size() >= 2 && s[1] == '&') {
    if (s[0] < '0' || s[0] > '9') return false;
    order = s[0] - '0';
    s.remove_prefix(2);
  }
  return parseInteger(s, value);
}

/// Writes |y| / 10^decimals right-aligned in `width` characters, as CRX2RNX does:
/// the integer part is left out when it is zero (".123", "-.123"). False when
/// the number does not fit.
bool formatFixed(std::int64_t y, int decimals, int width, char* out) {
  std::memset(out, ' ', width);
  const bool negative = y < 0;
  std::uint64_t a = negative ? 0 - static_cast<std::uint64_t>(y) : static_cast<std::uint64_t>(y);
  int pos = width - 1;
  for (int i = 0; i < decimals; ++i, --pos) {
    out[pos] = static_cast<char>('0' + a % 10);
    a /= 10;
  }
  out[pos--] = '.';
  while (a > 0) {
    if (pos < 0) return false;
    out[pos--] = static_cast<char>('0' + a % 10);
    a /= 10;
  }
  if (negative) {
    if (pos < 0) return false;
    out[pos] = '-';
  }
  return true;
}

bool isDigit(char c) { return c >= '0' && c <= '9'; }

int smallInt(std::string_view s, int fallback) {
  long long v = 0;
  if (parseInt(s, v) != FieldStatus::Ok || v < 0 || v > 100000) return fallback;
  return static_cast<int>(v);
}

}  // namespace

bool isCompactRinexFirstLine(std::string_view line) {
  return line.find("COMPACT RINEX FORMAT") != std::string_view::npos ||
         line.find("CRINEX VERS") != std::string_view::npos;
}

HatanakaDecoder::HatanakaDecoder(std::unique_ptr<LineSource> inner)
    : LineSource(inner->name()), inner_(std::move(inner)), ntype_by_letter_(256, -1),
      clock_(std::make_unique<Series>()) {
  std::string line;
  if (!inner_->next(line) || !isCompactRinexFirstLine(line)) {
    throw ParseError(name(), inner_->lineNumber(), "not a Compact RINEX file");
  }
  const std::string_view version = trim(column(line, 0, 20));
  if (version.substr(0, 3) == "1.0") {
    crinex_major_ = 1;
  } else if (version.substr(0, 3) == "3.0") {
    crinex_major_ = 3;
  } else {
    throw ParseError(name(), inner_->lineNumber(),
                     "unsupported Compact RINEX version '" + std::string(version) + "'");
  }
  if (!inner_->next(line) || trim(column(line, 60, 20)) != "CRINEX PROG / DATE") {
    throw ParseError(name(), inner_->lineNumber(), "missing CRINEX PROG / DATE line");
  }
  if (!inner_->next(line) || trim(column(line, 60, 20)) != "RINEX VERSION / TYPE" ||
      column(line, 5, 1).empty() || line[5] < '2' || line[5] > '4') {
    throw ParseError(name(), inner_->lineNumber(),
                     "Compact RINEX: third line is not a RINEX 2/3/4 VERSION / TYPE line");
  }
  rinex_major_ = line[5] - '0';
  chopBlanks(line);
  emit(line);
}

HatanakaDecoder::~HatanakaDecoder() = default;

std::vector<ParseProblem> HatanakaDecoder::takeProblems() {
  std::vector<ParseProblem> out;
  out.swap(problems_);
  return out;
}

void HatanakaDecoder::problem(const std::string& reason) {
  ++problem_count_;
  if (problems_.size() < ParseReport::kMaxStoredProblems) {
    problems_.push_back(ParseProblem{inner_->lineNumber(), reason});
  }
}

void HatanakaDecoder::emit(std::string_view line) {
  out_.append(line);
  out_.push_back('\n');
}

bool HatanakaDecoder::nextInner(std::string& line) {
  if (inner_->next(line)) return true;
  finished_ = true;
  if (inner_->streamError()) stream_error_ = inner_->streamError();
  return false;
}

std::size_t HatanakaDecoder::readBytes(char* buffer, std::size_t capacity) {
  while (out_pos_ >= out_.size() && !finished_) {
    out_.clear();
    out_pos_ = 0;
    decodeMore();
  }
  const std::size_t n = std::min(capacity, out_.size() - out_pos_);
  std::memcpy(buffer, out_.data() + out_pos_, n);
  out_pos_ += n;
  return n;
}

void HatanakaDecoder::decodeMore() {
  // Decode until a reasonable amount of text is waiting.
  while (!finished_ && out_.size() < 64 * 1024) {
    if (in_header_) {
      if (!nextInner(in_line_)) return;
      headerLine(in_line_);
    } else if (!dataEpoch()) {
      return;
    }
  }
}

void HatanakaDecoder::headerLine(std::string& line) {
  chopBlanks(line);
  emit(line);
  const std::string_view lab = trim(column(line, 60, 20));
  if (lab == "# / TYPES OF OBSERV" && !isBlank(column(line, 0, 6))) {
    const int n = smallInt(column(line, 0, 6), -1);
    rinex2_ntype_ = (n >= 0 && n <= kMaxTypesPerSystem) ? n : -1;
  } else if (lab == "SYS / # / OBS TYPES" && !line.empty() && line[0] != ' ') {
    const int n = smallInt(column(line, 3, 3), -1);
    ntype_by_letter_[static_cast<unsigned char>(line[0])] = (n >= 0 && n <= kMaxTypesPerSystem) ? n : -1;
  } else if (lab == "END OF HEADER") {
    in_header_ = false;
  }
}

bool HatanakaDecoder::eventRecord() {
  // in_line_ is an initialised epoch line with an event flag 2..6: emit it and
  // the records that follow as they are.
  const bool v2 = rinex_major_ == 2;
  in_line_[0] = v2 ? ' ' : '>';
  chopBlanks(in_line_);
  emit(in_line_);
  const std::size_t count_col = v2 ? 29 : 32;
  const int n = in_line_.size() > 29 ? smallInt(column(in_line_, count_col, 3), 0) : 0;
  for (int i = 0; i < n; ++i) {
    if (!nextInner(in_line_)) {
      problem("event record truncated at end of data");
      return false;
    }
    headerLine(in_line_);  // emits it, and notes new observation types (flag 4)
    in_header_ = false;
  }
  need_init_ = true;  // CRX2RNX: the epoch after an event is initialised
  return true;
}

bool HatanakaDecoder::dataEpoch() {
  if (!nextInner(in_line_)) return false;
  if (crinex_major_ == 3 && !in_line_.empty() && in_line_[0] == '&') return true;  // escape line
  if (!in_line_.empty() && in_line_[0] == '\x1a') {  // DOS end of file
    finished_ = true;
    return false;
  }
  const char init_mark = crinex_major_ == 1 ? '&' : '>';
  const bool init = !in_line_.empty() && in_line_[0] == init_mark;
  if (init) {
    const std::size_t flag_col = rinex_major_ == 2 ? 28 : 31;
    if (flag_col < in_line_.size() && isDigit(in_line_[flag_col]) && in_line_[flag_col] >= '2') {
      return eventRecord();
    }
    epoch_line_.clear();
    prev_.clear();
    *clock_ = Series{};
    need_init_ = false;
  } else if (need_init_) {
    return true;  // skipping to the next initialised epoch
  }
  if (!decodeEpoch(in_line_)) {
    need_init_ = true;
    return !finished_;
  }
  return true;
}

bool HatanakaDecoder::decodeEpoch(const std::string& diff_line) {
  // 1. The epoch line, restored from its difference to the previous one.
  const int nsat = restoreEpochLine(diff_line);
  if (nsat < 0) return false;
  // 2. The receiver clock offset line.
  bool has_clock = false;
  if (!decodeClock(has_clock)) return false;
  // 3. The epoch line(s) of the restored record.
  if (!writeEpochLines(nsat, has_clock)) return false;
  // 4. The satellite records.
  cur_.resize(static_cast<std::size_t>(nsat));
  for (int i = 0; i < nsat; ++i) {
    if (!decodeSatellite(i)) return false;
  }
  out_.append(epoch_out_);
  prev_.swap(cur_);
  return true;
}

int HatanakaDecoder::restoreEpochLine(const std::string& diff_line) {
  const bool v2 = rinex_major_ == 2;
  const std::size_t offset = v2 ? 3 : 6;
  const char top = v2 ? ' ' : '>';
  std::string_view diff = diff_line;
  if (!diff.empty() && diff[0] == (crinex_major_ == 1 ? '&' : '>')) {
    work_.assign(diff.begin(), diff.end());
    work_[0] = top;
    diff = work_;
  }
  repair(epoch_line_, diff);
  for (char& c : epoch_line_) {
    if (c == '&') c = ' ';
  }
  chopBlanks(epoch_line_);
  const std::string& line = epoch_line_;
  if (line.empty() || line[0] != top || line.size() < 26 + offset || line[offset + 23] != ' ' ||
      line[offset + 24] != ' ' || !isDigit(line[offset + 25])) {
    problem("bad epoch line; skipping to the next initialised epoch");
    return -1;
  }
  const int nsat = smallInt(column(line, v2 ? 29 : 32, 3), -1);
  if (nsat < 0 || nsat > kMaxSatellites || line.size() < listColumn() + 3 * static_cast<std::size_t>(nsat)) {
    problem("bad satellite count or list in epoch line");
    return -1;
  }
  return nsat;
}

std::size_t HatanakaDecoder::listColumn() const { return rinex_major_ == 2 ? 32 : 41; }

bool HatanakaDecoder::decodeClock(bool& has_clock) {
  std::string& clock_line = work_;
  if (!nextInner(clock_line)) {
    problem("epoch truncated at end of data");
    return false;
  }
  if (clock_line.empty()) {
    if (clock_->arc_order >= 0) clock_->count = 0;  // CRX2RNX: the next value restarts the arc at its order
    return true;
  }
  int order = -1;
  std::int64_t v = 0;
  if (!parseToken(clock_line, order, v)) {
    problem("bad receiver clock line '" + clock_line.substr(0, 40) + "'");
    return false;
  }
  if (order >= 0) {
    *clock_ = Series{};
    clock_->arc_order = static_cast<std::int8_t>(order);
  } else if (clock_->arc_order < 0) {
    problem("receiver clock difference without initialisation");
    return false;
  }
  if (!clock_->push(v)) {
    problem("receiver clock overflows 64 bits");
    return false;
  }
  has_clock = true;
  return true;
}

bool HatanakaDecoder::writeEpochLines(int nsat, bool has_clock) {
  const std::string& line = epoch_line_;
  const bool v2 = rinex_major_ == 2;
  // RINEX 2: the clock offset in F12.9 at column 69, the satellite list on
  // continuation lines of 12; RINEX 3: F15.12 at column 42.
  const std::size_t clock_col = v2 ? 68 : 41;
  const int decimals = v2 ? 9 : 12;
  const int width = v2 ? 12 : 15;
  epoch_out_.clear();
  epoch_out_.append(line, 0, std::min<std::size_t>(line.size(), clock_col));
  if (has_clock) {
    epoch_out_.resize(clock_col, ' ');
    char buf[15];
    if (!formatFixed(clock_->d[0], decimals, width, buf)) {
      problem(v2 ? "receiver clock offset out of the F12.9 range" : "receiver clock offset out of the F15.12 range");
      return false;
    }
    epoch_out_.append(buf, static_cast<std::size_t>(width));
  } else if (!v2) {
    chopBlanks(epoch_out_);
  }
  epoch_out_.push_back('\n');
  if (!v2) return true;
  for (int first = 12; first < nsat; first += 12) {
    epoch_out_.append(32, ' ');
    epoch_out_.append(line, listColumn() + 3 * first, 3 * std::min(12, nsat - first));
    epoch_out_.push_back('\n');
  }
  return true;
}

bool HatanakaDecoder::decodeSatellite(int i) {
  const char* id = epoch_line_.data() + listColumn() + 3 * i;
  SatState& sat = cur_[i];
  std::memcpy(sat.id, id, 3);
  sat.ntype = rinex_major_ == 2 ? rinex2_ntype_ : ntype_by_letter_[static_cast<unsigned char>(id[0])];
  if (sat.ntype < 0) {
    problem("satellite '" + std::string(id, 3) + "' of a system without observation types");
    return false;
  }
  const SatState* prev = previousState(i, sat);
  if (prev != nullptr) {
    sat.series.assign(prev->series.begin(), prev->series.end());
    sat.flags.assign(prev->flags);
  } else {
    sat.series.assign(static_cast<std::size_t>(sat.ntype), Series{});
    sat.flags.assign(2 * static_cast<std::size_t>(sat.ntype), ' ');
  }
  if (!nextInner(in_line_)) {
    problem("epoch truncated at end of data");
    return false;
  }
  return readSatelliteFields(sat, prev != nullptr) && writeSatelliteRecord(sat);
}

const HatanakaDecoder::SatState* HatanakaDecoder::previousState(int i, const SatState& sat) const {
  const SatState* prev = nullptr;
  if (static_cast<std::size_t>(i) < prev_.size() && std::memcmp(prev_[i].id, sat.id, 3) == 0) {
    prev = &prev_[i];
  } else {
    for (const SatState& p : prev_) {
      if (std::memcmp(p.id, sat.id, 3) == 0) {
        prev = &p;
        break;
      }
    }
  }
  if (prev != nullptr && prev->ntype != sat.ntype) prev = nullptr;
  return prev;
}

bool HatanakaDecoder::readSatelliteFields(SatState& sat, bool has_previous) {
  // Split the fields: ntype space-terminated fields, then the flags.
  const std::size_t nt = static_cast<std::size_t>(sat.ntype);
  std::string_view data = in_line_;
  std::size_t pos = 0;
  for (std::size_t j = 0; j < nt; ++j) {
    std::string_view token;
    if (pos <= data.size()) {
      std::size_t end = data.find(' ', pos);
      if (end == std::string_view::npos) end = data.size();
      token = data.substr(pos, end - pos);
      pos = end + 1;
    }
    Series& s = sat.series[j];
    if (token.empty()) {
      s.arc_order = -1;
      continue;
    }
    int order = -1;
    std::int64_t v = 0;
    if (!parseToken(token, order, v)) {
      problem("bad data field '" + std::string(token.substr(0, 30)) + "'");
      return false;
    }
    if (order >= 0) {
      s = Series{};
      s.arc_order = static_cast<std::int8_t>(order);
    } else if (!has_previous || s.arc_order < 0) {
      problem("difference without arc initialisation for " + std::string(sat.id, 3));
      return false;
    }
    if (!s.push(v)) {
      problem("data value overflows 64 bits");
      return false;
    }
  }
  const std::string_view dflags = pos < data.size() ? data.substr(pos) : std::string_view();
  for (std::size_t k = 0; k < dflags.size() && k < sat.flags.size(); ++k) {
    const char c = dflags[k];
    if (c != ' ') sat.flags[k] = c == '&' ? ' ' : c;
  }
  return true;
}

bool HatanakaDecoder::writeSatelliteRecord(SatState& sat) {
  // Restored record: RINEX 3 satellite + all fields; RINEX 2 five per line.
  const bool v2 = rinex_major_ == 2;
  const std::size_t nt = static_cast<std::size_t>(sat.ntype);
  std::size_t line_start = epoch_out_.size();
  if (!v2) epoch_out_.append(sat.id, 3);
  for (std::size_t j = 0; j < nt; ++j) {
    const Series& s = sat.series[j];
    char buf[16];
    if (s.arc_order >= 0) {
      if (!formatFixed(s.d[0], 3, 14, buf)) {
        problem("data value out of the F14.3 range");
        return false;
      }
    } else {
      std::memset(buf, ' ', 14);
      if (crinex_major_ == 1) sat.flags[2 * j] = sat.flags[2 * j + 1] = ' ';
    }
    buf[14] = sat.flags[2 * j];
    buf[15] = sat.flags[2 * j + 1];
    epoch_out_.append(buf, 16);
    if (j + 1 == nt || (v2 && (j + 1) % 5 == 0)) {
      std::size_t n = epoch_out_.size();
      while (n > line_start && epoch_out_[n - 1] == ' ') --n;
      epoch_out_.resize(n);
      epoch_out_.push_back('\n');
      line_start = epoch_out_.size();
    }
  }
  if (nt == 0) {
    chopBlanks(epoch_out_);
    epoch_out_.push_back('\n');
  }
  return true;
}

std::unique_ptr<LineSource> observationSource(std::unique_ptr<LineSource> source) {
  std::string first;
  if (!source->next(first)) return source;
  const bool crx = isCompactRinexFirstLine(first);
  source->unread(std::move(first));
  if (!crx) return source;
  return std::make_unique<HatanakaDecoder>(std::move(source));
}

std::unique_ptr<LineSource> openObservationSource(const std::string& path) {
  return observationSource(openLineSource(path));
}

}  // namespace ppp
