// Benchmark of the PPP measurement model: signal selection and model
// evaluation per epoch on the real ZIM2 and CCJ2 hours (../shared/data beside
// the repository, or $PPP_SHARED_DATA). Prints figures, asserts nothing.
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/sinex_bias_provider.h"
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"

using namespace ppp;

namespace {

void run(const std::string& label, const std::string& obs, const std::string& sp3, const std::string& clk,
         const std::vector<std::string>& atx, const std::string& bia, const Eigen::Vector3d& position) {
  const PreciseEphemeris products = PreciseEphemeris::load({sp3}, {clk});
  const BiasSinexFile bias_file = readBiasSinexFile(bia);
  const SinexBiasProvider bias(bias_file, bia);
  auto reader = RinexObsReader::open(obs);
  std::vector<AntexSource> antex;
  for (const auto& p : atx) antex.push_back({p, readAntexFile(p)});
  PppMeasurementModel model(products, std::make_shared<AntexCalibrations>(std::move(antex)), ReceiverAntenna::fromHeader(reader.header()), nullptr);
  SignalSelector selector(reader.header(), {}, &bias);
  std::vector<ObsEpoch> epochs;
  ObsEpoch e;
  while (reader.next(e)) epochs.push_back(e);
  ReceiverState state;
  state.position_ecef_m = position;
  state.zwd_m = 0.1;
  SignalSelectionResult sel;
  EpochMeasurements em;
  WindupTracker windup;
  std::vector<ArcId> arcs;
  const int repeats = 20;
  double select_us = 0.0, model_us = 0.0;
  std::size_t used = 0;
  for (int r = 0; r < repeats; ++r) {
    windup.reset();
    for (const auto& ep : epochs) {
      auto t0 = std::chrono::steady_clock::now();
      selector.select(ep, sel);
      auto t1 = std::chrono::steady_clock::now();
      arcs.assign(sel.observations.size(), 1);
      model.evaluate(sel.observations, arcs, state, &windup, em);
      auto t2 = std::chrono::steady_clock::now();
      select_us += std::chrono::duration<double, std::micro>(t1 - t0).count();
      model_us += std::chrono::duration<double, std::micro>(t2 - t1).count();
      used += em.used.size();
    }
  }
  const double n = static_cast<double>(epochs.size() * repeats);
  std::printf("%s: %zu epochs x %d, %.1f satellites used per epoch: selection %.1f us/epoch, model %.1f us/epoch "
              "(%.2f us/satellite)\n",
              label.c_str(), epochs.size(), repeats, used / n, select_us / n, model_us / n, model_us / used);
}

}  // namespace

int main() {
  const char* env = std::getenv("PPP_SHARED_DATA");
  const std::string d = env ? env : "../shared/data";
  run("ZIM2", d + "/zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx",
      d + "/zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3",
      d + "/zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK", {d + "/antex/igs20_zim2_gps_trim.atx"},
      d + "/zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz",
      Eigen::Vector3d(4331299.5841, 567537.7070, 4633133.9645));
  run("CCJ2", d + "/ccj2-2021-210/ccj22100.21o", d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz",
      d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz",
      {d + "/antex/igs20_gps_satellites_trim.atx", d + "/antex/igs20_zim2_gps_trim.atx"},
      d + "/ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz",
      Eigen::Vector3d(-4490605.094, 3483895.065, 2884928.334));
  return 0;
}
