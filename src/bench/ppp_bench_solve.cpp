// Benchmark: epochs per second of the EKF-PPP pipeline (ppp_solve --estimator
// ekf: reading, signal selection, arc tracking, model, EKF, output files) on the
// two shared datasets, product loading timed separately. Prints, asserts nothing.
//
// usage: ppp_bench_solve [REPEATS]   (default 5; needs ../shared/data)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>
#include <algorithm>

#include "ppp_bayes_tree/app/ppp_solve_run.h"

namespace {

std::string dataDir() {
  const char* e = std::getenv("PPP_SHARED_DATA");
  return e ? e : "../shared/data";
}

struct Dataset {
  const char* label;
  ppp::PppInputFiles files;
};

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const std::string d = dataDir();
  std::vector<Dataset> sets = {
      {"ZIM2", ppp::preciseInputFiles(d + "/zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx",
                                      {d + "/zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"},
                                      {d + "/zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"},
                                      {d + "/antex/igs20_zim2_gps_trim.atx"},
                                      d + "/zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz")},
      {"CCJ2", ppp::preciseInputFiles(d + "/ccj2-2021-210/ccj22100.21o",
                                      {d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz"},
                                      {d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"},
                                      {d + "/antex/igs20_gps_satellites_trim.atx", d + "/antex/igs20_zim2_gps_trim.atx"},
                                      d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz")},
  };
  const std::string out = (std::filesystem::temp_directory_path() / "ppp_bench_solve").string();
  std::printf("ppp_bench_solve: EKF pipeline, best of %d runs\n", repeats);
  std::printf("%-6s %8s %12s %14s %14s %12s\n", "data", "epochs", "total [s]", "processing [s]", "epochs/s", "us/epoch");
  for (const auto& s : sets) {
    if (!std::filesystem::exists(s.files.obs)) {
      std::printf("%-6s skipped: %s missing (set PPP_SHARED_DATA)\n", s.label, s.files.obs.c_str());
      continue;
    }
    double best_total = 1e30, best_proc = 1e30;
    std::size_t epochs = 0;
    for (int r = 0; r < repeats; ++r) {
      ppp::PppSolveRequest req;
      req.files = s.files;
      req.out_dir = out;
      const auto t0 = std::chrono::steady_clock::now();
      const auto o = ppp::solvePpp(req);
      const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      best_total = std::min(best_total, total);
      best_proc = std::min(best_proc, o.run.processing_time_s);
      epochs = o.run.epochs_read;
    }
    std::printf("%-6s %8zu %12.3f %14.3f %14.0f %12.0f\n", s.label, epochs, best_total, best_proc,
                epochs / best_proc, best_proc / epochs * 1e6);
  }
  std::printf("total = product loading + processing + outputs; processing = epochs loop incl. outputs\n");
  std::filesystem::remove_all(out);
  return 0;
}
