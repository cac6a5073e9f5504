// Real-data validation of the PPP measurement model on ZIM2 and CCJ2: with the
// truth position, the IF code residuals after removing the receiver clock must
// be at the decimetre level for every satellite above the cutoff (this checks
// the whole chain: signal selection, OSB, orbits, clocks, antennas, troposphere,
// relativity); over the ZIM2 hour the phase residuals must be constant per arc
// up to a few centimetres (wind-up, PCO/PCV, tides).
#include <gtest/gtest.h>

#include <chrono>
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
  SignalSelector selector(ds.reader->header(), {}, ds.biases.get());
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
  std::vector<double> phase_clock;
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
    a(k, 1) = em.used[k].jacobian(ReceiverStateLayout().zwd());
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
  for (const auto& r : em.rejected) std::printf("  rejected %s: %s\n", r.satellite.toString().c_str(), r.detail.c_str());
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
  // CCJ2's C1C codes are noisier (G08 +1.9 m, G30 -1.95 m at this epoch; their
  // hour means are below 0.4 m, see Ccj2HourPhaseResidualsConstantPerArc): the
  // single-epoch RMS is 1.06-1.09 m, hence the looser bound here.
  EXPECT_LT(c.rms_m, 1.3);
  EXPECT_LT(c.max_abs_m, 2.5);
  const auto sources = ds.model->antennaSources();
  for (const auto& s : sources) std::printf("  antenna %s\n", s.c_str());
  ASSERT_GE(sources.size(), 2u);
  EXPECT_NE(sources[0].find("igs20_zim2_gps_trim.atx"), std::string::npos) << sources[0];
  EXPECT_NE(sources[1].find("igs20_gps_satellites_trim.atx"), std::string::npos) << sources[1];
}

struct ArcStats {
  SatelliteId satellite;
  ArcId arc = 0;
  int n = 0;
  double min_el_deg = 90.0, max_el_deg = 0.0;
  double code_mean_m = 0.0, code_rms_m = 0.0;       // code residual after clock + ZWD
  double phase_rms_m = 0.0;                         // phase residual after clock + bias + ZWD
  double phase_drift_m = 0.0;                       // linear trend over the arc (slope x duration)
  double phase_codeclock_rms_m = 0.0;               // phase minus the code-derived clock, arc mean removed
  double phase_codeclock_drift_m = 0.0;
  double windup_first_cycles = 0.0, windup_last_cycles = 0.0;
};

struct HourAnalysis {
  std::vector<ArcStats> arcs;
  double zwd_phase_m = 0.0, zwd_code_m = 0.0;
  double microseconds_per_epoch = 0.0;
  int epochs = 0;
};

double trendTimesDuration(const std::vector<double>& t, const std::vector<double>& r) {
  const std::size_t n = t.size();
  if (n < 3) return 0.0;
  double mt = 0, mr = 0;
  for (std::size_t i = 0; i < n; ++i) mt += t[i], mr += r[i];
  mt /= n;
  mr /= n;
  double stt = 0, str = 0;
  for (std::size_t i = 0; i < n; ++i) stt += (t[i] - mt) * (t[i] - mt), str += (t[i] - mt) * (r[i] - mr);
  return stt > 0 ? str / stt * (t.back() - t.front()) : 0.0;
}

