#pragma once
// Writes small synthetic SP3-c/d texts for the tests, column by column as laid
// out in the SP3-d document (Hilla 2016). The record callback decides what each
// satellite holds at each epoch, so tests can drop epochs or put bad markers in.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ppp::test {

struct SyntheticRecord {
  bool present = true;
  Eigen::Vector3d position_km = Eigen::Vector3d::Zero();  // 0.000000 = bad marker
  double clock_us = 999999.999999;
  std::optional<Eigen::Vector3d> velocity_dm_s;
  double clock_rate = 999999.999999;
  std::string flags;  // columns 75-80 verbatim, e.g. "EP  MP"
};

struct SyntheticSp3 {
  char version = 'd';
  int year = 2026, month = 5, day = 13;  // first epoch at 00:00:00
  int epochs = 10;
  double interval_s = 900.0;
  std::string time_system = "GPS";
  char file_type = 'G';
  std::vector<std::string> satellites{"G01"};
  std::vector<std::string> comments{"synthetic test product"};
  bool with_eof = true;
  bool with_velocity = false;
  std::function<SyntheticRecord(int epoch, const std::string& sat)> record;

  std::string text() const {
    std::string out;
    char buf[256];
    const int n = static_cast<int>(satellites.size());
    std::snprintf(buf, sizeof buf, "#%c%c%4d %2d %2d %2d %2d %11.8f %7d %-5s %-5s %-3s %-4s\n", version,
                  with_velocity ? 'V' : 'P', year, month, day, 0, 0, 0.0, epochs, "ORBIT", "IGS20", "FIT", "TST");
    out += buf;
    // GPS week / seconds of week for 2026-05-13 (week 2418, Wednesday) and MJD 61173.
    std::snprintf(buf, sizeof buf, "## %4d %15.8f %14.8f %5d %15.13f\n", 2418, 259200.0, interval_s, 61173, 0.0);
    out += buf;
    const int lines = std::max(5, (n + 16) / 17);
    for (int l = 0; l < lines; ++l) {
      if (l == 0) std::snprintf(buf, sizeof buf, "+  %3d   ", n);
      else std::snprintf(buf, sizeof buf, "+        ");
      out += buf;
      for (int k = 0; k < 17; ++k) {
        const int i = l * 17 + k;
        out += i < n ? satellites[i] : std::string("  0");
      }
      out += "\n";
    }
    for (int l = 0; l < lines; ++l) {
      out += "++       ";
      for (int k = 0; k < 17; ++k) out += (l * 17 + k) < n ? "  7" : "  0";
      out += "\n";
    }
    out += std::string("%c ") + file_type + "  cc " + time_system + " ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc\n";
    out += "%c cc cc ccc ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc\n";
    std::snprintf(buf, sizeof buf, "%%f %10.7f %12.9f %14.11f %18.15f\n", 1.25, 1.025, 0.0, 0.0);
    out += buf;
    out += "%f  0.0000000  0.000000000  0.00000000000  0.000000000000000\n";
    out += "%i    0    0    0    0      0      0      0      0         0\n";
    out += "%i    0    0    0    0      0      0      0      0         0\n";
    for (const auto& c : comments) out += "/* " + c + "\n";
    for (int e = 0; e < epochs; ++e) {
      const double t = e * interval_s;
      const int hour = static_cast<int>(t / 3600), minute = static_cast<int>((t - hour * 3600) / 60);
      const double second = t - hour * 3600 - minute * 60;
      std::snprintf(buf, sizeof buf, "*  %4d %2d %2d %2d %2d %11.8f\n", year, month, day + hour / 24, hour % 24,
                    minute, second);
      out += buf;
      for (const auto& sat : satellites) {
        const SyntheticRecord r = record(e, sat);
        if (!r.present) continue;
        std::snprintf(buf, sizeof buf, "P%s%14.6f%14.6f%14.6f%14.6f  5  5  5  60 %s\n", sat.c_str(),
                      r.position_km.x(), r.position_km.y(), r.position_km.z(), r.clock_us, r.flags.c_str());
        out += buf;
        if (with_velocity && r.velocity_dm_s) {
          std::snprintf(buf, sizeof buf, "V%s%14.6f%14.6f%14.6f%14.6f\n", sat.c_str(), r.velocity_dm_s->x(),
                        r.velocity_dm_s->y(), r.velocity_dm_s->z(), r.clock_rate);
          out += buf;
        }
      }
    }
    if (with_eof) out += "EOF\n";
    return out;
  }
};

}  // namespace ppp::test
