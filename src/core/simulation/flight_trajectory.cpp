#include "ppp_bayes_tree/simulation/flight_trajectory.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kGravity_mps2 = 9.80665;  // standard gravity (CGPM 1901)
constexpr double kRampHalfWidth_s = 1.0;   // commands are smoothed by a 2-s moving average
constexpr double kIntegrationStep_s = 0.01;

/// Piecewise-constant commands of one segment: heading rate (clockwise
/// positive) and vertical speed.
struct Segment {
  double duration_s;
  double heading_rate_radps;
  double vertical_speed_mps;
};

struct ProfileDefinition {
  double speed_mps = 15.0;             // horizontal speed
  Eigen::Vector3d start_enu_m = Eigen::Vector3d::Zero();
  double start_heading_rad = 0.0;
  std::vector<Segment> segments;
  double height_oscillation_m = 0.0;   // added sinusoid (figure8)
  double height_period_s = 120.0;
};

void addTurn(std::vector<Segment>& s, double angle_rad, double radius_m, double speed_mps, double vz = 0.0) {
  const double rate = speed_mps / radius_m;
  s.push_back({std::abs(angle_rad) / rate, angle_rad > 0 ? rate : -rate, vz});
}
void addStraight(std::vector<Segment>& s, double length_m, double speed_mps, double vz = 0.0) {
  s.push_back({length_m / speed_mps, 0.0, vz});
}

double total(const std::vector<Segment>& s) {
  double t = 0.0;
  for (const auto& x : s) t += x.duration_s;
  return t;
}

/// Loiter: a circle of 250 m radius at 15 m/s around the origin, 100 m up.
ProfileDefinition loiterProfile(double needed_s) {
  ProfileDefinition p;
  p.speed_mps = 15.0;
  const double radius = 250.0;
  p.start_enu_m = {-radius, 0.0, 100.0};
  p.start_heading_rad = 0.0;  // north, turning right around the origin
  p.segments.push_back({needed_s, p.speed_mps / radius, 0.0});
  return p;
}

/// Survey: 800-m east-west legs 100 m apart at 15 m/s, blocks of ten legs north then south.
ProfileDefinition surveyProfile(double needed_s) {
  ProfileDefinition p;
  p.speed_mps = 15.0;
  const double leg = 800.0, spacing = 100.0;
  p.start_enu_m = {-400.0, -500.0, 120.0};
  p.start_heading_rad = 0.5 * kPi;  // east
  int block_sense = 1;              // +1: next leg to the north
  for (int k = 0; total(p.segments) < needed_s; ++k) {
    addStraight(p.segments, leg, p.speed_mps);
    if (k % 10 == 9) block_sense = -block_sense;
    const bool heading_east = k % 2 == 0;
    // Heading east, a left turn (negative rate) moves north; heading west, a right turn.
    const double sign = (heading_east ? -1.0 : 1.0) * block_sense;
    addTurn(p.segments, sign * kPi, 0.5 * spacing, p.speed_mps);
  }
  return p;
}

/// Figure8: 90-m circles right then left at 22 m/s, the height oscillating by 20 m.
ProfileDefinition figure8Profile(double needed_s) {
  ProfileDefinition p;
  p.speed_mps = 22.0;
  const double radius = 90.0;
  p.start_enu_m = {0.0, 0.0, 150.0};
  p.start_heading_rad = 0.0;
  p.height_oscillation_m = 20.0;
  p.height_period_s = 120.0;
  while (total(p.segments) < needed_s) {
    addTurn(p.segments, -2.0 * kPi, radius, p.speed_mps);
    addTurn(p.segments, 2.0 * kPi, radius, p.speed_mps);
  }
  return p;
}

/// Climb: a 3 m/s spiral climb, a cruise of straight legs and quarter turns, the spiral descent.
ProfileDefinition climbProfile(double duration_s) {
  ProfileDefinition p;
  p.speed_mps = 22.0;
  p.start_enu_m = {0.0, -400.0, 100.0};
  p.start_heading_rad = 0.5 * kPi;  // east, circling left around the origin
  const double climb_rate = 3.0, spiral_radius = 400.0;
  const double vertical_time = std::min(300.0, 0.25 * duration_s);  // 900 m at 3 m/s
  const double spiral_rate = -p.speed_mps / spiral_radius;
  p.segments.push_back({vertical_time, spiral_rate, climb_rate});
  const double cruise_end = duration_s + kRampHalfWidth_s - vertical_time;
  std::vector<Segment> cruise;
  const double turn_radius = 110.0;
  for (int k = 0; total(p.segments) + total(cruise) < cruise_end; ++k) {
    addStraight(cruise, k % 2 == 0 ? 3000.0 : 2000.0, p.speed_mps);
    addTurn(cruise, 0.5 * kPi, turn_radius, p.speed_mps);
  }
  // Cut the cruise so that the descent ends with the flight.
  double t = total(p.segments);
  for (const auto& s : cruise) {
    if (t >= cruise_end) break;
    p.segments.push_back({std::min(s.duration_s, cruise_end - t), s.heading_rate_radps, 0.0});
    t += p.segments.back().duration_s;
  }
  p.segments.push_back({vertical_time + 10.0, spiral_rate, -climb_rate});
  return p;
}

