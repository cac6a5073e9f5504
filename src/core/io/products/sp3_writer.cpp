#include "ppp_bayes_tree/io/products/sp3_writer.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// Exponent n of base^n closest to `value` (SP3 record accuracy), blank when unknown.
std::string exponent(const std::optional<double>& value, double base, double unit, int width) {
  if (!value || !(base > 1.0) || !(*value > 0.0)) return std::string(width, ' ');
  const long n = std::lround(std::log(*value / unit) / std::log(base));
  if (n < 0 || n > (width == 2 ? 99 : 999)) return std::string(width, ' ');
  return format("%*ld", width, n);
}

/// SP3-c P-record columns 61-80: x, y, z exponents (base^n mm), clock exponent
/// (base^n ps), clock event / prediction and maneuver / orbit prediction flags.
std::string sigmaColumns(const Sp3Record& r, double position_base, double clock_base) {
  std::string c = " " + exponent(r.position_sigma_m[0], position_base, 1e-3, 2) + " " +
                  exponent(r.position_sigma_m[1], position_base, 1e-3, 2) + " " +
                  exponent(r.position_sigma_m[2], position_base, 1e-3, 2) + " " +
                  exponent(r.clock_sigma_s, clock_base, 1e-12, 3) + " ";
  c += r.clock_event ? 'E' : ' ';
  c += r.clock_predicted ? 'P' : ' ';
  c += "  ";
  c += r.maneuver ? 'M' : ' ';
  c += r.orbit_predicted ? 'P' : ' ';
  while (!c.empty() && c.back() == ' ') c.pop_back();
  return c;
}

}  // namespace

GpsSp3Summary gpsOnlySp3(const Sp3File& sp3) { return sp3Copy(sp3, {GnssSystem::GPS}); }

GpsSp3Summary sp3Copy(const Sp3File& sp3, const std::vector<GnssSystem>& systems) {
  const bool gps_only = systems.size() == 1 && systems.front() == GnssSystem::GPS;
  std::vector<SatelliteId> sats;
  for (const auto& [sat, records] : sp3.satellites)
    if (std::find(systems.begin(), systems.end(), sat.system) != systems.end() && !records.empty())
      sats.push_back(sat);
  // Epochs that hold at least one GPS record.
  std::map<GnssTime, std::vector<std::pair<SatelliteId, const Sp3Record*>>> epochs;
  for (const auto& sat : sats)
    for (const auto& r : sp3.satellites.at(sat)) epochs[r.time].emplace_back(sat, &r);

  GpsSp3Summary out;
  out.satellites = sats.size();
  out.epochs = epochs.size();
  if (epochs.empty()) return out;
  const GnssTime t0 = epochs.begin()->first;
  const auto c0 = t0.toCalendar(TimeSystem::GPS);
  const auto w0 = t0.gpsWeek();
  const double mjd = t0.mjd(TimeSystem::GPS);
  const double mjd_day = std::floor(mjd);
  auto pad = [](std::string s, std::size_t n) { return s.substr(0, n) + std::string(n - std::min(n, s.size()), ' '); };
  std::string& t = out.text;
  // SP3-c line 1 and 2 (Hilla 2010, "The Extended Standard Product 3 Orbit Format (SP3-c)").
  t += format("#c%c%4d %2d %2d %2d %2d %11.8f %7zu ", 'P', c0.year, c0.month, c0.day, c0.hour, c0.minute, c0.second,
              out.epochs);
  t += pad(sp3.header.data_used.empty() ? "ORBIT" : sp3.header.data_used, 5) + " " +
       pad(sp3.header.coordinate_system, 5) + " " + pad(sp3.header.orbit_type, 3) + " " + pad(sp3.header.agency, 4) +
       "\n";
  t += format("## %4d %15.8f %14.8f %5.0f %15.13f\n", w0.week, w0.seconds_of_week, sp3.header.interval_s, mjd_day,
              mjd - mjd_day);
  const std::size_t lines = std::max<std::size_t>(5, (sats.size() + 16) / 17);
  for (std::size_t l = 0; l < lines; ++l) {
    std::string ids;
    for (std::size_t k = 0; k < 17; ++k) {
      const std::size_t i = l * 17 + k;
      ids += i < sats.size() ? sats[i].toString() : "  0";
    }
    t += (l == 0 ? format("+   %2zu   ", sats.size()) : std::string("+        ")) + ids + "\n";
  }
  for (std::size_t l = 0; l < lines; ++l) {
    std::string acc;
    for (std::size_t k = 0; k < 17; ++k) acc += "  0";  // accuracy unknown
    t += "++       " + acc + "\n";
  }
  t += gps_only ? "%c G  cc GPS ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc\n"
                : "%c M  cc GPS ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc\n";
  t += "%c cc cc ccc ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc\n";
  // Floating-point bases of the record standard deviations, kept so that the
  // records' exponents (which RTKLIB turns into orbit/clock variances) mean the same.
  t += format("%%f %10.7f %12.9f  0.00000000000  0.000000000000000\n", sp3.header.position_base,
              sp3.header.clock_base);
  t += "%f  0.0000000  0.000000000  0.00000000000  0.000000000000000\n";
  t += "%i    0    0    0    0      0      0      0      0         0\n";
  t += "%i    0    0    0    0      0      0      0      0         0\n";
  t += gps_only ? "/* GPS-ONLY COPY WRITTEN BY PPP_RTKLIB_INPUTS (PPP_BAYES_TREE)\n"
                : "/* COPY WRITTEN BY PPP_BAYES_TREE\n";
  t += "/* FROM AN SP3 FILE READ BY OUR SP3 READER, TIMES IN GPST\n";
  t += "/*\n/*\n";
  for (const auto& [time, recs] : epochs) {
    const auto c = time.toCalendar(TimeSystem::GPS);
    t += format("*  %4d %2d %2d %2d %2d %11.8f\n", c.year, c.month, c.day, c.hour, c.minute, c.second);
    for (const auto& [sat, r] : recs) {
      const Eigen::Vector3d p_km = r->position_ecef_m ? Eigen::Vector3d(*r->position_ecef_m / 1000.0)
                                                      : Eigen::Vector3d::Zero();
      const double clk_us = r->clock_bias_s ? *r->clock_bias_s * 1e6 : 999999.999999;
      t += format("P%s%14.6f%14.6f%14.6f%14.6f", sat.toString().c_str(), p_km.x(), p_km.y(), p_km.z(), clk_us);
      t += sigmaColumns(*r, sp3.header.position_base, sp3.header.clock_base) + "\n";
    }
  }
  t += "EOF\n";
  return out;
}

}  // namespace ppp
