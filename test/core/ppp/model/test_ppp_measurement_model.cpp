// PPP measurement model: Jacobian against central differences, known values
// (IF coefficients, Sagnac, receiver PCO IF combination from the ZIM2 ANTEX, the GPS
// receiver calibration standing in for Galileo on ESBC,
// eclipse and cutoff rejection), and a noise-free self-consistency test (data
// synthesised by the model itself: zero residuals at the truth, Gauss-Newton
// recovers the truth). Real products: ZIM2 (IGS final), ESBC (GRG) from ../shared/data.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <stdexcept>

#include <Eigen/Dense>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/models/ocean_loading.h"
#include "ppp_bayes_tree/models/solid_earth_tide.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/models/troposphere_gradient.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_dataset.h"

namespace ppp {
namespace {

constexpr double kF1 = 1575.42e6, kF2 = 1227.60e6;  // IS-GPS-200 3.3.1.1

struct Zim2Epoch {
  test::LoadedDataset ds;
  std::vector<DualFrequencyObservation> obs;
  std::vector<ArcId> arcs;
  ReceiverState truth;
  explicit Zim2Epoch(MeasurementModelOptions options = {}) : ds(test::zim2Dataset(), options) {
    SignalSelector selector(ds.reader->header(), {}, ds.biases.get());
    ObsEpoch epoch;
    ds.reader->next(epoch);
    ds.reader->next(epoch);  // second epoch: products cover the emission times
    obs = selector.select(epoch).observations;
    for (std::size_t i = 0; i < obs.size(); ++i) arcs.push_back(static_cast<ArcId>(i + 1));
    truth.position_ecef_m = ds.paths.truth_ecef_m;
    truth.zwd_m = 0.12;
    truth.setClock_m(GnssSystem::GPS, 123.4);
  }
};

TEST(PppMeasurementModel, IonosphereFreeCoefficientsGpsL1L2) {
  // GPS L1/L2 (IS-GPS-200): alpha = f1^2/(f1^2-f2^2) = 2.5457, beta = -1.5457.
  const auto f1 = carrierFrequency_hz(GnssSystem::GPS, '1');
  const auto f2 = carrierFrequency_hz(GnssSystem::GPS, '2');
  ASSERT_TRUE(f1 && f2);
  const auto k = ionosphereFreeCoefficients(*f1, *f2);
  EXPECT_NEAR(k.alpha, 2.5457, 5e-5);
  EXPECT_NEAR(k.beta, -1.5457, 5e-5);
  // Wind-up weight in the IF phase: alpha lambda1 + beta lambda2 = c/(f1+f2) = 0.1070 m (narrow lane).
  EXPECT_NEAR(k.alpha * kSpeedOfLight_mps / kF1 + k.beta * kSpeedOfLight_mps / kF2, 0.10695, 1e-5);
}

TEST(PppMeasurementModel, ReceiverPcoIonosphereFreeFromZim2Antex) {
  PPP_REQUIRE_SHARED_DATA();
  test::LoadedDataset ds(test::zim2Dataset());
  // igs20_zim2_gps_trim.atx, TRM59800.00 NONE: G01 NORTH/EAST/UP 0.65 1.35 89.35 mm
  // (line 844), G02 -0.24 0.00 117.76 mm (line 1229). IF = 2.5457 x G01 - 1.5457 x G02:
  // N 2.0257, E 3.4367, U 45.436 mm.
  const auto pco = ds.model->receiverPcoIonosphereFree_m(GnssSystem::GPS, 1, 2, kF1, kF2);
  ASSERT_TRUE(pco);
  EXPECT_NEAR(pco->x(), 2.0257e-3, 2e-6);
  EXPECT_NEAR(pco->y(), 3.4367e-3, 2e-6);
  EXPECT_NEAR(pco->z(), 45.436e-3, 2e-5);
}

TEST(PppMeasurementModel, JacobianMatchesCentralDifferences) {
  PPP_REQUIRE_SHARED_DATA();
  Zim2Epoch z;
  ReceiverState x0 = z.truth;
  x0.position_ecef_m += Eigen::Vector3d(3.0, -2.0, 1.5);
  const EpochMeasurements base = z.ds.model->evaluate(z.obs, z.arcs, x0, nullptr);
  ASSERT_GE(base.used.size(), 8u);
  const ReceiverStateLayout& layout = x0.layout;
  ASSERT_EQ(layout.dim(), 5);  // GPS only: x, y, z, zwd, clock
  const std::vector<double> steps = {0.5, 0.5, 0.5, 0.05, 1.0};
  for (int j = 0; j < layout.dim(); ++j) {
    auto v = x0.vector();
    v(j) += steps[j];
    const auto plus = z.ds.model->evaluate(z.obs, z.arcs, ReceiverState::fromVector(v), nullptr);
    v(j) -= 2.0 * steps[j];
    const auto minus = z.ds.model->evaluate(z.obs, z.arcs, ReceiverState::fromVector(v), nullptr);
    ASSERT_EQ(plus.used.size(), base.used.size());
    ASSERT_EQ(minus.used.size(), base.used.size());
    for (std::size_t i = 0; i < base.used.size(); ++i) {
      const double dc = (plus.used[i].predicted_code_m - minus.used[i].predicted_code_m) / (2.0 * steps[j]);
      const double dp = (plus.used[i].predicted_phase_m - minus.used[i].predicted_phase_m) / (2.0 * steps[j]);
      // Position: the neglected elevation dependence of mapping/PCV and the
      // Sagnac rotation are ~1e-5 relative; ZWD and clock enter linearly.
      const double tol = layout.isPosition(j) ? 2e-5 : 1e-7;
      EXPECT_NEAR(dc, base.used[i].jacobian(j), tol) << base.used[i].satellite.toString() << " column " << j;
      EXPECT_NEAR(dp, base.used[i].jacobian(j), tol) << base.used[i].satellite.toString() << " column " << j;
    }
  }
  // Position rows are unit vectors (minus line of sight); the clock column is 1.
  for (const auto& m : base.used) {
    EXPECT_NEAR(m.jacobian.head<3>().norm(), 1.0, 2e-3);  // unit LOS + the dry-delay height term
    EXPECT_EQ(m.jacobian(layout.clock(GnssSystem::GPS)), 1.0);
    EXPECT_GT(m.jacobian(layout.zwd()), 1.0);  // wet mapping >= 1 above the horizon
  }
}

TEST(PppMeasurementModel, TroposphereGradientsAddChenHerringDelayWithMatchingJacobian) {
  PPP_REQUIRE_SHARED_DATA();
  Zim2Epoch z;
  const ReceiverStateLayout layout({GnssSystem::GPS}, true);
  ReceiverState x0(layout);
  x0.position_ecef_m = z.truth.position_ecef_m;
  x0.zwd_m = z.truth.zwd_m;
  x0.setClock_m(GnssSystem::GPS, z.truth.clock_m(GnssSystem::GPS));
  x0.gradient_north_m = 0.0015;
  x0.gradient_east_m = -0.0008;
  std::vector<ModelTerms> terms;
  EpochMeasurements with;
  z.ds.model->evaluate(z.obs, z.arcs, x0, nullptr, with, &terms);
  const EpochMeasurements without = z.ds.model->evaluate(z.obs, z.arcs, z.truth, nullptr);
  ASSERT_GE(with.used.size(), 8u);
  ASSERT_EQ(with.used.size(), without.used.size());
  ASSERT_EQ(terms.size(), with.used.size());
  for (std::size_t i = 0; i < with.used.size(); ++i) {
    const SatelliteMeasurement& m = with.used[i];
    ASSERT_EQ(m.jacobian.size(), layout.dim());
    // The gradient term, and only it, separates the two predictions.
    const double expected = slantGradientDelay_m(m.elevation_rad, m.azimuth_rad, 0.0015, -0.0008);
    EXPECT_NEAR(m.predicted_code_m - without.used[i].predicted_code_m, expected, 1e-6) << m.satellite.toString();
    EXPECT_NEAR(m.predicted_phase_m - without.used[i].predicted_phase_m, expected, 1e-6) << m.satellite.toString();
    EXPECT_NEAR(terms[i].troposphere_gradient_m, expected, 1e-12);
    // The other columns are the model's without gradients.
    EXPECT_LT((m.jacobian.head(without.used[i].jacobian.size()) - without.used[i].jacobian).norm(), 1e-12);
  }
  // Gradient columns against central differences (the delay is linear in the gradients).
  for (const int j : {layout.gradientNorth(), layout.gradientEast()}) {
    const double step = 0.01;
    auto v = x0.vector();
    v(j) += step;
    const auto plus = z.ds.model->evaluate(z.obs, z.arcs, ReceiverState::fromVector(v, layout), nullptr);
    v(j) -= 2.0 * step;
    const auto minus = z.ds.model->evaluate(z.obs, z.arcs, ReceiverState::fromVector(v, layout), nullptr);
    ASSERT_EQ(plus.used.size(), with.used.size());
    ASSERT_EQ(minus.used.size(), with.used.size());
    for (std::size_t i = 0; i < with.used.size(); ++i) {
      const double dc = (plus.used[i].predicted_code_m - minus.used[i].predicted_code_m) / (2.0 * step);
      const double dp = (plus.used[i].predicted_phase_m - minus.used[i].predicted_phase_m) / (2.0 * step);
      EXPECT_NEAR(dc, with.used[i].jacobian(j), 1e-6) << with.used[i].satellite.toString() << " column " << j;
      EXPECT_NEAR(dp, with.used[i].jacobian(j), 1e-6) << with.used[i].satellite.toString() << " column " << j;
    }
  }
  // m_g cos a and m_g sin a: the north and east columns' squares add to m_g^2.
  for (const auto& m : with.used) {
    const double m_g = gradientMapping(m.elevation_rad);
    EXPECT_NEAR(std::hypot(m.jacobian(layout.gradientNorth()), m.jacobian(layout.gradientEast())), m_g, 1e-9);
    EXPECT_NEAR(m.jacobian(layout.gradientNorth()), m_g * std::cos(m.azimuth_rad), 1e-9);
  }
}

TEST(PppMeasurementModel, SagnacSizeMatchesClosedForm) {
  PPP_REQUIRE_SHARED_DATA();
  Zim2Epoch z;
  EpochMeasurements em;
  std::vector<ModelTerms> terms;
  z.ds.model->evaluate(z.obs, z.arcs, z.truth, nullptr, em, &terms);
  ASSERT_FALSE(terms.empty());
  for (const auto& t : terms) {
    // omega_e (x_s y_r - y_s x_r) / c (signal_geometry.h, IS-GPS-200 20.3.3.4.3.4):
    // up to ~40 m for GPS; the rotation-based value agrees to the mm.
    const double closed = sagnacCorrection_m(t.satellite_apc_at_transmission_ecef_m, t.receiver_apc_ecef_m);
    EXPECT_NEAR(t.sagnac_m, closed, 1e-3) << t.satellite.toString();
    EXPECT_LT(std::abs(t.sagnac_m), 40.0);
    EXPECT_GT(t.geometric_range_m, 1.9e7);
    EXPECT_LT(t.geometric_range_m, 2.6e7);
  }
}

TEST(PppMeasurementModel, EclipsingSatelliteRejectedUnlessAllowed) {
  PPP_REQUIRE_SHARED_DATA();
  // G05 is in the Earth's shadow at 2026-05-13 00:00 (seen in the ZIM2 first epoch).
  Zim2Epoch z;
  const auto em = z.ds.model->evaluate(z.obs, z.arcs, z.truth, nullptr);
  bool rejected = false;
  for (const auto& r : em.rejected) {
    if (r.satellite.toString() == "G05") {
      rejected = true;
      EXPECT_NE(r.detail.find("eclipse"), std::string::npos) << r.detail;
    }
  }
  EXPECT_TRUE(rejected);
  MeasurementModelOptions o;
  o.exclude_eclipse = false;
  Zim2Epoch z2(o);
  const auto em2 = z2.ds.model->evaluate(z2.obs, z2.arcs, z2.truth, nullptr);
  bool used = false;
  for (const auto& m : em2.used) used = used || m.satellite.toString() == "G05";
  EXPECT_TRUE(used);
}

TEST(PppMeasurementModel, ElevationCutoffAndWeights) {
  PPP_REQUIRE_SHARED_DATA();
  MeasurementModelOptions o;
  o.elevation_cutoff_rad = 30.0 * kDegToRad;
  Zim2Epoch z(o);
  const auto em = z.ds.model->evaluate(z.obs, z.arcs, z.truth, nullptr);
  std::size_t below = 0;
  for (const auto& r : em.rejected) below += r.detail.find("below cutoff 30.0 deg") != std::string::npos;
  EXPECT_GE(below, 3u);  // G10, G12, G13, G30 are below 15 deg (see the real-data test output)
  const double factor = ionosphereFreeNoiseFactor(ionosphereFreeCoefficients(kF1, kF2));
  EXPECT_NEAR(factor, 2.978, 1e-3);
  for (const auto& m : em.used) {
    EXPECT_GE(m.elevation_rad, o.elevation_cutoff_rad);
    // sigma / sin(el): 0.003 m x 2.978 (IF) at zenith, code = 300 x phase (MeasurementModelOptions default).
    EXPECT_NEAR(m.phase_sigma_m, 0.003 * factor / std::sin(m.elevation_rad), 1e-12);
    EXPECT_NEAR(m.code_sigma_m, 300.0 * m.phase_sigma_m, 1e-12);
  }
}

/// Replaces the observations by the model's own predictions at `truth` (phase
/// plus a bias per arc), iterating because the emission time uses the code.
void synthesise(const PppMeasurementModel& model, std::vector<DualFrequencyObservation>& obs,
                const std::vector<ArcId>& arcs, const ReceiverState& truth, std::vector<double>& bias_m) {
  bias_m.assign(obs.size(), 0.0);
  for (int it = 0; it < 4; ++it) {
    const auto em = model.evaluate(obs, arcs, truth, nullptr);
    for (const auto& m : em.used) {
      for (std::size_t i = 0; i < obs.size(); ++i) {
        if (obs[i].satellite != m.satellite) continue;
        bias_m[i] = 1.25 * static_cast<double>(i) - 3.0;
        const double phase_m = m.predicted_phase_m + bias_m[i];
        // Equal values on both frequencies: the IF combination returns them (alpha + beta = 1).
        obs[i].code1_m = obs[i].code2_m = m.predicted_code_m;
        obs[i].phase1_cycles = phase_m * obs[i].frequency1_hz / kSpeedOfLight_mps;
        obs[i].phase2_cycles = phase_m * obs[i].frequency2_hz / kSpeedOfLight_mps;
      }
    }
  }
}

TEST(PppMeasurementModel, NoiseFreeSelfConsistencyAndGaussNewton) {
  PPP_REQUIRE_SHARED_DATA();
  Zim2Epoch z;
  std::vector<double> bias;
  synthesise(*z.ds.model, z.obs, z.arcs, z.truth, bias);
  const auto at_truth = z.ds.model->evaluate(z.obs, z.arcs, z.truth, nullptr);
  ASSERT_GE(at_truth.used.size(), 8u);
  for (const auto& m : at_truth.used) {
    std::size_t i = 0;
    while (z.obs[i].satellite != m.satellite) ++i;
    EXPECT_NEAR(m.codeResidual_m(), 0.0, 1e-6) << m.satellite.toString();
    EXPECT_NEAR(m.phaseResidualWithoutBias_m() - bias[i], 0.0, 1e-6) << m.satellite.toString();
  }
  // Gauss-Newton on this one epoch, code and (known-bias) phase, from 30 m away.
  ReceiverState x = z.truth;
  x.position_ecef_m += Eigen::Vector3d(20.0, -15.0, 16.0);
  x.zwd_m = 0.0;
  x.setClock_m(GnssSystem::GPS, 0.0);
  for (int it = 0; it < 8; ++it) {
    const auto em = z.ds.model->evaluate(z.obs, z.arcs, x, nullptr);
    const int n = static_cast<int>(em.used.size());
    Eigen::MatrixXd h(2 * n, x.layout.dim());
    Eigen::VectorXd r(2 * n);
    for (int k = 0; k < n; ++k) {
      const auto& m = em.used[k];
      std::size_t i = 0;
      while (z.obs[i].satellite != m.satellite) ++i;
      h.row(2 * k) = m.jacobian / m.code_sigma_m;
      r(2 * k) = m.codeResidual_m() / m.code_sigma_m;
      h.row(2 * k + 1) = m.jacobian / m.phase_sigma_m;
      r(2 * k + 1) = (m.phaseResidualWithoutBias_m() - bias[i]) / m.phase_sigma_m;
    }
    const Eigen::VectorXd dx = h.colPivHouseholderQr().solve(r);
    x = ReceiverState::fromVector(x.vector() + dx);
  }
  EXPECT_LT((x.position_ecef_m - z.truth.position_ecef_m).norm(), 1e-3);
  EXPECT_NEAR(x.zwd_m, z.truth.zwd_m, 1e-3);
  EXPECT_NEAR(x.clock_m(GnssSystem::GPS), z.truth.clock_m(GnssSystem::GPS), 1e-3);
}

/// Every number of two evaluations, exactly (EXPECT_EQ on doubles: bit for bit).
void expectSameMeasurements(const EpochMeasurements& a, const EpochMeasurements& b) {
  ASSERT_EQ(a.used.size(), b.used.size());
  ASSERT_EQ(a.rejected.size(), b.rejected.size());
  for (std::size_t k = 0; k < a.used.size(); ++k) {
    const SatelliteMeasurement &x = a.used[k], &y = b.used[k];
    const std::string sat = x.satellite.toString();
    EXPECT_EQ(x.satellite, y.satellite);
    EXPECT_EQ(x.predicted_code_m, y.predicted_code_m) << sat;
    EXPECT_EQ(x.predicted_phase_m, y.predicted_phase_m) << sat;
    EXPECT_EQ(x.observed_code_m, y.observed_code_m) << sat;
    EXPECT_EQ(x.code_sigma_m, y.code_sigma_m) << sat;
    EXPECT_EQ(x.elevation_rad, y.elevation_rad) << sat;
    EXPECT_EQ(x.azimuth_rad, y.azimuth_rad) << sat;
    ASSERT_EQ(x.jacobian.size(), y.jacobian.size());
    for (Eigen::Index i = 0; i < x.jacobian.size(); ++i) EXPECT_EQ(x.jacobian(i), y.jacobian(i)) << sat << " " << i;
    ASSERT_TRUE(x.satellite_apc_ecef_m && y.satellite_apc_ecef_m);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ((*x.satellite_apc_ecef_m)(i), (*y.satellite_apc_ecef_m)(i)) << sat;
      EXPECT_EQ(x.receiver_apc_offset_ecef_m(i), y.receiver_apc_offset_ecef_m(i)) << sat;
    }
  }
}

TEST(PppMeasurementModel, EvaluatingAgainGivesAFreshModelsNumbersBitForBit) {
  // The model keeps each satellite's last emission ephemeris and its last per-epoch
  // terms, for an epoch linearised again. Whatever it evaluated before, its numbers
  // must be a fresh model's, and a changed code (another emission time) must not
  // take the kept ephemeris.
  PPP_REQUIRE_SHARED_DATA();
  Zim2Epoch used, fresh;
  ReceiverState x1 = used.truth, x2 = used.truth;
  x1.position_ecef_m += Eigen::Vector3d(3.0, -2.0, 1.5);
  x2.position_ecef_m += Eigen::Vector3d(-0.4, 0.7, 0.2);
  x2.zwd_m = 0.2;
  (void)used.ds.model->evaluate(used.obs, used.arcs, x1, nullptr);
  (void)used.ds.model->evaluate(used.obs, used.arcs, x2, nullptr);
  const EpochMeasurements again = used.ds.model->evaluate(used.obs, used.arcs, x2, nullptr);
  ASSERT_GE(again.used.size(), 8u);
  expectSameMeasurements(again, fresh.ds.model->evaluate(fresh.obs, fresh.arcs, x2, nullptr));
  // The same observations with one code 300 m longer (~1 us earlier emission).
  std::vector<DualFrequencyObservation> changed = used.obs;
  changed[0].code1_m += 300.0;
  changed[0].code2_m += 300.0;
  Zim2Epoch other;
  expectSameMeasurements(used.ds.model->evaluate(changed, used.arcs, x2, nullptr),
                         other.ds.model->evaluate(changed, other.arcs, x2, nullptr));
}

// An epoch's observed IF code and phase depend on the observations alone: computed
// once (observedIonosphereFree) and given to each linearisation, they are the
// model's own numbers bit for bit, and the model takes them as given.
TEST(PppMeasurementModel, TheEpochsObservedIonosphereFreeComputedOnceIsTheModelsOwn) {
  PPP_REQUIRE_SHARED_DATA();
  Zim2Epoch z;
  std::vector<ObservedIonosphereFree> observed;
  observedIonosphereFree(z.obs, observed);
  ASSERT_EQ(observed.size(), z.obs.size());
  ReceiverState x = z.truth;
  x.position_ecef_m += Eigen::Vector3d(3.0, -2.0, 1.5);
  EpochMeasurements own, given;
  z.ds.model->evaluate(z.obs, z.arcs, x, nullptr, own);
  z.ds.model->evaluate(z.obs, observed, z.arcs, x, nullptr, given);
  ASSERT_GE(own.used.size(), 8u);
  expectSameMeasurements(own, given);
  for (std::size_t k = 0; k < own.used.size(); ++k)
    EXPECT_EQ(own.used[k].observed_phase_m, given.used[k].observed_phase_m) << own.used[k].satellite.toString();
  // The start model likewise, from the Earth centre.
  ReceiverState centre = z.truth;
  centre.position_ecef_m.setZero();
  EpochMeasurements start_own, start_given;
  z.ds.model->evaluateStart(z.obs, centre, start_own);
  z.ds.model->evaluateStart(z.obs, observed, centre, start_given);
  ASSERT_EQ(start_own.used.size(), start_given.used.size());
  ASSERT_GE(start_own.used.size(), 8u);
  for (std::size_t k = 0; k < start_own.used.size(); ++k) {
    EXPECT_EQ(start_own.used[k].observed_code_m, start_given.used[k].observed_code_m);
    EXPECT_EQ(start_own.used[k].observed_phase_m, start_given.used[k].observed_phase_m);
    EXPECT_EQ(start_own.used[k].predicted_code_m, start_given.used[k].predicted_code_m);
  }
  // The given phase is the one used (that of the first satellite used).
  std::size_t first = 0;
  while (z.obs[first].satellite != own.used.front().satellite) ++first;
  observed[first].phase_m += 0.5;
  z.ds.model->evaluate(z.obs, observed, z.arcs, x, nullptr, given);
  ASSERT_EQ(given.used.front().satellite, own.used.front().satellite);
  EXPECT_EQ(given.used.front().observed_phase_m, own.used.front().observed_phase_m + 0.5);
  // Not one per observation: refused.
  observed.pop_back();
  EXPECT_THROW(z.ds.model->evaluate(z.obs, observed, z.arcs, x, nullptr, given), std::invalid_argument);
  EXPECT_THROW(z.ds.model->evaluateStart(z.obs, observed, centre, start_given), std::invalid_argument);
}

TEST(PppMeasurementModel, WindupContinuityAndArcReset) {
  PPP_REQUIRE_SHARED_DATA();
  Zim2Epoch z;
  WindupTracker tracker;
  EpochMeasurements em;
  std::vector<ModelTerms> t1, t2;
  z.ds.model->evaluate(z.obs, z.arcs, z.truth, &tracker, em, &t1);
  ASSERT_FALSE(t1.empty());
  const SatelliteId s = t1.front().satellite;
  ASSERT_TRUE(tracker.previous(s, z.arcs[0]).has_value() || s != z.obs[0].satellite);
  // Pretend the previous value was 7 cycles more: the next value follows it
  // (continuity adds whole cycles), while a new arc id starts from [-0.5, 0.5].
  for (std::size_t i = 0; i < z.obs.size(); ++i) {
    if (z.obs[i].satellite == s) tracker.update(s, z.arcs[i], t1.front().windup_cycles + 7.0);
  }
  z.ds.model->evaluate(z.obs, z.arcs, z.truth, &tracker, em, &t2);
  EXPECT_NEAR(t2.front().windup_cycles, t1.front().windup_cycles + 7.0, 1e-9);
  auto new_arcs = z.arcs;
  for (auto& a : new_arcs) a += 1000;
  z.ds.model->evaluate(z.obs, new_arcs, z.truth, &tracker, em, &t2);
  EXPECT_NEAR(t2.front().windup_cycles, t1.front().windup_cycles, 1e-9);
  EXPECT_LE(std::abs(t2.front().windup_cycles), 0.5);
}

TEST(PppMeasurementModel, StationDisplacementsMoveTheAntennaPhaseCentre) {
  PPP_REQUIRE_SHARED_DATA();
  // Solid tide (IERS 2010 step 1) and ocean loading (BLQ) move the receiver
  // antenna phase centre by exactly their displacement; the marker (the state)
  // stays where it is.
  MeasurementModelOptions off;
  off.solid_earth_tide = false;
  Zim2Epoch z_off(off);
  Zim2Epoch z_on;
  EpochMeasurements em;
  std::vector<ModelTerms> t_off, t_on;
  z_off.ds.model->evaluate(z_off.obs, z_off.arcs, z_off.truth, nullptr, em, &t_off);
  z_on.ds.model->evaluate(z_on.obs, z_on.arcs, z_on.truth, nullptr, em, &t_on);
  ASSERT_FALSE(t_on.empty());
  const GnssTime t = z_on.obs.front().time;
  const auto sm = sunMoonPositionsEcef(t);
  const Eigen::Vector3d tide = solidEarthTideDisplacementEcef_m(z_on.truth.position_ecef_m, sm.sun_ecef_m, sm.moon_ecef_m);
  EXPECT_GT(tide.norm(), 0.01);  // decimetre-level body tide, far from zero
  const Eigen::Vector3d moved = t_on.front().receiver_apc_ecef_m - t_off.front().receiver_apc_ecef_m;
  EXPECT_NEAR((moved - tide).norm(), 0.0, 1e-9);

  // Ocean loading: a synthetic BLQ record with 1 cm radial M2 only.
  OceanLoadingCoefficients blq;
  blq.station = "TEST";
  blq.amplitude_radial_m[0] = 0.01;
  blq.phase_radial_deg[0] = 30.0;
  std::vector<AntexSource> antex;
  antex.push_back({"zim2", readAntexFile(z_on.ds.paths.atx[0])});
  PppMeasurementModel with_ol(z_on.ds.products, std::make_shared<AntexCalibrations>(std::move(antex)), ReceiverAntenna::fromHeader(z_on.ds.reader->header()),
                              &blq, {});
  std::vector<ModelTerms> t_ol;
  with_ol.evaluate(z_on.obs, z_on.arcs, z_on.truth, nullptr, em, &t_ol);
  const Geodetic g = ecefToGeodetic(z_on.truth.position_ecef_m);
  const Eigen::Vector3d ol_enu = oceanLoadingDisplacementEnu_m(blq, t);
  const Eigen::Vector3d ol = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).transpose() * ol_enu;
  EXPECT_GT(std::abs(ol_enu.z()), 1e-4);
  EXPECT_NEAR((t_ol.front().receiver_apc_ecef_m - t_on.front().receiver_apc_ecef_m - ol).norm(), 0.0, 1e-9);
}