ProfileDefinition defineProfile(FlightProfile profile, double duration_s) {
  const double needed_s = duration_s + 4.0 * kRampHalfWidth_s + 10.0;
  switch (profile) {
    case FlightProfile::Loiter: return loiterProfile(needed_s);
    case FlightProfile::Survey: return surveyProfile(needed_s);
    case FlightProfile::Figure8: return figure8Profile(needed_s);
    case FlightProfile::Climb: return climbProfile(duration_s);
  }
  return ProfileDefinition{};
}

/// Commands smoothed by a moving average of width 2 * kRampHalfWidth_s:
/// linear ramps between segments, preserving the integral of each command.
class SmoothedCommands {
 public:
  explicit SmoothedCommands(const std::vector<Segment>& segments) {
    double t = 0.0, heading = 0.0, height = 0.0;
    for (const auto& s : segments) {
      start_.push_back(t);
      heading_integral_.push_back(heading);
      height_integral_.push_back(height);
      t += s.duration_s;
      heading += s.heading_rate_radps * s.duration_s;
      height += s.vertical_speed_mps * s.duration_s;
    }
    segments_ = segments;
  }
  /// Smoothed (heading rate, vertical speed) at time t.
  Eigen::Vector2d at(double t) const {
    return (integral(t + kRampHalfWidth_s) - integral(t - kRampHalfWidth_s)) / (2.0 * kRampHalfWidth_s);
  }

 private:
  Eigen::Vector2d integral(double t) const {
    if (t <= 0.0) return Eigen::Vector2d(segments_.front().heading_rate_radps, segments_.front().vertical_speed_mps) * t;
    auto it = std::upper_bound(start_.begin(), start_.end(), t);
    const std::size_t i = static_cast<std::size_t>(it - start_.begin()) - 1;
    const double dt = t - start_[i];
    return {heading_integral_[i] + segments_[i].heading_rate_radps * dt,
            height_integral_[i] + segments_[i].vertical_speed_mps * dt};
  }
  std::vector<Segment> segments_;
  std::vector<double> start_, heading_integral_, height_integral_;
};

double bankAngle_rad(double horizontal_speed_mps, double heading_rate_radps) {
  return std::atan(horizontal_speed_mps * heading_rate_radps / kGravity_mps2);
}

TrajectorySample makeSample(const GnssTime& t, const Eigen::Vector3d& enu, const Eigen::Vector3d& velocity_enu,
                            double heading_rate, const Eigen::Vector3d& origin_ecef,
                            const Eigen::Matrix3d& ecef_from_enu) {
  TrajectorySample s;
  s.time = t;
  s.position_ecef_m = enuToEcef(enu, origin_ecef);
  s.velocity_ecef_mps = ecef_from_enu * velocity_enu;
  const double vh = std::hypot(velocity_enu.x(), velocity_enu.y());
  s.yaw_rad = std::atan2(velocity_enu.x(), velocity_enu.y());
  if (s.yaw_rad < 0.0) s.yaw_rad += 2.0 * kPi;
  s.pitch_rad = std::atan2(velocity_enu.z(), vh);
  s.roll_rad = bankAngle_rad(vh, heading_rate);
  return s;
}

}  // namespace

const char* flightProfileName(FlightProfile profile) {
  switch (profile) {
    case FlightProfile::Loiter: return "loiter";
    case FlightProfile::Survey: return "survey";
    case FlightProfile::Figure8: return "figure8";
    case FlightProfile::Climb: return "climb";
  }
  return "?";
}

FlightProfile parseFlightProfile(const std::string& name) {
  for (FlightProfile p : {FlightProfile::Loiter, FlightProfile::Survey, FlightProfile::Figure8, FlightProfile::Climb})
    if (name == flightProfileName(p)) return p;
  throw std::invalid_argument("unknown flight profile '" + name + "' (loiter, survey, figure8, climb)");
}

Geodetic defaultSimulationOrigin() { return {46.877 * kDegToRad, 7.465 * kDegToRad, 950.0}; }

