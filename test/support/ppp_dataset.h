#pragma once
// Loading of the real ZIM2 / CCJ2 datasets (../shared/data) for the PPP model tests.
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/sinex_bias_provider.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "test_support.h"

namespace ppp::test {

struct PppDataset {
  std::string obs;
  std::vector<std::string> sp3, clk, atx;
  std::string bia;
  Eigen::Vector3d truth_ecef_m;
};

inline PppDataset zim2Dataset() {
  return {dataPath("zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx"),
          {dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3")},
          {dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK")},
          {dataPath("antex/igs20_zim2_gps_trim.atx")},
          dataPath("zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz"),
          // Truth from ../shared/data/README.md (ITRF2020 propagated to 2026-05-13).
          Eigen::Vector3d(4331299.5841, 567537.7070, 4633133.9645)};
}

inline PppDataset ccj2Dataset() {
  return {dataPath("ccj2-2021-210/ccj22100.21o"),
          {dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz")},
          {dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz")},
          // Satellites from the first file, the receiver (TRM59800.00 NONE for SCIS) from the second.
          {dataPath("antex/igs20_gps_satellites_trim.atx"), dataPath("antex/igs20_zim2_gps_trim.atx")},
          dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz"),
          // Truth from ../shared/data/README.md (WUM clock file header station coordinate).
          Eigen::Vector3d(-4490605.094, 3483895.065, 2884928.334)};
}

/// Everything the model needs, loaded once.
struct LoadedDataset {
  PppDataset paths;
  std::unique_ptr<RinexObsReader> reader;
  PreciseEphemeris products;
  std::unique_ptr<BiasSinexFile> bias;
  std::unique_ptr<SinexBiasProvider> biases;  // the bias file as the chain sees it
  std::unique_ptr<PppMeasurementModel> model;

  explicit LoadedDataset(PppDataset d, MeasurementModelOptions options = {})
      : paths(std::move(d)), products(PreciseEphemeris::load(paths.sp3, paths.clk)) {
    reader = std::make_unique<RinexObsReader>(RinexObsReader::open(paths.obs));
    bias = std::make_unique<BiasSinexFile>(readBiasSinexFile(paths.bia));
    biases = std::make_unique<SinexBiasProvider>(*bias, paths.bia.substr(paths.bia.find_last_of('/') + 1));
    std::vector<AntexSource> antex;
    for (const auto& p : paths.atx) antex.push_back({p.substr(p.find_last_of('/') + 1), readAntexFile(p)});
    model = std::make_unique<PppMeasurementModel>(products, std::make_shared<AntexCalibrations>(std::move(antex)),
                                                  ReceiverAntenna::fromHeader(reader->header()), nullptr, options);
  }
};

/// The dataset's files as ppp_solve's inputs.
inline PppInputFiles inputFiles(const PppDataset& d) {
  PppInputFiles f;
  f.obs = d.obs;
  f.sp3 = d.sp3;
  f.clk = d.clk;
  f.atx = d.atx;
  f.bias = d.bia;
  return f;
}

/// ppp_solve's request for a dataset, as a user runs real data: the defaults
/// (the real-data values: ppp_solve without --config).
inline PppSolveRequest solveRequest(const PppDataset& d, const std::string& out_dir,
                                    const std::string& estimator = "ekf") {
  PppSolveRequest r;
  r.files = inputFiles(d);
  r.truth_ecef_m = d.truth_ecef_m;
  r.out_dir = out_dir;
  r.estimator = estimator;
  return r;
}

}  // namespace ppp::test