/// Whole file at the truth position: per epoch clock, per arc bias and one ZWD
/// fitted by least squares to the phase residuals; per arc statistics.
HourAnalysis analyseHour(test::LoadedDataset& ds, const char* label) {
  SignalSelector selector(ds.reader->header(), {}, ds.biases.get());
  ReceiverState truth;
  truth.position_ecef_m = ds.paths.truth_ecef_m;
  truth.zwd_m = 0.0;  // the fitted ZWD enters through the wet mapping (Jacobian column 3)
  WindupTracker windup;
  ObsEpoch epoch;
  SignalSelectionResult sel;
  EpochMeasurements em;
  struct Row { int epoch; int arc_index; double t, code, phase, mw, el, w; };
  std::vector<Row> rows;
  std::map<int, ArcId> current_arc;       // satellite index -> arc id
  std::map<int, GnssTime> last_seen;
  std::map<ArcId, int> arc_index;
  std::vector<ArcStats> arcs;
  ArcId next_arc = 1;
  std::vector<ArcId> arc_ids;
  std::vector<double> phase_clock;
  std::vector<ModelTerms> terms;
  double total_us = 0.0;
  int k = 0;
  GnssTime t0;
  while (ds.reader->next(epoch)) {
    if (k == 0) t0 = epoch.time;
    selector.select(epoch, sel);
    arc_ids.clear();
    for (const auto& o : sel.observations) {
      const int si = o.satellite.index();
      const bool gap = last_seen.count(si) == 0 || epoch.time - last_seen[si] > 60.0;
      if (gap || o.loss_of_lock1 || o.loss_of_lock2) current_arc[si] = next_arc++;
      last_seen[si] = epoch.time;
      arc_ids.push_back(current_arc[si]);
    }
    const auto start = std::chrono::steady_clock::now();
    ds.model->evaluate(sel.observations, arc_ids, truth, &windup, em);
    total_us += std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    ds.model->evaluate(sel.observations, arc_ids, truth, &windup, em, &terms);
    for (std::size_t u = 0; u < em.used.size(); ++u) {
      const auto& m = em.used[u];
      if (arc_index.count(m.arc) == 0) {
        arc_index[m.arc] = static_cast<int>(arcs.size());
        ArcStats a;
        a.satellite = m.satellite;
        a.arc = m.arc;
        a.windup_first_cycles = terms[u].windup_cycles;
        arcs.push_back(a);
      }
      arcs[arc_index[m.arc]].windup_last_cycles = terms[u].windup_cycles;
      rows.push_back({k, arc_index[m.arc], epoch.time - t0, m.codeResidual_m(), m.phaseResidualWithoutBias_m(),
                      m.jacobian(ReceiverStateLayout().zwd()), m.elevation_rad * kRadToDeg, 1.0 / (m.code_sigma_m * m.code_sigma_m)});
    }
    ++k;
  }
  HourAnalysis h;
  h.epochs = k;
  h.microseconds_per_epoch = total_us / std::max(1, k);
  const int n_arcs = static_cast<int>(arcs.size());
  // Phase: clock per epoch (epoch 0 fixed to 0: the biases absorb it) + bias per arc + ZWD.
  {
    const int n = k + n_arcs + 1;
    Eigen::MatrixXd nm = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (const auto& r : rows) {
      std::vector<std::pair<int, double>> a;
      if (r.epoch > 0) a.push_back({r.epoch, 1.0});
      a.push_back({k + r.arc_index, 1.0});
      a.push_back({k + n_arcs, r.mw});
      for (auto [i, vi] : a) {
        b(i) += vi * r.phase;
        for (auto [j, vj] : a) nm(i, j) += vi * vj;
      }
    }
    nm(0, 0) = 1.0;  // epoch-0 clock fixed
    const Eigen::VectorXd x = nm.ldlt().solve(b);
    h.zwd_phase_m = x(k + n_arcs);
    phase_clock.assign(k, 0.0);
    for (int e = 1; e < k; ++e) phase_clock[e] = x(e);
    std::vector<std::vector<double>> ts(n_arcs), rs(n_arcs);
    for (const auto& r : rows) {
      const double v = r.phase - (r.epoch > 0 ? x(r.epoch) : 0.0) - x(k + r.arc_index) - r.mw * x(k + n_arcs);
      ts[r.arc_index].push_back(r.t);
      rs[r.arc_index].push_back(v);
      auto& a = arcs[r.arc_index];
      a.n++;
      a.min_el_deg = std::min(a.min_el_deg, r.el);
      a.max_el_deg = std::max(a.max_el_deg, r.el);
    }
    for (int a = 0; a < n_arcs; ++a) {
      double s2 = 0;
      for (double v : rs[a]) s2 += v * v;
      arcs[a].phase_rms_m = std::sqrt(s2 / rs[a].size());
      arcs[a].phase_drift_m = trendTimesDuration(ts[a], rs[a]);
    }
  }
  // Code: clock per epoch + ZWD (weighted); then the code-derived clock.
  {
    const int n = k + 1;
    Eigen::MatrixXd nm = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (const auto& r : rows) {
      Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
      a(r.epoch) = 1.0;
      a(k) = r.mw;
      nm += r.w * a * a.transpose();
      b += r.w * a * r.code;
    }
    Eigen::VectorXd x = nm.ldlt().solve(b);
    h.zwd_code_m = x(k);  // for the record: poorly determined by code alone
    // A diagnostic: receiver clock per epoch = weighted mean of the code
    // residuals, with the wet delay from the phase fit.
    std::vector<double> sw(k, 0.0), swr(k, 0.0);
    for (const auto& r : rows) {
      sw[r.epoch] += r.w;
      swr[r.epoch] += r.w * (r.code - r.mw * h.zwd_phase_m);
    }
    for (int e = 0; e < k; ++e) x(e) = sw[e] > 0 ? swr[e] / sw[e] : 0.0;
    x(k) = h.zwd_phase_m;
    std::printf("  code-derived clock minus phase clock [m], every 10 epochs (first epoch = 0):");
    for (int e = 0; e < k; e += 10) std::printf(" %.2f", (x(e) - phase_clock[e]) - (x(0) - phase_clock[0]));
    std::printf("\n");
    std::vector<double> sum(n_arcs, 0), sum2(n_arcs, 0);
    std::vector<int> cnt(n_arcs, 0);
    for (const auto& r : rows) {
      const double v = r.code - x(r.epoch) - r.mw * x(k);
      sum[r.arc_index] += v;
      sum2[r.arc_index] += v * v;
      cnt[r.arc_index]++;
    }
    for (int a = 0; a < n_arcs; ++a) {
      arcs[a].code_mean_m = sum[a] / cnt[a];
      arcs[a].code_rms_m = std::sqrt(sum2[a] / cnt[a]);
    }
    // Phase minus the code-derived clock (a standard diagnostic), ZWD from the code fit.
    std::vector<std::vector<double>> ts(n_arcs), rs(n_arcs);
    for (const auto& r : rows) {
      ts[r.arc_index].push_back(r.t);
      rs[r.arc_index].push_back(r.phase - x(r.epoch) - r.mw * x(k));
    }
    for (int a = 0; a < n_arcs; ++a) {
      double m = 0;
      for (double v : rs[a]) m += v;
      m /= rs[a].size();
      double s2 = 0;
      for (double v : rs[a]) s2 += (v - m) * (v - m);
      arcs[a].phase_codeclock_rms_m = std::sqrt(s2 / rs[a].size());
      arcs[a].phase_codeclock_drift_m = trendTimesDuration(ts[a], rs[a]);
    }
  }
  h.arcs = arcs;
  std::printf("%s: %d epochs, model %.0f us/epoch; ZWD fitted: phase %.3f m, code %.3f m\n", label, h.epochs,
              h.microseconds_per_epoch, h.zwd_phase_m, h.zwd_code_m);
  std::printf("  sat  arc  n  el[deg]     code mean/rms[m]   phase rms/drift[mm] (LSQ clock)  phase-codeclock rms/drift[mm]  wind-up first/last[cyc]\n");
  for (const auto& a : h.arcs) {
    std::printf("  %s %3u %3d  %4.1f-%4.1f  %7.3f %6.3f      %6.1f %7.1f              %7.1f %7.1f   %6.3f %6.3f\n",
                a.satellite.toString().c_str(), a.arc, a.n, a.min_el_deg, a.max_el_deg, a.code_mean_m, a.code_rms_m,
                a.phase_rms_m * 1e3, a.phase_drift_m * 1e3, a.phase_codeclock_rms_m * 1e3,
                a.phase_codeclock_drift_m * 1e3, a.windup_first_cycles, a.windup_last_cycles);
  }
  return h;
}

