#pragma once
// Offline run of the EKF and the smoother side by side on one RINEX file, for the
// smoother benchmark (ppp_bench_smoother) and its real-data regression test. This is
// NOT the pipeline (ppp_solve owns that); it is the minimal loop the estimators
// need: signal selection (GPS, OSB), arc tracking (ended arcs removed from both
// estimators), one MeasurementFunction per epoch and estimator (each with its own
// wind-up tracker), then the statistics of each solution against the truth.
#include <chrono>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/evaluation/solution_epoch.h"
#include "ppp_bayes_tree/io/antex_reader.h"
#include "ppp_bayes_tree/io/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/rinex_obs_reader.h"
#include "ppp_bayes_tree/ppp/arc_tracker.h"
#include "ppp_bayes_tree/ppp/ekf_ppp.h"
#include "ppp_bayes_tree/ppp/ppp_measurement_model.h"
#include "ppp_bayes_tree/ppp/ppp_smoother.h"
#include "ppp_bayes_tree/ppp/signal_selection.h"

namespace ppp::bench {

struct SmootherRunInputs {
  std::string obs;
  std::vector<std::string> sp3, clk, atx;
  std::string bia;
  Eigen::Vector3d truth_ecef_m;
};

struct SmootherRunConfig {
  StochasticModel model;
  EkfOptions ekf;
  PppSmootherOptions smoother;
  MeasurementModelOptions measurement_model;
  bool run_ekf = true;
};

struct SmootherRunOutput {
  std::vector<SolutionEpoch> ekf, filtered, smoothed;
  std::vector<SmootherEpochResult> smoother_epochs;
  std::vector<double> ekf_epoch_time_s;
  double ekf_total_s = 0.0, smoother_total_s = 0.0;  // estimator calls only
  PositionErrorStatistics ekf_stats, filtered_stats, smoothed_stats;
};

inline SolutionEpoch toSolutionEpoch(const GnssTime& time, const std::optional<EpochSolution>& s, int used,
                                     int rejected) {
  SolutionEpoch e;
  e.time = time;
  e.satellites_used = used;
  e.satellites_rejected = rejected;
  if (!s) {
    e.status = SolutionStatus::NoSolution;
    return e;
  }
  e.status = SolutionStatus::PppFloat;
  e.position_ecef_m = s->state.position_ecef_m;
  e.covariance_ecef_m2 = s->positionCovariance_m2();
  e.zwd_m = s->state.zwd_m;
  e.receiver_clock_m = s->state.clock_m;
  return e;
}

inline SmootherRunOutput runSmootherAndEkf(const SmootherRunInputs& in, const SmootherRunConfig& config) {
  using Clock = std::chrono::steady_clock;
  const PreciseEphemeris products = PreciseEphemeris::load(in.sp3, in.clk);
  const BiasSinexFile bias = readBiasSinexFile(in.bia);
  auto reader = RinexObsReader::open(in.obs);
  std::vector<AntexSource> antex;
  for (const auto& p : in.atx) antex.push_back({p.substr(p.find_last_of('/') + 1), readAntexFile(p)});
  const PppMeasurementModel model(products, std::move(antex), ReceiverAntenna::fromHeader(reader.header()), nullptr,
                                  config.measurement_model);
  SignalSelector selector(reader.header(), {}, &bias);
  ArcTracker tracker;
  EkfPpp ekf(config.model, config.ekf);
  PppSmoother smoother(config.model, config.smoother);
  if (reader.header().approx_position_ecef_m) {
    ekf.setApproximatePosition(*reader.header().approx_position_ecef_m);
    smoother.setApproximatePosition(*reader.header().approx_position_ecef_m);
  }
  WindupTracker windup_ekf, windup_smoother;
  SmootherRunOutput out;
  ObsEpoch epoch;
  SignalSelectionResult sel;
  std::vector<DualFrequencyObservation> obs;
  std::vector<ArcId> arcs;
  while (reader.next(epoch)) {
    selector.select(epoch, sel);
    const ArcEpochResult arc_result = tracker.process(epoch.time, sel.observations);
    if (!arc_result.accepted) continue;
    obs.clear();
    arcs.clear();
    for (std::size_t i = 0; i < sel.observations.size(); ++i) {
      if (!arc_result.satellites[i].usable || arc_result.satellites[i].arc == 0) continue;
      obs.push_back(sel.observations[i]);
      arcs.push_back(arc_result.satellites[i].arc);
    }
    for (const auto& ended : arc_result.ended) {
      ekf.removeArc(ended.arc);
      smoother.removeArc(ended.arc);
    }
    auto function = [&](WindupTracker& windup) -> MeasurementFunction {
      return [&model, &obs, &arcs, w = &windup](const ReceiverState& s) {
        EpochMeasurements em;
        model.evaluate(obs, arcs, s, w, em);
        return em;
      };
    };
    if (config.run_ekf) {
      const auto t0 = Clock::now();
      const EkfEpochResult r = ekf.processEpoch(epoch.time, function(windup_ekf));
      const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
      out.ekf_total_s += dt;
      out.ekf_epoch_time_s.push_back(dt);
      out.ekf.push_back(toSolutionEpoch(epoch.time, r.solution, static_cast<int>(r.used.size()),
                                        static_cast<int>(r.rejected.size())));
    }
    const auto t0 = Clock::now();
    SmootherEpochResult r = smoother.processEpoch(epoch.time, function(windup_smoother));
    out.smoother_total_s += std::chrono::duration<double>(Clock::now() - t0).count();
    out.filtered.push_back(toSolutionEpoch(epoch.time, r.solution, static_cast<int>(r.used.size()),
                                           static_cast<int>(r.rejected.size())));
    out.smoother_epochs.push_back(std::move(r));
  }
  for (const auto& s : smoother.smoothedTrajectory()) {
    SolutionEpoch e;
    e.time = s.time;
    e.position_ecef_m = s.state.position_ecef_m;
    e.zwd_m = s.state.zwd_m;
    e.receiver_clock_m = s.state.clock_m;
    out.smoothed.push_back(e);
  }
  if (config.run_ekf) out.ekf_stats = computePositionErrorStatistics(out.ekf, in.truth_ecef_m);
  out.filtered_stats = computePositionErrorStatistics(out.filtered, in.truth_ecef_m);
  out.smoothed_stats = computePositionErrorStatistics(out.smoothed, in.truth_ecef_m);
  return out;
}

inline SmootherRunInputs zim2Inputs(const std::string& d) {
  return {d + "/zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx",
          {d + "/zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"},
          {d + "/zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"},
          {d + "/antex/igs20_zim2_gps_trim.atx"},
          d + "/zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz",
          // ../shared/data/README.md (ITRF2020 propagated to 2026-05-13).
          Eigen::Vector3d(4331299.5841, 567537.7070, 4633133.9645)};
}

inline SmootherRunInputs ccj2Inputs(const std::string& d) {
  return {d + "/ccj2-2021-210/ccj22100.21o",
          {d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz"},
          {d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"},
          {d + "/antex/igs20_gps_satellites_trim.atx", d + "/antex/igs20_zim2_gps_trim.atx"},
          d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz",
          // ../shared/data/README.md (WUM clock file header station coordinate).
          Eigen::Vector3d(-4490605.094, 3483895.065, 2884928.334)};
}

}  // namespace ppp::bench
