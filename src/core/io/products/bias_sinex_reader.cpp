// Bias-SINEX 1.00 reader. Column positions (0-based here) follow the format's
// BIAS/SOLUTION record: BIAS 1-4, SVN 6-9, PRN 11-13, STATION 15-23, OBS1 25-28,
// OBS2 30-33, BIAS_START 35-48, BIAS_END 50-63, UNIT 65-68, VALUE 70-90,
// STD_DEV 92-102 (the spec's 1-based columns minus one).
#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/io/bias_bounds.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

std::string_view biasTypeName(BiasType type) {
  switch (type) {
    case BiasType::OSB: return "OSB";
    case BiasType::DSB: return "DSB";
    case BiasType::ISB: return "ISB";
  }
  return "?";
}

namespace {

/// "YYYY:DDD:SSSSS" before conversion; `open` for 0000:000:00000 or blank.
struct RawEpoch {
  bool open = true;
  int year = 0, doy = 0;
  long long sod = 0;
};

std::vector<std::string_view> tokens(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

bool allDigits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

int daysInYear(int y) { return (y % 4 == 0 && (y % 100 != 0 || y % 400 == 0)) ? 366 : 365; }

/// Parses "YYYY:DDD:SSSSS" (or the SINEX 2-digit "YY:DDD:SSSSS"); nullopt when malformed.
std::optional<RawEpoch> parseRawEpoch(std::string_view text) {
  text = trim(text);
  if (text.empty()) return RawEpoch{};
  const std::size_t c1 = text.find(':');
  const std::size_t c2 = c1 == std::string_view::npos ? c1 : text.find(':', c1 + 1);
  if (c2 == std::string_view::npos) return std::nullopt;
  const auto y = text.substr(0, c1), d = text.substr(c1 + 1, c2 - c1 - 1), s = text.substr(c2 + 1);
  if (!allDigits(y) || !allDigits(d) || !allDigits(s) || (y.size() != 4 && y.size() != 2) || d.size() != 3 ||
      s.size() != 5) {
    return std::nullopt;
  }
  RawEpoch e;
  e.year = static_cast<int>(*toInt(y));
  e.doy = static_cast<int>(*toInt(d));
  e.sod = *toInt(s);
  if (e.year == 0 && e.doy == 0 && e.sod == 0) return RawEpoch{};  // open bound
  if (y.size() == 2) e.year += e.year <= 50 ? 2000 : 1900;
  if (e.year < 1980 || e.year > 2200 || e.doy < 1 || e.doy > daysInYear(e.year) || e.sod > 86400) {
    return std::nullopt;
  }
  e.open = false;
  return e;
}

std::optional<GnssTime> toTime(const RawEpoch& e, TimeSystem system) {
  if (e.open) return std::nullopt;
  // Day of year -> calendar date (through GPST, which has no leap seconds), then
  // midnight of that date read in `system`, plus the seconds of day.
  CalendarTime jan1;
  jan1.year = e.year;
  const CalendarTime date =
      (GnssTime::fromCalendar(jan1, TimeSystem::GPS) + static_cast<double>(e.doy - 1) * 86400.0).toCalendar();
  CalendarTime midnight;
  midnight.year = date.year;
  midnight.month = date.month;
  midnight.day = date.day;
  return GnssTime::fromCalendar(midnight, system) + static_cast<double>(e.sod);
}

std::optional<TimeSystem> parseBiasTimeSystem(std::string_view code) {
  code = trim(code);
  if (code.size() == 1) {
    switch (code[0]) {
      case 'G': return TimeSystem::GPS;
      case 'E': return TimeSystem::Galileo;
      case 'C': return TimeSystem::BeiDou;
      case 'J': return TimeSystem::QZSS;
      case 'R': return TimeSystem::GLONASS;
      default: return std::nullopt;
    }
  }
  return parseTimeSystem(code);
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

class BiasSinexParser {
 public:
  BiasSinexParser(LineSource& src, BiasSinexFile& out, const RecordFilter& filter)
      : src_(src), out_(out), filter_(filter) {}
  void run();

 private:
  [[noreturn]] void headerError(const std::string& reason) const {
    throw ParseError(src_.name(), src_.lineNumber(), reason);
  }
  void readHeaderLine();
  void readDescriptionLine(const std::string& line);
  void readSolutionLine(const std::string& line);
  void finish();
  void dropConflictingDuplicates();

  LineSource& src_;
  BiasSinexFile& out_;
  RecordFilter filter_;
  std::size_t other_system_rows_ = 0;  // skipped by the filter (counted, not parsed)
  RawEpoch creation_, start_, end_;
  std::vector<std::pair<RawEpoch, RawEpoch>> raw_epochs_;  // parallel to out_.records
};

void BiasSinexParser::readHeaderLine() {
  std::string line;
  if (!src_.next(line)) headerError("empty file: no %=BIA header line");
  if (line.rfind("%=BIA", 0) != 0) headerError("first line does not start with %=BIA");
  const auto t = tokens(line);
  if (t.size() < 9) headerError("%=BIA header line has " + std::to_string(t.size()) + " fields, expected 9");
  double version = 0.0;
  if (parseDouble(t[1], version) != FieldStatus::Ok || version < 0.0 || version >= 2.0) {
    headerError("unsupported Bias-SINEX version '" + std::string(t[1]) + "'");
  }
  out_.header.version = std::string(t[1]);
  out_.header.file_agency = std::string(t[2]);
  out_.header.data_agency = std::string(t[4]);
  const auto c = parseRawEpoch(t[3]), s = parseRawEpoch(t[5]), e = parseRawEpoch(t[6]);
  if (!c || !s || !e) headerError("malformed epoch in %=BIA header line");
  creation_ = *c;
  start_ = *s;
  end_ = *e;
  if (t[7] != "A" && t[7] != "R") headerError("bias mode must be A or R, found '" + std::string(t[7]) + "'");
  out_.header.bias_mode = t[7][0];
  long long n = 0;
  if (parseInt(t[8], n) != FieldStatus::Ok || n < 0) headerError("malformed number of estimates");
  out_.header.estimate_count = static_cast<std::size_t>(n);
}

void BiasSinexParser::readDescriptionLine(const std::string& line) {
  const auto t = tokens(line);
  if (t.empty()) return;
  const std::string_view key = t[0];
  const auto requireValue = [&]() {
    if (t.size() < 2) headerError("BIAS/DESCRIPTION " + std::string(key) + " without value");
  };
  const auto seconds = [&]() -> double {
    requireValue();
    double v = 0.0;
    if (parseDouble(t[1], v) != FieldStatus::Ok || v < 0.0) {
      headerError("BIAS/DESCRIPTION " + std::string(key) + ": malformed value '" + std::string(t[1]) + "'");
    }
    return v;
  };
  BiasDescription& d = out_.description;
  if (key == "OBSERVATION_SAMPLING") {
    d.observation_sampling_s = seconds();
  } else if (key == "PARAMETER_SPACING") {
    d.parameter_spacing_s = seconds();
  } else if (key == "DETERMINATION_METHOD") {
    requireValue();
    d.determination_method = std::string(t[1]);
  } else if (key == "BIAS_MODE") {
    requireValue();
    if (t[1] != "ABSOLUTE" && t[1] != "RELATIVE") {
      headerError("BIAS_MODE must be ABSOLUTE or RELATIVE, found '" + std::string(t[1]) + "'");
    }
    d.bias_mode = std::string(t[1]);
  } else if (key == "TIME_SYSTEM") {
    requireValue();
    d.time_system = parseBiasTimeSystem(t[1]);
    if (!d.time_system) headerError("unknown TIME_SYSTEM '" + std::string(t[1]) + "'");
  } else if (key == "APC_MODEL") {
    requireValue();
    d.apc_model = std::string(t[1]);
  } else if (key == "RECEIVER_CLOCK_REFERENCE_GNSS") {
    requireValue();
    d.receiver_clock_reference_gnss = std::string(t[1]);
  } else if (key == "SATELLITE_CLOCK_REFERENCE_OBSERVABLES") {
    requireValue();
    const auto sys = t[1].size() == 1 ? systemFromLetter(t[1][0]) : std::nullopt;
    if (!sys) headerError("SATELLITE_CLOCK_REFERENCE_OBSERVABLES: unknown system '" + std::string(t[1]) + "'");
    auto& list = d.satellite_clock_reference_observables[*sys];
    for (std::size_t i = 2; i < t.size() && list.size() < 16; ++i) list.emplace_back(t[i]);
  } else {
    out_.report.count("unknown BIAS/DESCRIPTION keywords ignored");
  }
}

/// OBS1 and OBS2 of a solution row (an OSB has no OBS2, a DSB or ISB needs one);
/// the problem, "" when none.
std::string readObservationCodes(const std::string& line, std::string_view type, BiasRecord& r) {
  const auto obs1 = ObservationCode::parse(trim(column(line, 25, 4)));
  if (!obs1 || trim(column(line, 25, 4)).size() != 3) return "malformed OBS1";
  r.obs1 = *obs1;
  const std::string_view obs2_text = trim(column(line, 30, 4));
  if (!obs2_text.empty()) {
    r.obs2 = ObservationCode::parse(obs2_text);
    if (!r.obs2 || obs2_text.size() != 3) return "malformed OBS2";
  }
  if (r.type == BiasType::OSB && r.obs2) return "OSB row with an OBS2 code";
  if (r.type != BiasType::OSB && !r.obs2) return std::string(type) + " row without OBS2";
  return {};
}

void BiasSinexParser::readSolutionLine(const std::string& line) {
  const std::size_t n = src_.lineNumber();
  const auto problem = [&](const std::string& reason) { out_.report.addProblem(n, reason); };
  BiasRecord r;
  r.line = n;
  const std::string_view type = trim(column(line, 1, 4));
  if (type == "OSB") r.type = BiasType::OSB;
  else if (type == "DSB") r.type = BiasType::DSB;
  else if (type == "ISB") r.type = BiasType::ISB;
  else return problem("unknown bias type '" + std::string(type) + "'");
  r.svn = std::string(trim(column(line, 6, 4)));
  const std::string_view prn = trim(column(line, 11, 3));
  const auto sys = prn.empty() ? std::nullopt : systemFromLetter(prn[0]);
  if (!sys) return problem("malformed PRN field '" + std::string(prn) + "'");
  if (!filter_.keepsSystem(*sys)) {
    out_.report.count("rows of other systems skipped");
    ++other_system_rows_;
    return;
  }
  r.system = *sys;
  if (prn.size() > 1) {
    r.satellite = SatelliteId::parse(prn);
    if (!r.satellite || prn.size() != 3) return problem("malformed PRN '" + std::string(prn) + "'");
  }
  r.station = upper(trim(column(line, 15, 9)));
  if (!r.satellite && r.station.empty()) return problem("row names neither a satellite nor a station");
  if (const std::string why = readObservationCodes(line, type, r); !why.empty()) return problem(why);
  const auto start = parseRawEpoch(column(line, 35, 14));
  const auto end = parseRawEpoch(column(line, 50, 14));
  if (!start || !end) return problem("malformed BIAS_START or BIAS_END");
  const std::string_view unit = trim(column(line, 65, 4));
  if (unit == "ns") r.unit = BiasUnit::Nanoseconds;
  else if (unit == "cyc") r.unit = BiasUnit::Cycles;
  else return problem("unsupported unit '" + std::string(unit) + "'");
  if (parseDouble(column(line, 70, 21), r.value) != FieldStatus::Ok) return problem("malformed bias value");
  const BiasKind kind = r.obs1.type == ObservableType::CarrierPhase ? BiasKind::Phase : BiasKind::Code;
  if (const auto beyond = biasBeyondBound(kind, r.value, r.unit == BiasUnit::Cycles)) {
    ++out_.refused.beyond_bound;
    if (kind == BiasKind::Phase) out_.refused.countPhaseRow(n, *beyond + ": row not used");
    return problem(*beyond + ": row not used");
  }
  double sd = 0.0;
  switch (parseDouble(column(line, 92, 11), sd)) {
    case FieldStatus::Ok:
      if (sd < 0.0) return problem("negative standard deviation");
      r.std_dev = sd;
      break;
    case FieldStatus::Blank: break;
    case FieldStatus::Malformed: return problem("malformed standard deviation");
  }
  out_.records.push_back(std::move(r));
  raw_epochs_.emplace_back(*start, *end);
}

void BiasSinexParser::run() {
  readHeaderLine();
  std::string line, block;
  bool footer = false, saw_solution = false;
  while (src_.next(line)) {
    if (line.empty() || line[0] == '*') continue;
    if (line.rfind("%=ENDBIA", 0) == 0) {
      footer = true;
      break;
    }
    if (line[0] == '+') {
      if (!block.empty()) out_.report.addProblem(src_.lineNumber(), "block " + block + " not closed");
      block = std::string(trim(column(line, 1, 40)));
      saw_solution = saw_solution || block == "BIAS/SOLUTION";
      continue;
    }
    if (line[0] == '-') {
      if (trim(column(line, 1, 40)) != block) {
        out_.report.addProblem(src_.lineNumber(), "block end does not match +" + block);
      }
      block.clear();
      continue;
    }
    if (block == "BIAS/SOLUTION") {
      readSolutionLine(line);
    } else if (block == "BIAS/DESCRIPTION") {
      readDescriptionLine(line);
    } else if (block == "FILE/REFERENCE") {
      if (out_.reference.size() < 1000) {
        out_.reference.emplace_back(trim(column(line, 1, 18)), trim(column(line, 19, std::string::npos)));
      }
    } else if (!block.empty()) {
      out_.report.count("lines in other blocks ignored");
    } else if (!isBlank(line)) {
      out_.report.addProblem(src_.lineNumber(), "line outside any block ignored");
    }
  }
  if (src_.streamError()) out_.report.addProblem(src_.lineNumber(), "read stopped: " + *src_.streamError());
  if (src_.overlongLines() > 0)
    out_.report.addProblem(0, overlongLinesProblem(src_.overlongLines()));
  if (!block.empty()) out_.report.addProblem(src_.lineNumber(), "file ends inside block " + block);
  if (!footer) out_.report.addProblem(src_.lineNumber(), "no %=ENDBIA footer (file truncated?)");
  if (!saw_solution) out_.report.addProblem(src_.lineNumber(), "no BIAS/SOLUTION block");
  finish();
}

void BiasSinexParser::finish() {
  TimeSystem ts = TimeSystem::GPS;
  if (out_.description.time_system) ts = *out_.description.time_system;
  else out_.report.count("TIME_SYSTEM not given, GPS assumed");
  out_.header.creation_time = toTime(creation_, ts);
  out_.header.data_start = toTime(start_, ts);
  out_.header.data_end = toTime(end_, ts);
  for (std::size_t i = 0; i < out_.records.size(); ++i) {
    out_.records[i].start = toTime(raw_epochs_[i].first, ts);
    out_.records[i].end = toTime(raw_epochs_[i].second, ts);
  }
  // Drop rows whose end precedes their start (kept parallel: erase after reporting).
  std::vector<BiasRecord> kept;
  kept.reserve(out_.records.size());
  for (auto& r : out_.records) {
    if (r.start && r.end && *r.end < *r.start) {
      out_.report.addProblem(r.line, "BIAS_END before BIAS_START");
      continue;
    }
    kept.push_back(std::move(r));
  }
  out_.records = std::move(kept);
  const std::size_t read = out_.records.size() + other_system_rows_ + out_.refused.beyond_bound;
  dropConflictingDuplicates();
  if (out_.header.estimate_count != 0 && out_.header.estimate_count != read) {
    out_.report.addProblem(1, "header announces " + std::to_string(out_.header.estimate_count) +
                                  " estimates, " + std::to_string(read) + " read");
  }
  for (const auto& r : out_.records) out_.report.count(std::string(biasTypeName(r.type)) + " rows");
  out_.buildIndex();
}

/// Rows for the same owner, bias type, observables and validity: the same value
/// is a repeat (counted, the first row kept); different values conflict. Of
/// conflicting rows none is used (neither can be trusted over the other), each
/// reported naming the first row's line.
void BiasSinexParser::dropConflictingDuplicates() {
  using Bound = std::pair<bool, double>;  // (open, GPS seconds)
  const auto bound = [](const std::optional<GnssTime>& t) {
    return t ? Bound{false, t->toGpsSecondsDouble()} : Bound{true, 0.0};
  };
  using Slot = std::tuple<std::string, std::string, int, std::string, std::string, Bound, Bound>;
  std::map<Slot, std::vector<std::size_t>> rows;
  for (std::size_t i = 0; i < out_.records.size(); ++i) {
    const BiasRecord& r = out_.records[i];
    rows[Slot{r.satellite ? r.satellite->toString() : std::string(), r.station + "/" + systemLetter(r.system),
              static_cast<int>(r.type), r.obs1.toString(), r.obs2 ? r.obs2->toString() : std::string(),
              bound(r.start), bound(r.end)}]
        .push_back(i);
  }
  std::vector<bool> drop(out_.records.size(), false);
  for (const auto& [slot, indices] : rows) {
    if (indices.size() < 2) continue;
    const BiasRecord& first = out_.records[indices.front()];
    const bool conflict = std::any_of(indices.begin() + 1, indices.end(), [&](std::size_t i) {
      return out_.records[i].value != first.value || out_.records[i].unit != first.unit;
    });
    for (std::size_t k = 1; k < indices.size(); ++k) drop[indices[k]] = true;
    if (!conflict) {
      out_.report.count("repeated rows (same value) ignored", indices.size() - 1);
      continue;
    }
    drop[indices.front()] = true;
    const std::string what = std::string(biasTypeName(first.type)) + " " +
                             (first.satellite ? first.satellite->toString() : first.station) + " " +
                             first.obs1.toString();
    out_.refused.conflicting += indices.size();
    const bool phase = first.obs1.type == ObservableType::CarrierPhase;
    if (phase) out_.refused.phase_rows += 1;  // the first row; the others with their problem below
    for (std::size_t k = 1; k < indices.size(); ++k) {
      const BiasRecord& r = out_.records[indices[k]];
      std::ostringstream os;
      os << what << " conflicts with line " << first.line << " (same observable and validity, value " << r.value
         << " against " << first.value << "): neither row used";
      out_.report.addProblem(r.line, os.str());
      if (phase) out_.refused.countPhaseRow(r.line, os.str());
    }
  }
  std::vector<BiasRecord> kept;
  for (std::size_t i = 0; i < out_.records.size(); ++i)
    if (!drop[i]) kept.push_back(std::move(out_.records[i]));
  out_.records = std::move(kept);
}

BiasValue toValue(const BiasRecord& r) {
  BiasValue v;
  v.line = r.line;
  if (r.unit == BiasUnit::Nanoseconds) {
    constexpr double kNsToM = 1e-9 * kSpeedOfLight_mps;
    v.value = r.value * kNsToM;
    v.unit = BiasValueUnit::Metres;
    if (r.std_dev) v.std_dev = *r.std_dev * kNsToM;
  } else {
    v.value = r.value;
    v.unit = BiasValueUnit::Cycles;
    v.std_dev = r.std_dev;
  }
  return v;
}

}  // namespace

std::string BiasSinexFile::stationOwner(std::string_view station, GnssSystem system) {
  return upper(trim(station)) + "/" + systemLetter(system);
}

void BiasSinexFile::buildIndex() {
  index_.clear();
  for (std::size_t i = 0; i < records.size(); ++i) {
    const BiasRecord& r = records[i];
    const std::string owner = r.station.empty() ? satelliteOwner(*r.satellite) : stationOwner(r.station, r.system);
    index_[Key{owner, static_cast<int>(r.type), r.obs1.toString(), r.obs2 ? r.obs2->toString() : ""}].push_back(i);
  }
}

const BiasRecord* BiasSinexFile::find(const Key& key, const GnssTime& t) const {
  const auto it = index_.find(key);
  if (it == index_.end()) return nullptr;
  const BiasRecord* best = nullptr;
  for (std::size_t i : it->second) {
    const BiasRecord& r = records[i];
    if (!r.validAt(t)) continue;
    if (best == nullptr || (r.start && (!best->start || *best->start < *r.start))) best = &r;
  }
  return best;
}

std::optional<BiasValue> BiasSinexFile::osb(const SatelliteId& sat, const ObservationCode& code,
                                            const GnssTime& t) const {
  const BiasRecord* r = find(Key{satelliteOwner(sat), static_cast<int>(BiasType::OSB), code.toString(), ""}, t);
  if (r == nullptr) return std::nullopt;
  return toValue(*r);
}

std::optional<BiasValue> BiasSinexFile::dsb(const SatelliteId& sat, const ObservationCode& code1,
                                            const ObservationCode& code2, const GnssTime& t) const {
  const int dsb = static_cast<int>(BiasType::DSB);
  if (const BiasRecord* r = find(Key{satelliteOwner(sat), dsb, code1.toString(), code2.toString()}, t)) {
    return toValue(*r);
  }
  if (const BiasRecord* r = find(Key{satelliteOwner(sat), dsb, code2.toString(), code1.toString()}, t)) {
    BiasValue v = toValue(*r);
    v.value = -v.value;
    return v;
  }
  const auto b1 = osb(sat, code1, t), b2 = osb(sat, code2, t);
  if (!b1 || !b2 || b1->unit != b2->unit) return std::nullopt;
  BiasValue v;
  v.value = b1->value - b2->value;
  v.unit = b1->unit;
  v.derived_from_osb = true;
  v.line = b1->line;
  return v;
}

std::optional<BiasValue> BiasSinexFile::stationOsb(std::string_view station, GnssSystem system,
                                                   const ObservationCode& code, const GnssTime& t) const {
  const BiasRecord* r = find(Key{stationOwner(station, system), static_cast<int>(BiasType::OSB), code.toString(), ""}, t);
  if (r == nullptr) return std::nullopt;
  return toValue(*r);
}

std::vector<std::string> BiasSinexFile::stations() const {
  std::set<std::string> names;
  for (const auto& r : records) {
    if (!r.station.empty()) names.insert(r.station);
  }
  return {names.begin(), names.end()};
}

BiasSinexFile readBiasSinex(LineSource& source, const RecordFilter& filter) {
  BiasSinexFile out;
  out.report.setFile(source.name());
  BiasSinexParser(source, out, filter).run();
  return out;
}

BiasSinexFile readBiasSinexFile(const std::string& path, const RecordFilter& filter) {
  auto source = openLineSource(path);
  return readBiasSinex(*source, filter);
}

FileSummary summarizeBiasSinexFile(const std::string& path) {
  const BiasSinexFile f = readBiasSinexFile(path);
  FileSummary s;
  s.path = path;
  s.type = "Bias-SINEX";
  s.version = f.header.version;
  s.first_epoch = f.header.data_start;
  s.last_epoch = f.header.data_end;
  if (f.description.parameter_spacing_s) s.interval_s = f.description.parameter_spacing_s;
  s.epoch_count = f.records.size();
  s.count_label = "bias rows";
  s.interval_label = "parameter spacing";
  std::map<std::string, std::size_t> per_type;
  for (const auto& r : f.records) {
    if (r.satellite) s.satellites[r.system].insert(*r.satellite);
    s.signals[r.system].insert(r.obs1.toString());
    if (r.obs2) s.signals[r.system].insert(r.obs2->toString());
    ++per_type[std::string(biasTypeName(r.type)) + (r.station.empty() ? " satellite" : " station")];
  }
  s.facts.push_back("agency " + f.header.file_agency + ", data from " + f.header.data_agency + ", mode " +
                    f.header.bias_mode + (f.description.bias_mode.empty() ? "" : " (" + f.description.bias_mode + ")"));
  if (f.description.time_system) {
    s.facts.push_back("time system " + std::string(timeSystemCode(*f.description.time_system)));
  }
  if (f.description.observation_sampling_s) {
    s.facts.push_back("observation sampling " + std::to_string(static_cast<long long>(*f.description.observation_sampling_s)) + " s");
  }
  if (!f.description.apc_model.empty()) s.facts.push_back("APC model " + f.description.apc_model);
  for (const auto& [name, n] : per_type) s.facts.push_back(name + " biases: " + std::to_string(n));
  s.facts.push_back("stations: " + std::to_string(f.stations().size()));
  s.report = f.report;
  return s;
}

}  // namespace ppp