// ESBC (ASH701945E_M SCIS of igs05_esbc_receiver_trim.atx: G01/G02 only),
// GPS + Galileo, GRG products, the IGS14 satellite antennas (Galileo ones
// included): with the default substitution the Galileo satellites get the
// receiver PCO of G01/G02 in their own E1/E5a ionosphere-free combination and a
// receiver PCV, named in one note; with "none" they get neither, and the
// "missing" warning instead.
struct EsbcGalileoEpoch {
  std::unique_ptr<RinexObsReader> reader;
  PreciseEphemeris products;
  std::unique_ptr<PppMeasurementModel> model;
  std::vector<DualFrequencyObservation> obs;
  std::vector<ArcId> arcs;
  ReceiverState state{ReceiverStateLayout({GnssSystem::GPS, GnssSystem::Galileo})};
  GnssTime time;

  static std::string esbc(const std::string& file) { return test::dataPath("esbc-2020-177/" + file); }
  /// The epoch_index-th epoch of the day (30 s: 1410 = 11:45:00).
  explicit EsbcGalileoEpoch(ReceiverFrequencySubstitution substitution,
                            YawManoeuvreHandling yaw = YawManoeuvreHandling::Model, int epoch_index = 1)
      : reader(std::make_unique<RinexObsReader>(RinexObsReader::open(esbc("ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz")))),
        products(PreciseEphemeris::load({esbc("GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz")},
                                        {esbc("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz")})) {
    std::vector<AntexSource> antex;
    for (const std::string name : {"igs14_2178_satellites.atx", "igs05_esbc_receiver_trim.atx"})
      antex.push_back({name, readAntexFile(test::dataPath("antex/" + name))});
    MeasurementModelOptions options;
    options.receiver_frequency_substitution = substitution;
    options.yaw_manoeuvre = yaw;
    model = std::make_unique<PppMeasurementModel>(products, std::make_shared<AntexCalibrations>(std::move(antex)),
                                                  ReceiverAntenna::fromHeader(reader->header()), nullptr, options);
    SignalSelectionOptions selection;
    selection.systems = {GnssSystem::GPS, GnssSystem::Galileo};
    selection.systems_from_products = false;
    SignalSelector selector(reader->header(), selection, nullptr);
    ObsEpoch epoch;
    for (int i = 0; i <= epoch_index; ++i) reader->next(epoch);
    time = epoch.time;
    obs = selector.select(epoch).observations;
    for (std::size_t i = 0; i < obs.size(); ++i) arcs.push_back(static_cast<ArcId>(i + 1));
    state.position_ecef_m = *reader->header().approx_position_ecef_m;
    state.zwd_m = 0.1;
  }
  /// Terms of the used satellites of one system (and the epoch's measurements).
  std::vector<ModelTerms> terms(GnssSystem system, EpochMeasurements* measurements = nullptr) const {
    std::vector<ModelTerms> all, out;
    EpochMeasurements local;
    EpochMeasurements& em = measurements ? *measurements : local;
    model->evaluate(obs, arcs, state, nullptr, em, &all);
    for (const auto& t : all)
      if (t.satellite.system == system) out.push_back(t);
    return out;
  }
};