std::vector<TrajectorySample> generateTrajectory(const TrajectoryOptions& options) {
  if (!(options.rate_hz > 0.0) || !(options.duration_s > 0.0) || options.duration_s > 86400.0)
    throw std::invalid_argument("trajectory: rate and duration must be positive (duration <= 1 day)");
  const ProfileDefinition p = defineProfile(options.profile, options.duration_s);
  const SmoothedCommands commands(p.segments);
  const Eigen::Vector3d origin_ecef = geodeticToEcef(options.origin);
  const Eigen::Matrix3d ecef_from_enu =
      rotationEnuFromEcef(options.origin.latitude_rad, options.origin.longitude_rad).transpose();
  const double interval = 1.0 / options.rate_hz;
  const auto count = static_cast<std::size_t>(std::floor(options.duration_s * options.rate_hz + 1e-9)) + 1;
  const double omega_h = 2.0 * kPi / p.height_period_s;

  auto velocityEnu = [&](double t, double heading) {
    const Eigen::Vector2d c = commands.at(t);
    const double vz = c.y() + p.height_oscillation_m * omega_h * std::cos(omega_h * t);
    return Eigen::Vector3d(p.speed_mps * std::sin(heading), p.speed_mps * std::cos(heading), vz);
  };
  std::vector<TrajectorySample> out;
  out.reserve(count);
  Eigen::Vector3d enu = p.start_enu_m;
  double heading = p.start_heading_rad;
  double t = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const double t_sample = static_cast<double>(k) * interval;
    // Midpoint (RK2) integration of heading and position up to the sample time.
    while (t < t_sample - 1e-12) {
      const double h = std::min(kIntegrationStep_s, t_sample - t);
      const double heading_mid = heading + 0.5 * h * commands.at(t).x();
      const Eigen::Vector3d v_mid = velocityEnu(t + 0.5 * h, heading_mid);
      heading += h * commands.at(t + 0.5 * h).x();
      enu += h * v_mid;
      t += h;
    }
    out.push_back(makeSample(options.start + t_sample, enu, velocityEnu(t, heading), commands.at(t).x(), origin_ecef,
                             ecef_from_enu));
  }
  return out;
}

Eigen::Matrix3d bodyFromNed(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch),
               cy = std::cos(yaw), sy = std::sin(yaw);
  Eigen::Matrix3d rz, ry, rx;  // frame rotations (passive), Z-Y-X sequence
  rz << cy, sy, 0, -sy, cy, 0, 0, 0, 1;
  ry << cp, 0, -sp, 0, 1, 0, sp, 0, cp;
  rx << 1, 0, 0, 0, cr, sr, 0, -sr, cr;
  return rx * ry * rz;
}

double bodyElevation_rad(const TrajectorySample& sample, const Eigen::Vector3d& los_ecef) {
  const Geodetic g = ecefToGeodetic(sample.position_ecef_m);
  const Eigen::Vector3d enu = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad) * los_ecef;
  const Eigen::Vector3d ned(enu.y(), enu.x(), -enu.z());
  const Eigen::Vector3d body = bodyFromNed(sample.roll_rad, sample.pitch_rad, sample.yaw_rad) * ned;
  return std::asin(std::clamp(-body.z() / body.norm(), -1.0, 1.0));
}

// ---- CSV trajectories.

namespace {

/// One row of a trajectory CSV: time since the start [s], latitude and longitude
/// [deg], height [m], attitude [rad] (zero without attitude columns).
struct TrajectoryRow {
  double t, lat, lon, h, roll, pitch, yaw;
};

/// The header line of a trajectory CSV: the column of each name.
struct TrajectoryColumns {
  std::map<std::string, std::size_t> index;
  std::size_t count = 0;
  bool have_attitude = false;
};

TrajectoryColumns readTrajectoryHeader(const std::vector<std::string>& fields, const std::string& file,
                                       std::size_t line) {
  TrajectoryColumns c;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (c.index.count(fields[i])) throw ParseError(file, line, "column '" + fields[i] + "' repeated");
    c.index[fields[i]] = i;
  }
  for (const char* column : {"time_s", "latitude_deg", "longitude_deg", "height_m"})
    if (!c.index.count(column)) throw ParseError(file, line, std::string("header lacks column '") + column + "'");
  const int att = static_cast<int>(c.index.count("roll_deg") + c.index.count("pitch_deg") + c.index.count("yaw_deg"));
  if (att != 0 && att != 3) throw ParseError(file, line, "give all of roll_deg, pitch_deg, yaw_deg or none");
  static const std::set<std::string> known{"time_s",   "latitude_deg", "longitude_deg", "height_m",
                                           "roll_deg", "pitch_deg",    "yaw_deg"};
  for (const auto& entry : c.index)
    if (!known.count(entry.first)) throw ParseError(file, line, "unknown column '" + entry.first + "'");
  c.have_attitude = att == 3;
  c.count = fields.size();
  return c;
}

