// ppp_rtklib_inputs: writes what RTKLIB's rnx2rtkp needs for a precise-product
// PPP run, from our own readers (see evaluation/rtklib_navigation.h and io/products/sp3_writer.h):
//   ppp_rtklib_inputs nav OUT.nav CLOCK_FILE [CLOCK_FILE...]
//       GPS RINEX 3 navigation file whose clock terms come from precise clocks.
//   ppp_rtklib_inputs sp3 OUT.sp3 SP3_FILE
//       GPS-only SP3-c copy (RTKLIB 2.4.3 reads at most 99 satellites).
// Inputs may be plain or gzip.
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/rtklib_navigation.h"
#include "ppp_bayes_tree/io/products/sp3_writer.h"

namespace {

int usage() {
  std::cerr << "usage: ppp_rtklib_inputs nav OUT.nav CLOCK_FILE [CLOCK_FILE...]\n"
            << "       ppp_rtklib_inputs sp3 OUT.sp3 SP3_FILE\n";
  return 2;
}

bool writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return usage();
  const std::string mode = argv[1], out_path = argv[2];
  try {
    if (mode == "nav") {
      std::vector<ppp::RinexClockFile> files;
      ppp::RinexClockReadOptions options;
      options.keep_receiver_clocks = false;
      for (int i = 3; i < argc; ++i) files.push_back(ppp::readRinexClock(argv[i], options));
      std::vector<const ppp::RinexClockFile*> ptrs;
      for (const auto& f : files) {
        if (!f.report.clean()) std::cerr << f.report.summary() << "\n";
        ptrs.push_back(&f);
      }
      const auto nav = ppp::gpsNavigationFromClocks(ptrs);
      if (!writeFile(out_path, nav.text)) return std::cerr << "cannot write " << out_path << "\n", 1;
      std::cerr << "ppp_rtklib_inputs: " << out_path << ": " << nav.records << " GPS records for " << nav.satellites
                << " satellites\n";
    } else if (mode == "sp3" && argc == 4) {
      const auto sp3 = ppp::readSp3(std::string(argv[3]));
      if (!sp3.report.clean()) std::cerr << sp3.report.summary() << "\n";
      const auto gps = ppp::gpsOnlySp3(sp3);
      if (!writeFile(out_path, gps.text)) return std::cerr << "cannot write " << out_path << "\n", 1;
      std::cerr << "ppp_rtklib_inputs: " << out_path << ": " << gps.epochs << " epochs, " << gps.satellites
                << " GPS satellites\n";
    } else {
      return usage();
    }
  } catch (const std::exception& e) {  // FileOpenError, ParseError
    std::cerr << "ppp_rtklib_inputs: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