TEST(PppMeasurementModel, GalileoTakesTheGpsReceiverCalibrationOnEsbc) {
  PPP_REQUIRE_SHARED_DATA();
  EsbcGalileoEpoch gps_values(ReceiverFrequencySubstitution::Gps);
  EsbcGalileoEpoch none(ReceiverFrequencySubstitution::None);
  const auto gps_sats = gps_values.terms(GnssSystem::GPS);
  const auto galileo = gps_values.terms(GnssSystem::Galileo);
  const auto galileo_none = none.terms(GnssSystem::Galileo);
  ASSERT_GE(gps_sats.size(), 5u);
  ASSERT_GE(galileo.size(), 4u);
  // "none" (warn): used uncorrected; with the GPS values a Galileo satellite below
  // the calibration's grid (igs05: zenith 0-80 deg) is rejected like a GPS one.
  ASSERT_GE(galileo_none.size(), galileo.size());

  // Expected: igs05_esbc_receiver_trim.atx ASH701945E_M SCIS G01/G02 PCOs in the
  // E1/E5a ionosphere-free combination (alpha 2.2606), against GPS's L1/L2 one.
  const AntennaCalibration* rx = gps_values.model->receiverCalibration();
  ASSERT_NE(rx, nullptr);
  ASSERT_EQ(rx->frequency(GnssSystem::Galileo, 1), nullptr);  // the file holds GPS only
  const Eigen::Vector3d g1 = rx->frequency(GnssSystem::GPS, 1)->pco_m, g2 = rx->frequency(GnssSystem::GPS, 2)->pco_m;
  const Eigen::Vector3d neu_gps = ionosphereFreeOffset(g1, g2, ionosphereFreeCoefficients(kF1, kF2));
  const Eigen::Vector3d neu_gal = ionosphereFreeOffset(g1, g2, ionosphereFreeCoefficients(kF1, 1176.45e6));
  const Geodetic geo = ecefToGeodetic(gps_values.state.position_ecef_m);
  const Eigen::Matrix3d ecef_from_enu = rotationEnuFromEcef(geo.latitude_rad, geo.longitude_rad).transpose();
  const auto enu = [](const Eigen::Vector3d& neu) { return Eigen::Vector3d(neu.y(), neu.x(), neu.z()); };
  const Eigen::Vector3d gps_apc = gps_sats.front().receiver_apc_ecef_m;
  for (std::size_t i = 0; i < galileo.size(); ++i) {
    EXPECT_NEAR((galileo[i].receiver_apc_ecef_m - gps_apc - ecef_from_enu * enu(neu_gal - neu_gps)).norm(), 0.0, 1e-9)
        << galileo[i].satellite.toString();
    EXPECT_NE(galileo[i].receiver_pcv_m, 0.0) << galileo[i].satellite.toString();
  }
  for (const auto& t : galileo_none) {
    // "none": no receiver PCO (the station displacements only) and no PCV.
    EXPECT_NEAR((t.receiver_apc_ecef_m - gps_apc + ecef_from_enu * enu(neu_gps)).norm(), 0.0, 1e-9);
    EXPECT_EQ(t.receiver_pcv_m, 0.0);
  }
  EXPECT_GT(neu_gal.z(), 0.03);  // several centimetres up that "none" leaves in the Galileo ranges

  // One note naming the substitution (the model evaluated twice above: still one).
  gps_values.terms(GnssSystem::Galileo);
  const auto& notes = gps_values.model->receiverAntennaWarnings();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0],
            "receiver antenna ASH701945E_M SCIS: no Galileo calibration, GPS L1/L2 values used for E1/E5a "
            "(measurement_model.corrections.receiver_frequency_substitution: gps)");
  const auto& missing = none.model->receiverAntennaWarnings();
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0].find("missing receiver antenna calibration for ASH701945E_M SCIS E01/E05"), 0u) << missing[0];
}