TrajectoryRow readTrajectoryRow(const std::vector<std::string>& fields, const TrajectoryColumns& c,
                                const std::string& file, std::size_t line) {
  if (fields.size() != c.count)
    throw ParseError(file, line, "expected " + std::to_string(c.count) + " fields, found " + std::to_string(fields.size()));
  auto value = [&](const char* name) {
    double v = 0.0;
    if (parseDouble(fields[c.index.at(name)], v) != FieldStatus::Ok || !std::isfinite(v))
      throw ParseError(file, line, std::string("malformed ") + name + " '" + fields[c.index.at(name)] + "'");
    return v;
  };
  TrajectoryRow r{value("time_s"), value("latitude_deg"), value("longitude_deg"), value("height_m"), 0, 0, 0};
  if (std::abs(r.lat) > 90.0 || std::abs(r.lon) > 360.0 || std::abs(r.h) > 1.0e5 || std::abs(r.t) > 1.0e7)
    throw ParseError(file, line, "value out of range (|lat| <= 90, |lon| <= 360, |h| <= 100 km)");
  if (c.have_attitude) {
    r.roll = value("roll_deg") * kDegToRad;
    r.pitch = value("pitch_deg") * kDegToRad;
    r.yaw = value("yaw_deg") * kDegToRad;
  }
  return r;
}

/// Samples of the rows: positions, central-difference velocities, and the given
/// attitude or the coordinated flight's.
std::vector<TrajectorySample> samplesOfRows(const std::vector<TrajectoryRow>& rows, bool have_attitude,
                                            const GnssTime& start) {
  std::vector<TrajectorySample> out(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    out[i].time = start + rows[i].t;
    out[i].position_ecef_m = geodeticToEcef({rows[i].lat * kDegToRad, rows[i].lon * kDegToRad, rows[i].h});
  }
  std::vector<double> heading(rows.size()), vh(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 == rows.size() ? i : i + 1;
    out[i].velocity_ecef_mps = (out[b].position_ecef_m - out[a].position_ecef_m) / (rows[b].t - rows[a].t);
    const Geodetic g{rows[i].lat * kDegToRad, rows[i].lon * kDegToRad, rows[i].h};
    const Eigen::Vector3d v = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad) * out[i].velocity_ecef_mps;
    vh[i] = std::hypot(v.x(), v.y());
    heading[i] = std::atan2(v.x(), v.y());
    out[i].pitch_rad = std::atan2(v.z(), vh[i]);
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (have_attitude) {
      out[i].roll_rad = rows[i].roll, out[i].pitch_rad = rows[i].pitch, out[i].yaw_rad = rows[i].yaw;
      continue;
    }
    const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 == rows.size() ? i : i + 1;
    double dpsi = std::remainder(heading[b] - heading[a], 2.0 * kPi);
    out[i].yaw_rad = heading[i] < 0 ? heading[i] + 2.0 * kPi : heading[i];
    out[i].roll_rad = vh[i] > 0.5 ? bankAngle_rad(vh[i], dpsi / (rows[b].t - rows[a].t)) : 0.0;
  }
  return out;
}

}  // namespace

std::vector<TrajectorySample> readTrajectoryCsv(LineSource& source, const GnssTime& start) {
  const std::string file = source.name();
  std::string line;
  TrajectoryColumns columns;
  std::vector<TrajectoryRow> rows;
  constexpr std::size_t kMaxRows = 10'000'000;
  while (source.next(line)) {
    if (isBlank(line) || trim(line).front() == '#') continue;
    const auto fields = splitCsvFields(line);
    if (columns.index.empty()) {
      columns = readTrajectoryHeader(fields, file, source.lineNumber());
      continue;
    }
    const TrajectoryRow r = readTrajectoryRow(fields, columns, file, source.lineNumber());
    if (!rows.empty() && !(r.t > rows.back().t))
      throw ParseError(file, source.lineNumber(), "time_s not strictly increasing");
    if (rows.size() >= kMaxRows) throw ParseError(file, source.lineNumber(), "more than 10^7 rows");
    rows.push_back(r);
  }
  if (source.streamError()) throw ParseError(file, source.lineNumber(), "corrupt or truncated compressed stream");
  if (columns.index.empty()) throw ParseError(file, source.lineNumber(), "no header line");
  if (rows.size() < 2) throw ParseError(file, source.lineNumber(), "fewer than two trajectory rows");
  return samplesOfRows(rows, columns.have_attitude, start);
}

std::vector<TrajectorySample> readTrajectoryCsv(const std::string& path, const GnssTime& start) {
  auto src = openLineSource(path);
  return readTrajectoryCsv(*src, start);
}

}  // namespace ppp