TEST(PppModelRealData, Zim2HourPhaseResidualsConstantPerArc) {
  PPP_REQUIRE_SHARED_DATA();
  test::LoadedDataset ds(test::zim2Dataset());
  const HourAnalysis h = analyseHour(ds, "ZIM2");
  EXPECT_EQ(h.epochs, 120);
  EXPECT_GT(h.zwd_phase_m, 0.0);
  EXPECT_LT(h.zwd_phase_m, 0.4);
  for (const auto& a : h.arcs) {
    if (a.n < 20) continue;  // short arcs: bias and trend poorly separated
    EXPECT_LT(a.phase_rms_m, 0.03) << a.satellite.toString();
    EXPECT_LT(std::abs(a.phase_drift_m), 0.05) << a.satellite.toString();
    EXPECT_LT(std::abs(a.code_mean_m), 0.8) << a.satellite.toString();
  }
}

TEST(PppModelRealData, Ccj2HourPhaseResidualsConstantPerArc) {
  PPP_REQUIRE_SHARED_DATA();
  test::LoadedDataset ds(test::ccj2Dataset());
  const HourAnalysis h = analyseHour(ds, "CCJ2");
  EXPECT_EQ(h.epochs, 120);
  for (const auto& a : h.arcs) {
    if (a.n < 20) continue;
    EXPECT_LT(a.phase_rms_m, 0.05) << a.satellite.toString();
    EXPECT_LT(std::abs(a.phase_drift_m), 0.08) << a.satellite.toString();
    EXPECT_LT(std::abs(a.code_mean_m), 0.6) << a.satellite.toString();
  }
}

}  // namespace
}  // namespace ppp