// G26 (Block IIF) on the ESBC day passed orbit noon at beta = -1.2 deg near
// 11:40 (GRG orbit): its nominal yaw swings through 180 deg at up to 0.4 deg/s,
// the satellite turns at 0.11 deg/s (yaw_manoeuvre.h). At 11:45:00 (x = +2.3
// deg past noon) the rate-limited yaw, 31.7 deg at the turn's start x_s =
// -1.945 deg plus 0.11 deg/s over (1.945 + 2.3) / 0.0083566 = 508 s, is 87 deg,
// the nominal one atan2(-tan beta, sin mu) = 152 deg: 65 deg apart, a wind-up
// difference of about 65 / 360 = 0.18 cycle. Satellites far from their turn
// are modelled the same either way; "exclude" leaves G26 out with the reason.
TEST(PppMeasurementModel, NoonTurnOfG26OnEsbcTakesTheRateLimitedYaw) {
  PPP_REQUIRE_SHARED_DATA();
  EsbcGalileoEpoch model(ReceiverFrequencySubstitution::Gps, YawManoeuvreHandling::Model, 1410);
  EsbcGalileoEpoch nominal(ReceiverFrequencySubstitution::Gps, YawManoeuvreHandling::Nominal, 1410);
  EsbcGalileoEpoch exclude(ReceiverFrequencySubstitution::Gps, YawManoeuvreHandling::Exclude, 1410);
  ASSERT_EQ(model.time.toCalendar().hour, 11);
  ASSERT_EQ(model.time.toCalendar().minute, 45);
  const auto by_satellite = [](const std::vector<ModelTerms>& terms) {
    std::map<std::string, ModelTerms> m;
    for (const ModelTerms& t : terms) m[t.satellite.toString()] = t;
    return m;
  };
  const auto m = by_satellite(model.terms(GnssSystem::GPS));
  const auto n = by_satellite(nominal.terms(GnssSystem::GPS));
  ASSERT_TRUE(m.count("G26") && n.count("G26"));
  const double dwindup = std::remainder(m.at("G26").windup_cycles - n.at("G26").windup_cycles, 1.0);
  EXPECT_GT(std::abs(dwindup), 0.12);
  EXPECT_LT(std::abs(dwindup), 0.24);
  EXPECT_GT((m.at("G26").satellite_reference_offset_ecef_m - n.at("G26").satellite_reference_offset_ecef_m).norm(),
            0.1);  // the IIF's 0.39 m x offset turned by 65 deg: 2 * 0.39 * sin(32.5 deg) = 0.42 m in the IF
  for (const auto& [sat, t] : n) {
    if (sat == "G26") continue;
    ASSERT_TRUE(m.count(sat)) << sat;
    EXPECT_EQ(m.at(sat).windup_cycles, t.windup_cycles) << sat;
  }
  EpochMeasurements excluded;
  const auto e = by_satellite(exclude.terms(GnssSystem::GPS, &excluded));
  EXPECT_FALSE(e.count("G26"));
  EXPECT_EQ(e.size(), n.size() - 1);
  bool named = false;
  for (const RejectedSatellite& r : excluded.rejected)
    named = named || (r.satellite.toString() == "G26" && r.reason == RejectionReason::YawManoeuvre);
  EXPECT_TRUE(named);
}

}  // namespace
}  // namespace ppp
