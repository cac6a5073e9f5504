#include "ppp_bayes_tree/io/products/rtklib_inputs.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// RINEX D19.12 field (Fortran "D" exponent written as "E", which RINEX 3 allows).
std::string d19(double v) { return format("%19.12E", v); }

std::string headerLine(const std::string& content, const char* label) {
  return format("%-60.60s%-20s\n", content.c_str(), label);
}

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

ClockNavigationSummary gpsNavigationFromClocks(const std::vector<const RinexClockFile*>& clocks) {
  // Samples per satellite, later files overriding equal epochs.
  std::map<SatelliteId, std::map<GnssTime, double>> samples;
  for (const auto* file : clocks)
    for (const auto& [sat, records] : file->satellite_clocks)
      if (sat.system == GnssSystem::GPS)
        for (const auto& r : records) samples[sat][r.time] = r.clock_bias_s;

  ClockNavigationSummary out;
  out.text = headerLine("     3.04           N: GNSS NAV DATA    G: GPS", "RINEX VERSION / TYPE");
  out.text += headerLine("ppp_rtklib_inputs   ppp_bayes_tree", "PGM / RUN BY / DATE");
  out.text += headerLine("clock terms from precise RINEX clocks; nominal orbits", "COMMENT");
  out.text += headerLine("", "END OF HEADER");
  for (const auto& [sat, series] : samples) {
    if (series.size() < 2) continue;
    const std::int64_t first_hour = series.begin()->first.wholeSeconds() / 3600;
    const std::int64_t last_hour = (series.rbegin()->first.wholeSeconds() + 3599) / 3600;
    bool any = false;
    for (std::int64_t h = first_hour; h <= last_hour; ++h) {
      const GnssTime toc = GnssTime::fromGpsSeconds(h * 3600);
      // Least-squares line through the samples within +-900 s of the hour.
      double n = 0, st = 0, sc = 0, stt = 0, stc = 0;
      for (auto it = series.lower_bound(toc - 900.0); it != series.end() && it->first <= toc + 900.0; ++it) {
        const double t = it->first - toc;
        n += 1, st += t, sc += it->second, stt += t * t, stc += t * it->second;
      }
      const double det = n * stt - st * st;
      if (n < 2 || det <= 0.0) continue;
      const double af1 = (n * stc - st * sc) / det;
      const double af0 = (sc - af1 * st) / n;
      const auto w = toc.gpsWeek();
      const int iod = static_cast<int>(std::llround(w.seconds_of_week / 3600.0)) % 256;
      const auto c = toc.toCalendar(TimeSystem::GPS);
      const double m0 = std::fmod(sat.prn * 0.37 + w.seconds_of_week * 1.458e-4, 2 * kPi) - kPi;
      const double omega0 = std::fmod(sat.prn * 1.047, 2 * kPi) - kPi;
      out.text += format("%s %04d %02d %02d %02d %02d %02d", sat.toString().c_str(), c.year, c.month, c.day, c.hour,
                         c.minute, static_cast<int>(c.second));
      out.text += d19(af0) + d19(af1) + d19(0.0) + "\n";
      auto row = [&](double a, double b, double cc, double d) {
        out.text += "    " + d19(a) + d19(b) + d19(cc) + d19(d) + "\n";
      };
      row(iod, 0.0, 0.0, m0);                              // IODE, Crs, Delta n, M0
      row(0.0, 0.005, 0.0, 5153.7);                        // Cuc, e, Cus, sqrt(A)
      row(w.seconds_of_week, 0.0, omega0, 0.0);            // Toe, Cic, OMEGA0, Cis
      row(0.96, 0.0, 0.0, -8.0e-9);                        // i0, Crc, omega, OMEGA DOT
      row(0.0, 0.0, w.week, 0.0);                          // IDOT, L2 codes, GPS week, L2 P flag
      row(2.0, 0.0, 0.0, iod);                             // SV accuracy, health, TGD, IODC
      row(w.seconds_of_week, 4.0, 0.0, 0.0);               // transmission time, fit interval
      ++out.records;
      any = true;
    }
    if (any) ++out.satellites;
  }
  return out;
}

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
