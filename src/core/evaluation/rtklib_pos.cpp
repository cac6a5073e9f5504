#include "ppp_bayes_tree/evaluation/rtklib_pos.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

constexpr double kSecondsPerWeek = 604800.0;

/// `time` rounded to `decimals` fractional digits of a second.
GnssTime roundTime(const GnssTime& time, int decimals) {
  const double scale = std::pow(10.0, decimals);
  const double fraction = std::round(time.fraction() * scale) / scale;
  return GnssTime::fromGpsSeconds(time.wholeSeconds(), fraction);
}

std::string formatTime(const GnssTime& time, const PosWriterOptions& o) {
  const int d = std::clamp(o.time_decimals, 0, 9);
  const GnssTime t = roundTime(time, d);
  if (o.time_form == PosTimeForm::WeekTow) {
    const auto w = t.gpsWeek();
    return format("%4d %*.*f", w.week, 6 + (d > 0 ? d + 1 : 0), d, w.seconds_of_week);
  }
  const auto c = t.toCalendar(TimeSystem::GPS);
  return format("%04d/%02d/%02d %02d:%02d:%0*.*f", c.year, c.month, c.day, c.hour, c.minute, d > 0 ? d + 3 : 2, d,
                c.second);
}

/// RTKLIB sqvar(): signed square root of a (co)variance.
double signedSqrt(double v) { return v < 0.0 ? -std::sqrt(-v) : std::sqrt(v); }

std::vector<std::string> splitBlanks(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream is(line);
  std::string tok;
  while (is >> tok && out.size() < 32) out.push_back(tok);
  return out;
}

bool number(const std::string& tok, double& v) {
  return parseDouble(tok, v) == FieldStatus::Ok && std::isfinite(v);
}

bool integer(const std::string& tok, int& v) {
  double d = 0.0;
  if (!number(tok, d) || d != std::floor(d) || std::abs(d) > 1e6) return false;
  v = static_cast<int>(d);
  return true;
}

/// Reads "yyyy/mm/dd" "hh:mm:ss.sss" in `system`; false when malformed.
bool parseCalendar(const std::string& date, const std::string& clock, TimeSystem system, double shift_s,
                   GnssTime& out) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double s = 0.0;
  char c1 = 0, c2 = 0, c3 = 0, c4 = 0;
  std::istringstream ds(date), cs(clock);
  if (!(ds >> y >> c1 >> mo >> c2 >> d) || c1 != '/' || c2 != '/' || !ds.eof()) return false;
  if (!(cs >> h >> c3 >> mi >> c4 >> s) || c3 != ':' || c4 != ':' || !cs.eof()) return false;
  if (y < 1980 || y > 2200 || h < 0 || h > 23 || mi < 0 || mi > 59 || !(s >= 0.0 && s < 61.0)) return false;
  if (!isValidDate(y, mo, d)) return false;
  out = GnssTime::fromCalendar(CalendarTime{y, mo, d, h, mi, s}, system) - shift_s;
  return true;
}

}  // namespace

namespace {
/// The ratio column: the AR ratio of a fixed epoch, capped at 999.9 as RTKLIB caps
/// it (rtkpos.c: MIN(s[1]/s[0], 999.9)) to keep the %6.1f column; 0 otherwise.
double posRatio(const SolutionEpoch& e) {
  if (e.status != SolutionStatus::PppFixed || !e.ambiguity_ratio || !std::isfinite(*e.ambiguity_ratio)) return 0.0;
  return std::min(*e.ambiguity_ratio, 999.9);
}
}  // namespace

std::string formatPosHeader(const PosWriterOptions& o) {
  std::string h = "% program   : " + o.program + "\n";
  for (const auto& c : o.comment_lines) h += "% " + c + "\n";
  h += "%\n% (x/y/z-ecef=WGS84,Q=1:fix,2:float,3:sbas,4:dgps,5:single,6:ppp,ns=# of satellites)\n";
  const int d = std::clamp(o.time_decimals, 0, 9);
  const int time_width = o.time_form == PosTimeForm::WeekTow ? 4 + 1 + 6 + (d > 0 ? d + 1 : 0)
                                                              : 19 + (d > 0 ? d + 1 : 0);
  h += format("%-*s", time_width, "%  GPST");
  h += format(" %14s %14s %14s %3s %3s", "x-ecef(m)", "y-ecef(m)", "z-ecef(m)", "Q", "ns");
  h += format(" %8s %8s %8s %8s %8s %8s %6s %6s\n", "sdx(m)", "sdy(m)", "sdz(m)", "sdxy(m)", "sdyz(m)", "sdzx(m)",
              "age(s)", "ratio");
  return h;
}

std::string formatPosRecord(const SolutionEpoch& e, const PosWriterOptions& o) {
  if (!e.position_ecef_m || !e.position_ecef_m->allFinite()) return {};
  const Eigen::Vector3d& p = *e.position_ecef_m;
  Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
  if (e.covariance_ecef_m2 && e.covariance_ecef_m2->allFinite()) q = *e.covariance_ecef_m2;
  return formatTime(e.time, o) +
         format(" %14.4f %14.4f %14.4f %3d %3d", p.x(), p.y(), p.z(), rtklibQuality(e.status), e.satellites_used) +
         format(" %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f %6.2f %6.1f\n", signedSqrt(q(0, 0)), signedSqrt(q(1, 1)),
                signedSqrt(q(2, 2)), signedSqrt(q(0, 1)), signedSqrt(q(1, 2)), signedSqrt(q(2, 0)), 0.0,
                posRatio(e));
}

