#include "ppp_bayes_tree/simulation/simulation_writers.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/io/data_file_name.h"
#include "ppp_bayes_tree/io/products/sp3_writer.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// RINEX header line: content in columns 1-60, label in 61-80.
std::string headerLine(const std::string& content, const char* label) {
  return format("%-60.60s%-20s\n", content.c_str(), label);
}

std::string headerTime(const CalendarTime& c) {
  return format("  %4d    %02d    %02d    %02d    %02d   %10.7f     GPS", c.year, c.month, c.day, c.hour, c.minute,
             c.second);
}

std::string sow(const GnssTime& t) { return format("%.3f", t.gpsWeek().seconds_of_week); }

}  // namespace

void writeRinexObs(std::ostream& out, const RinexObsHeader& h, const std::vector<ObsEpoch>& epochs) {
  out << headerLine(format("%9.2f           OBSERVATION DATA    %c: %s", 3.04, h.file_system,
                        h.file_system == 'M' ? "MIXED" : h.file_system == 'G' ? "GPS" : "GNSS"),
                    "RINEX VERSION / TYPE");
  out << headerLine(format("%-20.20s%-20.20s%-20.20s", h.program.c_str(), h.run_by.c_str(), h.date.c_str()),
                    "PGM / RUN BY / DATE");
  for (const auto& c : h.comments) out << headerLine(c, "COMMENT");
  out << headerLine(h.marker_name, "MARKER NAME");
  if (!h.marker_type.empty()) out << headerLine(h.marker_type, "MARKER TYPE");
  out << headerLine(format("%-20.20s%-40.40s", h.observer.c_str(), h.agency.c_str()), "OBSERVER / AGENCY");
  out << headerLine(format("%-20.20s%-20.20s%-20.20s", h.receiver_number.c_str(), h.receiver_type.c_str(),
                        h.receiver_version.c_str()),
                    "REC # / TYPE / VERS");
  out << headerLine(format("%-20.20s%-16.16s%-4.4s", h.antenna_number.c_str(), h.antenna_type.c_str(),
                        h.radomeOrNone().c_str()),
                    "ANT # / TYPE");
  const Eigen::Vector3d p = h.approx_position_ecef_m.value_or(Eigen::Vector3d::Zero());
  out << headerLine(format("%14.4f%14.4f%14.4f", p.x(), p.y(), p.z()), "APPROX POSITION XYZ");
  const Eigen::Vector3d d = h.antenna_delta_hen_m.value_or(Eigen::Vector3d::Zero());
  out << headerLine(format("%14.4f%14.4f%14.4f", d.x(), d.y(), d.z()), "ANTENNA: DELTA H/E/N");
  // SYS / # / OBS TYPES: A1,2X,I3,13(1X,A3), continuation lines 6X,13(1X,A3).
  for (int s = 0; s < kNumGnssSystems; ++s) {
    const auto& types = h.obs_types[static_cast<std::size_t>(s)];
    if (types.empty()) continue;
    std::string line = format("%c  %3zu", systemLetter(static_cast<GnssSystem>(s)), types.size());
    for (std::size_t i = 0; i < types.size(); ++i) {
      if (i > 0 && i % 13 == 0) {
        out << headerLine(line, "SYS / # / OBS TYPES");
        line = "      ";
      }
      line += " " + types[i].toString();
    }
    out << headerLine(line, "SYS / # / OBS TYPES");
  }
  if (h.interval_s) out << headerLine(format("%10.3f", *h.interval_s), "INTERVAL");
  if (h.time_of_first_obs) out << headerLine(headerTime(h.time_of_first_obs->calendar), "TIME OF FIRST OBS");
  if (h.time_of_last_obs) out << headerLine(headerTime(h.time_of_last_obs->calendar), "TIME OF LAST OBS");
  out << headerLine("", "END OF HEADER");

  std::string line;
  for (const auto& e : epochs) {
    const CalendarTime c = e.time.toCalendar(TimeSystem::GPS);
    out << format("> %4d %02d %02d %02d %02d%11.7f  %d%3zu\n", c.year, c.month, c.day, c.hour, c.minute, c.second,
               static_cast<int>(e.flag), e.satellites.size());
    for (std::size_t i = 0; i < e.satellites.size(); ++i) {
      line = e.satellites[i].satellite.toString();
      for (const Observation* o = e.begin(i); o != e.end(i); ++o) {
        if (o->value && std::abs(*o->value) < 1e10) {
          line += format("%14.3f", *o->value);
        } else {
          line += std::string(14, ' ');
        }
        line += o->lli ? static_cast<char>('0' + *o->lli % 10) : ' ';
        line += o->ssi ? static_cast<char>('0' + *o->ssi % 10) : ' ';
      }
      while (!line.empty() && line.back() == ' ') line.pop_back();
      out << line << '\n';
    }
  }
}

