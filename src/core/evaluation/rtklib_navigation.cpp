#include "ppp_bayes_tree/evaluation/rtklib_navigation.h"

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

}  // namespace ppp