RtklibPosWriter::RtklibPosWriter(std::ostream& out, PosWriterOptions options)
    : out_(out), options_(std::move(options)) {
  out_ << formatPosHeader(options_);
}

void RtklibPosWriter::write(const SolutionEpoch& epoch) { out_ << formatPosRecord(epoch, options_); }

PosFile readRtklibPos(LineSource& source) {
  PosFile file;
  file.report.setFile(source.name());
  std::optional<PosCoordinates> coordinates;
  double shift_s = 0.0;  // time-zone shift of the calendar times (JST = UTC + 9 h)
  std::string line;
  while (source.next(line)) {
    const std::size_t ln = source.lineNumber();
    if (isBlank(line)) continue;
    if (line[0] == '%') {
      if (file.header_lines.size() < 1000) file.header_lines.push_back(line.substr(0, 512));
      if (line.find("x-ecef(m)") != std::string::npos) coordinates = PosCoordinates::Xyz;
      if (line.find("latitude(") != std::string::npos) coordinates = PosCoordinates::Llh;
      if (line.find("-ecef(m)") != std::string::npos || line.find("latitude(") != std::string::npos) {
        const auto toks = splitBlanks(line);
        const std::string ts = toks.size() > 1 ? toks[1] : "";
        if (ts == "UTC") file.time_system = TimeSystem::UTC;
        else if (ts == "JST") file.time_system = TimeSystem::UTC, shift_s = 9 * 3600.0;
        else if (ts != "GPST") file.report.addProblem(ln, "unknown time system '" + ts + "', GPST assumed");
      }
      continue;
    }
    const auto toks = splitBlanks(line);
    PosRecord r;
    std::size_t k = 0;
    if (!toks.empty() && toks[0].find('/') != std::string::npos) {
      file.time_form = PosTimeForm::Calendar;
      if (toks.size() < 2 || !parseCalendar(toks[0], toks[1], file.time_system, shift_s, r.time)) {
        file.report.addProblem(ln, "malformed calendar time");
        continue;
      }
      k = 2;
    } else {
      file.time_form = PosTimeForm::WeekTow;
      int week = 0;
      double tow = 0.0;
      if (toks.size() < 2 || !integer(toks[0], week) || !number(toks[1], tow) || week < 0 || week > 100000 ||
          tow < 0.0 || tow >= kSecondsPerWeek + 1.0) {
        file.report.addProblem(ln, "malformed GPS week / time of week");
        continue;
      }
      r.time = GnssTime::fromGpsWeek(week, tow);
      k = 2;
    }
    double c[3];
    if (toks.size() < k + 3 || !number(toks[k], c[0]) || !number(toks[k + 1], c[1]) || !number(toks[k + 2], c[2])) {
      file.report.addProblem(ln, "malformed or missing coordinates");
      continue;
    }
    k += 3;
    if (!coordinates) coordinates = Eigen::Vector3d(c[0], c[1], c[2]).norm() > 1e5 ? PosCoordinates::Xyz
                                                                                     : PosCoordinates::Llh;
    if (*coordinates == PosCoordinates::Xyz) {
      r.position_ecef_m = Eigen::Vector3d(c[0], c[1], c[2]);
    } else {
      if (std::abs(c[0]) > 90.0 || std::abs(c[1]) > 360.0 || std::abs(c[2]) > 1e7) {
        file.report.addProblem(ln, "latitude/longitude/height out of range");
        continue;
      }
      r.position_ecef_m = geodeticToEcef(Geodetic{c[0] * kDegToRad, c[1] * kDegToRad, c[2]});
    }
    // Optional columns: Q ns sd x6 age ratio.
    if (toks.size() >= k + 2 && (!integer(toks[k], r.quality) || !integer(toks[k + 1], r.satellites))) {
      file.report.addProblem(ln, "malformed Q / ns");
      continue;
    }
    k += 2;
    if (toks.size() >= k + 6) {
      std::array<double, 6> sd{};
      bool ok = true;
      for (int i = 0; i < 6; ++i) ok = ok && number(toks[k + i], sd[i]);
      if (ok) r.sd_m = sd;
      k += 6;
    }
    double v = 0.0;
    if (toks.size() > k && number(toks[k], v)) r.age_s = v;
    if (toks.size() > k + 1 && number(toks[k + 1], v)) r.ratio = v;
    file.records.push_back(r);
  }
  file.coordinates = coordinates.value_or(PosCoordinates::Xyz);
  if (source.streamError()) file.report.addProblem(source.lineNumber(), *source.streamError());
  return file;
}

PosFile readRtklibPos(const std::string& path) {
  auto source = openLineSource(path);
  return readRtklibPos(*source);
}

std::vector<SolutionEpoch> toSolutionEpochs(const PosFile& file) {
  std::vector<SolutionEpoch> out;
  out.reserve(file.records.size());
  for (const auto& r : file.records) {
    SolutionEpoch e;
    e.time = r.time;
    e.position_ecef_m = r.position_ecef_m;
    e.satellites_used = r.satellites;
    e.status = r.quality == 1 ? SolutionStatus::PppFixed
               : r.quality == 5 ? SolutionStatus::Single
                                : SolutionStatus::PppFloat;
    if (e.status == SolutionStatus::PppFixed && r.ratio) e.ambiguity_ratio = r.ratio;
    out.push_back(e);
  }
  return out;
}

}  // namespace ppp