std::string rinexObsText(const RinexObsHeader& header, const std::vector<ObsEpoch>& epochs) {
  std::ostringstream os;
  writeRinexObs(os, header, epochs);
  return os.str();
}

std::string rinexClockText(const RinexClockFile& clocks) {
  const RinexClockHeader& h = clocks.header;
  std::string t;
  const std::string system(1, h.satellite_system == 'M' ? 'M' : 'G');  // GPS, or GPS+Galileo (mixed)
  t += headerLine(format("%9.2f           C                   ", 3.00) + system, "RINEX VERSION / TYPE");
  t += headerLine(format("%-20.20s%-20.20s%-20.20s", h.program.c_str(), h.run_by.c_str(), h.date.c_str()),
                  "PGM / RUN BY / DATE");
  t += headerLine("GPS", "TIME SYSTEM ID");
  t += headerLine("     1    AS", "# / TYPES OF DATA");
  t += headerLine(format("%-3.3s  %-55.55s", h.analysis_center_id.c_str(), h.analysis_center_name.c_str()),
                  "ANALYSIS CENTER");
  std::vector<SatelliteId> sats;
  for (const auto& [sat, recs] : clocks.satellite_clocks)
    if (!recs.empty()) sats.push_back(sat);
  t += headerLine(format("%6zu", sats.size()), "# OF SOLN SATS");
  for (std::size_t i = 0; i < sats.size(); i += 15) {
    std::string ids;
    for (std::size_t k = i; k < std::min(sats.size(), i + 15); ++k) ids += sats[k].toString() + " ";
    t += headerLine(ids, "PRN LIST");
  }
  t += headerLine("", "END OF HEADER");
  // Records in time order, satellites in PRN order within an epoch.
  std::map<GnssTime, std::vector<std::pair<SatelliteId, double>>> epochs;
  for (const auto& [sat, recs] : clocks.satellite_clocks)
    for (const auto& r : recs) epochs[r.time].emplace_back(sat, r.clock_bias_s);
  // "AS %-4.4s %4d %02d %02d %02d %02d %9.6f  1   %19.12E": the epoch's fields formatted once.
  for (const auto& [time, values] : epochs) {
    const CalendarTime c = time.toCalendar(TimeSystem::GPS);
    const std::string when = format("%4d %02d %02d %02d %02d %9.6f", c.year, c.month, c.day, c.hour, c.minute, c.second);
    for (const auto& [sat, v] : values)
      t += format("AS %-4.4s %s  1   %19.12E\n", sat.toString().c_str(), when.c_str(), v);
  }
  return t;
}

std::string sp3Text(const Sp3File& sp3) {
  std::vector<GnssSystem> systems;
  for (const auto& [sat, records] : sp3.satellites)
    if (std::find(systems.begin(), systems.end(), sat.system) == systems.end()) systems.push_back(sat.system);
  if (systems.empty()) systems.push_back(GnssSystem::GPS);
  return sp3Copy(sp3, systems).text;
}

void writeTruthEpochsCsv(std::ostream& out, const SimulatedFlight& f) {
  out << "time_gpst,gps_week,seconds_of_week,x_m,y_m,z_m,latitude_deg,longitude_deg,height_m,vx_mps,vy_mps,vz_mps,"
         "roll_deg,pitch_deg,yaw_deg,zwd_m,clock_m,satellites\n";
  for (const auto& e : f.truth) {
    const auto& s = e.trajectory;
    const Geodetic g = ecefToGeodetic(s.position_ecef_m);
    const auto w = s.time.gpsWeek();
    out << s.time.toString(TimeSystem::GPS, 3)
        << format(",%d,%.3f,%.4f,%.4f,%.4f,%.9f,%.9f,%.4f", w.week, w.seconds_of_week, s.position_ecef_m.x(),
               s.position_ecef_m.y(), s.position_ecef_m.z(), g.latitude_rad * kRadToDeg, g.longitude_rad * kRadToDeg,
               g.height_m)
        << format(",%.4f,%.4f,%.4f,%.4f,%.4f,%.4f", s.velocity_ecef_mps.x(), s.velocity_ecef_mps.y(),
               s.velocity_ecef_mps.z(), s.roll_rad * kRadToDeg, s.pitch_rad * kRadToDeg, s.yaw_rad * kRadToDeg)
        << format(",%.5f,%.4f,%zu\n", e.zwd_m, e.clock_m, e.signals.size());
  }
}

void writeTruthArcsCsv(std::ostream& out, const SimulatedFlight& f) {
  out << "seconds_of_week,satellite,arc,bias_if_m,n1_cycles,n2_cycles,elevation_deg,body_elevation_deg\n";
  for (const auto& e : f.truth) {
    const std::string t = sow(e.trajectory.time);
    for (const auto& s : e.signals) {
      const TruthArc& a = f.arcs[s.arc - 1];
      out << t << ',' << s.satellite.toString() << ',' << s.arc << format(",%.4f", a.bias_if_m) << ',' << a.n1_cycles << ','
          << a.n2_cycles << format(",%.3f,%.3f\n", s.elevation_rad * kRadToDeg, s.body_elevation_rad * kRadToDeg);
    }
  }
}

