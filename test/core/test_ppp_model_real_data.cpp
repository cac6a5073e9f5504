// Real-data validation of the PPP measurement model on ZIM2 and CCJ2: with the
// truth position, the IF code residuals after removing the receiver clock must
// be at the decimetre level for every satellite above the cutoff (this checks
// the whole chain: signal selection, OSB, orbits, clocks, antennas, troposphere,
// relativity); over the ZIM2 hour the phase residuals must be constant per arc
// up to a few centimetres (wind-up, PCO/PCV, tides).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include <Eigen/Dense>

#include "ppp_dataset.h"

namespace ppp {
namespace {

struct CodeCheck {
  double rms_m = 0.0;
  double rms_lsq_m = 0.0;
  double max_abs_m = 0.0;
  std::size_t used = 0;
  std::size_t rejected = 0;
};

/// First epoch at the truth position: IF code residuals minus their mean.
CodeCheck firstEpochCodeResiduals(test::LoadedDataset& ds, const char* label) {
  SignalSelector selector(ds.reader->header(), {}, ds.bias.get());
  ObsEpoch epoch;
  EXPECT_TRUE(ds.reader->next(epoch));
  const auto sel = selector.select(epoch);
  std::vector<ArcId> arcs(sel.observations.size(), 1);
  ReceiverState truth;
  truth.position_ecef_m = ds.paths.truth_ecef_m;
  truth.zwd_m = 0.1;
  WindupTracker windup;
  EpochMeasurements em;
  std::vector<ModelTerms> terms;
  ds.model->evaluate(sel.observations, arcs, truth, &windup, em, &terms);
  CodeCheck c;
  c.used = em.used.size();
  c.rejected = em.rejected.size();
  // Receiver clock and the ZWD correction (to the 0.1 m linearisation value) by
  // least squares on the code residuals: r = clock + m_w dZWD.
  Eigen::MatrixXd a(em.used.size(), 2);
  Eigen::VectorXd y(em.used.size());
  for (std::size_t k = 0; k < em.used.size(); ++k) {
    a(k, 0) = 1.0;
    a(k, 1) = em.used[k].jacobian(3);
    y(k) = em.used[k].codeResidual_m();
  }
  const Eigen::Vector2d x = a.colPivHouseholderQr().solve(y);
  double mean = 0.0;
  for (const auto& m : em.used) mean += m.codeResidual_m();
  mean /= std::max<std::size_t>(1, em.used.size());
  std::printf("%s %s: mean code residual %.3f m; LSQ clock %.3f m, ZWD %.3f m\n", label,
              epoch.time.toString().c_str(), mean, x(0), truth.zwd_m + x(1));
  std::printf("  sat  el[deg]  res-mean[m]  res-lsq[m] sagnac[m]  rel[m]  shapiro[m] pcv_r[m] pcv_s[m] windup[cyc]\n");
  for (std::size_t k = 0; k < em.used.size(); ++k) {
    const auto& m = em.used[k];
    const auto& t = terms[k];
    const double r = m.codeResidual_m() - mean;
    const double r2 = y(k) - a.row(k).dot(x);
    c.rms_m += r * r;
    c.rms_lsq_m += r2 * r2;
    c.max_abs_m = std::max(c.max_abs_m, std::abs(r));
    std::printf("  %s  %6.1f  %9.3f  %9.3f  %9.3f  %7.3f  %7.4f  %7.4f  %7.4f  %7.3f\n", m.satellite.toString().c_str(),
                m.elevation_rad * kRadToDeg, r, r2, t.sagnac_m, t.relativistic_clock_m, t.shapiro_m, t.receiver_pcv_m,
                t.satellite_pcv_m, t.windup_cycles);
  }
  c.rms_lsq_m = std::sqrt(c.rms_lsq_m / std::max<std::size_t>(1, em.used.size()));
  c.rms_m = std::sqrt(c.rms_m / std::max<std::size_t>(1, em.used.size()));
  for (const auto& r : em.rejected) std::printf("  rejected %s: %s\n", r.satellite.toString().c_str(), r.reason.c_str());
  std::printf("  RMS %.3f m (mean removed), %.3f m (clock and ZWD fitted), max %.3f m over %zu satellites\n", c.rms_m,
              c.rms_lsq_m, c.max_abs_m, c.used);
  return c;
}

TEST(PppModelRealData, Zim2FirstEpochCodeResidualsAtTruth) {
  PPP_REQUIRE_SHARED_DATA();
  test::LoadedDataset ds(test::zim2Dataset());
  const CodeCheck c = firstEpochCodeResiduals(ds, "ZIM2");
  EXPECT_GE(c.used, 7u);
  EXPECT_LT(c.rms_m, 1.0);
  EXPECT_LT(c.max_abs_m, 2.5);
  for (const auto& s : ds.model->antennaSources()) std::printf("  antenna %s\n", s.c_str());
}

TEST(PppModelRealData, Ccj2FirstEpochCodeResidualsAtTruth) {
  PPP_REQUIRE_SHARED_DATA();
  test::LoadedDataset ds(test::ccj2Dataset());
  // The receiver TRM59800.00 SCIS is in no file: TRM59800.00 NONE from the second file is used.
  ASSERT_NE(ds.model->receiverCalibration(), nullptr);
  EXPECT_EQ(ds.model->receiverCalibration()->radome, "NONE");
  const CodeCheck c = firstEpochCodeResiduals(ds, "CCJ2");
  EXPECT_GE(c.used, 7u);
  EXPECT_LT(c.rms_m, 1.0);
  EXPECT_LT(c.max_abs_m, 2.5);
  const auto sources = ds.model->antennaSources();
  for (const auto& s : sources) std::printf("  antenna %s\n", s.c_str());
  ASSERT_GE(sources.size(), 2u);
  EXPECT_NE(sources[0].find("igs20_zim2_gps_trim.atx"), std::string::npos) << sources[0];
  EXPECT_NE(sources[1].find("igs20_gps_satellites_trim.atx"), std::string::npos) << sources[1];
}

}  // namespace
}  // namespace ppp
