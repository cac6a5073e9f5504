#pragma once
// The EKF and the smoother run through the offline pipeline (PppPipeline: signal
// selection, arc tracking, the measurement model; one pipeline per estimator, fed
// identical epochs), with the statistics of the EKF, smoother-filtered and
// smoother-smoothed solutions against the truth. Used by ppp_bench_smoother and the
// smoother's real-data test.
#include <chrono>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"

namespace ppp::bench {

struct SmootherRunInputs {
  PppInputFiles files;
  Eigen::Vector3d truth_ecef_m;
};

struct SmootherRunOutput {
  std::vector<SolutionEpoch> ekf, filtered, smoothed;
  std::vector<EstimatorEpochResult> smoother_epochs;  // processed epochs (refused ones left out)
  double ekf_run_s = 0.0, smoother_run_s = 0.0;      // whole pipeline runs
  PositionErrorStatistics ekf_stats, filtered_stats, smoothed_stats;
};

inline SmootherRunOutput runSmootherAndEkf(const SmootherRunInputs& in, const PppConfig& config,
                                           bool run_ekf = true) {
  using Clock = std::chrono::steady_clock;
  SmootherRunOutput out;
  if (run_ekf) {
    PppPipeline pipeline(in.files, config);
    const std::unique_ptr<PppEstimator> ekf_made = makeEstimator("ekf", config);
    PppEstimator& ekf = *ekf_made;
    const auto t0 = Clock::now();
    pipeline.run(ekf, [&](const PppEpochRecord& rec) {
      if (!rec.refused) out.ekf.push_back(rec.solution);
    });
    out.ekf_run_s = std::chrono::duration<double>(Clock::now() - t0).count();
    out.ekf_stats = computePositionErrorStatistics(out.ekf, in.truth_ecef_m);
  }
  PppPipeline pipeline(in.files, config);
  const std::unique_ptr<PppEstimator> smoother_made = makeEstimator("smoother", config);
  PppEstimator& smoother = *smoother_made;
  const auto t0 = Clock::now();
  pipeline.run(smoother, [&](const PppEpochRecord& rec) {
    if (rec.refused) return;
    out.filtered.push_back(rec.solution);
    out.smoother_epochs.push_back(smoother.lastResult());
  });
  out.smoother_run_s = std::chrono::duration<double>(Clock::now() - t0).count();
  for (const auto& s : smoother.smoothing()->smoothedTrajectory()) {
    SolutionEpoch e;
    e.time = s.time;
    e.position_ecef_m = s.state.position_ecef_m;
    e.zwd_m = s.state.zwd_m;
    e.receiver_clock_m = s.state.referenceClock_m();
    out.smoothed.push_back(e);
  }
  out.filtered_stats = computePositionErrorStatistics(out.filtered, in.truth_ecef_m);
  out.smoothed_stats = computePositionErrorStatistics(out.smoothed, in.truth_ecef_m);
  return out;
}

inline SmootherRunInputs zim2Inputs(const std::string& d) {
  SmootherRunInputs in;
  in.files.obs = d + "/zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx";
  in.files.sp3 = {d + "/zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"};
  in.files.clk = {d + "/zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"};
  in.files.atx = {d + "/antex/igs20_zim2_gps_trim.atx"};
  in.files.bias = d + "/zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz";
  // ../shared/data/README.md (ITRF2020 propagated to 2026-05-13).
  in.truth_ecef_m = Eigen::Vector3d(4331299.5841, 567537.7070, 4633133.9645);
  return in;
}

inline SmootherRunInputs ccj2Inputs(const std::string& d) {
  SmootherRunInputs in;
  in.files.obs = d + "/ccj2-2021-210/ccj22100.21o";
  in.files.sp3 = {d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz"};
  in.files.clk = {d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"};
  in.files.atx = {d + "/antex/igs20_gps_satellites_trim.atx", d + "/antex/igs20_zim2_gps_trim.atx"};
  in.files.bias = d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz";
  // ../shared/data/README.md (WUM clock file header station coordinate).
  in.truth_ecef_m = Eigen::Vector3d(-4490605.094, 3483895.065, 2884928.334);
  return in;
}

}  // namespace ppp::bench