void writeArcListCsv(std::ostream& out, const SimulatedFlight& f) {
  out << "arc,satellite,first_sow,last_sow,epochs,n1_cycles,n2_cycles,bias_if_m,after_phase_break\n";
  for (const auto& a : f.arcs)
    out << a.id << ',' << a.satellite.toString() << ',' << sow(a.first_time) << ',' << sow(a.last_time) << ','
        << a.epochs << ',' << a.n1_cycles << ',' << a.n2_cycles << format(",%.4f,", a.bias_if_m)
        << (a.after_phase_break ? 1 : 0) << '\n';
}

void writeBreaksCsv(std::ostream& out, const SimulatedFlight& f) {
  out << "satellite,last_tracked_sow,reacquired_sow,previous_arc,new_arc,min_body_elevation_deg,max_roll_deg\n";
  for (const auto& b : f.breaks)
    out << b.satellite.toString() << ',' << sow(b.last_tracked) << ',' << sow(b.reacquired) << ',' << b.previous_arc
        << ',' << b.new_arc << format(",%.3f", b.min_body_elevation_rad * kRadToDeg)
        << format(",%.3f\n", b.max_roll_rad * kRadToDeg);
}

void writeImuCsv(std::ostream& out, const std::vector<ImuSample>& samples) {
  out << "# gps_week,seconds_of_week,fx,fy,fz,wx,wy,wz\n";
  for (const ImuSample& s : samples) {
    const GpsWeekTime w = s.time.gpsWeek();
    const Eigen::Vector3d& f = s.specific_force_mps2;
    const Eigen::Vector3d& r = s.angular_rate_radps;
    out << format("%d,%.9f,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", w.week, w.seconds_of_week, f.x(), f.y(), f.z(),
                  r.x(), r.y(), r.z());
  }
}

void writeImuBiasCsv(std::ostream& out, const SimulatedImu& imu) {
  out << "gps_week,seconds_of_week,ba_x,ba_y,ba_z,bg_x,bg_y,bg_z\n";
  for (std::size_t k = 0; k < imu.samples.size() && k < imu.biases.size(); ++k) {
    const GpsWeekTime w = imu.samples[k].time.gpsWeek();
    const Eigen::Vector3d& a = imu.biases[k].accel_mps2;
    const Eigen::Vector3d& g = imu.biases[k].gyro_radps;
    out << format("%d,%.9f,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", w.week, w.seconds_of_week, a.x(), a.y(), a.z(),
                  g.x(), g.y(), g.z());
  }
}

std::vector<std::string> writeSimulatedFlight(const SimulatedFlight& f, const std::string& directory) {
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  if (ec) throw std::runtime_error("cannot create directory " + directory + ": " + ec.message());
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const auto& body) {
    const std::string path = (std::filesystem::path(directory) / name).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + path);
    body(out);
    out.flush();
    if (!out) throw std::runtime_error("write error on " + path);
    written.push_back(path);
  };
  write(dataFileName(f.config.marker_name) + ".obs", [&](std::ostream& o) { writeRinexObs(o, f.header, f.epochs); });
  write("products.sp3", [&](std::ostream& o) { o << f.products_sp3_text; });
  write("products.clk", [&](std::ostream& o) { o << f.products_clk_text; });
  write("truth.sp3", [&](std::ostream& o) { o << f.truth_sp3_text; });
  write("truth.clk", [&](std::ostream& o) { o << f.truth_clk_text; });
  write("truth.csv", [&](std::ostream& o) { writeTruthEpochsCsv(o, f); });
  write("truth_arcs.csv", [&](std::ostream& o) { writeTruthArcsCsv(o, f); });
  write("arcs.csv", [&](std::ostream& o) { writeArcListCsv(o, f); });
  write("breaks.csv", [&](std::ostream& o) { writeBreaksCsv(o, f); });
  write("parameters.txt", [&](std::ostream& o) {
    o << "seed " << f.seed << "\n";
    for (const auto& l : f.drawn.describe()) o << l << "\n";
    o << "epochs " << f.epochs.size() << ", arcs " << f.arcs.size() << ", phase breaks " << f.breaks.size() << "\n";
  });
  if (!f.imu.samples.empty()) {
    write("imu.csv", [&](std::ostream& o) { writeImuCsv(o, f.imu.samples); });
    write("imu_bias.csv", [&](std::ostream& o) { writeImuBiasCsv(o, f.imu); });
  }
  return written;
}

}  // namespace ppp
