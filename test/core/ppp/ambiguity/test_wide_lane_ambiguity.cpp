// Wide-lane ambiguities from Melbourne-Wuebbena means with satellite OSBs, and
// the product rule that decides whether narrow-lane fixing is allowed. Real
// data: CCJ2 with the WUM ABS.BIA phase OSBs (single-differenced wide lanes
// near integers only once the satellite biases are removed), ZIM2 with CODE's
// OSBs (clock-free wide lane fine; narrow lane refused by the product rule).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <sstream>

#include "ppp_dataset.h"
#include "table_biases.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/ppp/ambiguity/phase_bias_consistency.h"
#include "ppp_bayes_tree/ppp/ambiguity/wide_lane_ambiguity.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

constexpr double kF1 = 1575.42e6, kF2 = 1227.60e6;  // GPS L1/L2 (IS-GPS-200)

DualFrequencyObservation makeObservation(const SatelliteId& sat, double range_m, int n1, int n2) {
  DualFrequencyObservation o;
  o.satellite = sat;
  o.code1 = *ObservationCode::parse("C1W");
  o.code2 = *ObservationCode::parse("C2W");
  o.phase1 = *ObservationCode::parse("L1C");
  o.phase2 = *ObservationCode::parse("L2W");
  o.frequency1_hz = kF1;
  o.frequency2_hz = kF2;
  o.code1_m = o.code2_m = range_m;
  o.phase1_cycles = range_m * kF1 / kSpeedOfLight_mps + n1;
  o.phase2_cycles = range_m * kF2 / kSpeedOfLight_mps + n2;
  return o;
}

TEST(WideLaneAmbiguity, MelbourneWuebbenaOfCleanObservationsIsTheWideLaneInteger) {
  // Geometry cancels: range only, ambiguities (N1, N2) -> MW = N1 - N2.
  const SatelliteId g05{GnssSystem::GPS, 5};
  EXPECT_NEAR(melbourneWuebbena_cycles(makeObservation(g05, 2.2e7, 17, 4)), 13.0, 1e-6);
  EXPECT_NEAR(wideLaneWavelength_m(kF1, kF2), 0.8619, 1e-4);  // 86.2 cm
}

TEST(WideLaneAmbiguity, SatelliteOsbsAreRemovedWithTheBiasSinexSign) {
  const SatelliteId g05{GnssSystem::GPS, 5};
  DualFrequencyObservation o = makeObservation(g05, 2.2e7, 17, 4);
  // Observed = true + bias: a phase OSB of 0.1 m on L1 adds 0.1 / lambda1 cycles.
  TableBiases b;
  b.table[{g05, "L1C"}] = 0.1;
  b.table[{g05, "L2W"}] = -0.05;
  b.table[{g05, "C1W"}] = 1.5;
  b.table[{g05, "C2W"}] = 2.5;
  o.phase1_cycles += 0.1 * kF1 / kSpeedOfLight_mps;
  o.phase2_cycles += -0.05 * kF2 / kSpeedOfLight_mps;
  o.code1_m += 1.5;
  o.code2_m += 2.5;
  EXPECT_GT(std::abs(melbourneWuebbena_cycles(o) - 13.0), 0.1);
  const auto mw = correctedMelbourneWuebbena(o, &b);
  ASSERT_TRUE(mw.mw_cycles.has_value());
  EXPECT_NEAR(*mw.mw_cycles, 13.0, 1e-6);
  // Codes already corrected by the signal selection are not corrected twice.
  DualFrequencyObservation selected = o;
  selected.code1_m -= 1.5;
  selected.code2_m -= 2.5;
  selected.code1_osb_m = 1.5;
  selected.code2_osb_m = 2.5;
  EXPECT_NEAR(*correctedMelbourneWuebbena(selected, &b).mw_cycles, 13.0, 1e-6);
  // Missing biases are reported, never silently ignored.
  TableBiases none;
  EXPECT_EQ(correctedMelbourneWuebbena(o, &none).issue, WideLaneBiasIssue::MissingPhaseBias);
  EXPECT_EQ(correctedMelbourneWuebbena(o, nullptr).issue, WideLaneBiasIssue::NoBiasProvider);
}

TEST(WideLaneAmbiguity, RoundingFixesSingleDifferencesWhenPrecise) {
  // Four arcs with a common receiver bias of 0.37 cycles, noise 0.2 cycles.
  WideLaneOptions opt;
  WideLaneResolver r(opt);
  const std::vector<std::pair<ArcId, int>> truth = {{1, 3}, {2, -8}, {3, 12}, {4, 0}};
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);
  const auto at = [](int k) { return GnssTime::fromGpsSeconds(1300000000 + 30 * k); };  // 30 s epochs
  for (int k = 0; k < 120; ++k)
    for (const auto& [arc, n] : truth)
      r.addValue(arc, SatelliteId{GnssSystem::GPS, static_cast<int>(arc)}, n + 0.37 + noise(rng), at(k));
  const WideLaneResolution res = r.resolve();
  ASSERT_TRUE(res.reference_arc.has_value());
  EXPECT_EQ(res.arcs.size(), 3u);
  int ref_n = 0;
  for (const auto& [arc, n] : truth)
    if (arc == *res.reference_arc) ref_n = n;
  for (const auto& f : res.arcs) {
    EXPECT_TRUE(f.fixed) << f.arc << " sigma " << f.sigma_cycles;
    int n = 0;
    for (const auto& [arc, m] : truth)
      if (arc == f.arc) n = m;
    EXPECT_EQ(f.integer_cycles, n - ref_n);
  }
  EXPECT_EQ(res.fixedCount(), 3);
  // After 3 epochs nothing is eligible; a fraction near 0.5 is never fixed.
  WideLaneResolver young(opt);
  for (int k = 0; k < 3; ++k) young.addValue(1, SatelliteId{GnssSystem::GPS, 1}, 0.0, at(k));
  EXPECT_FALSE(young.resolve().reference_arc.has_value());
  WideLaneResolver half(opt);
  for (int k = 0; k < 200; ++k) {
    half.addValue(1, SatelliteId{GnssSystem::GPS, 1}, 0.0, at(k));
    half.addValue(2, SatelliteId{GnssSystem::GPS, 2}, 2.48, at(k));
  }
  const auto h = half.resolve();
  ASSERT_EQ(h.arcs.size(), 1u);
  EXPECT_FALSE(h.arcs[0].fixed);
  EXPECT_NEAR(roundingSuccessRate(0.5), 0.682689492, 1e-8);  // 2 Phi(1) - 1
}

// A mean started again (after a slip repair whose wide lane may be one off with its
// whole system) holds only the samples after it, and a single difference with it says
// nothing about the wide lane until both means have min_samples (10) and the
// difference rounds with min_success_rate (0.999: a sigma below 0.152 cycles).
TEST(WideLaneAmbiguity, AMeanStartedAgainSaysNothingUntilItRounds) {
  WideLaneOptions opt;
  opt.correlation_time_s = 0.0;  // white: the sigma of a mean is max(sample sd, 0.15) / sqrt(n)
  WideLaneResolver r(opt);
  const auto at = [](int k) { return GnssTime::fromGpsSeconds(1300000000 + k); };
  const SatelliteId e1{GnssSystem::Galileo, 1}, e2{GnssSystem::Galileo, 2};
  for (int k = 0; k < 100; ++k) {
    r.addValue(1, e1, 5.0 + (k % 2 ? 0.1 : -0.1), at(k));
    r.addValue(2, e2, 2.0, at(k));
  }
  EXPECT_TRUE(pairDetermined(r.arcs().at(1), r.arcs().at(2), opt));  // neither started again
  r.restartArc(1);
  r.restartArc(2);
  EXPECT_EQ(r.arcs().at(1).samples, 0);
  EXPECT_TRUE(r.arcs().at(1).restarted);
  // Both one cycle off after the repair: their difference stays 3.
  for (int k = 100; k < 109; ++k) {
    r.addValue(1, e1, 6.0, at(k));
    r.addValue(2, e2, 3.0, at(k));
  }
  EXPECT_NEAR(r.arcs().at(1).mean_cycles, 6.0, 1e-12);
  EXPECT_FALSE(pairDetermined(r.arcs().at(1), r.arcs().at(2), opt));  // 9 samples
  r.addValue(1, e1, 6.0, at(109));
  r.addValue(2, e2, 3.0, at(109));
  // 10 samples: sigma 0.15 / sqrt(10) per mean, 0.067 for the difference: rounds.
  EXPECT_TRUE(pairDetermined(r.arcs().at(1), r.arcs().at(2), opt));
  // A noisy one (sd 0.63 cycle) does not round at 10 samples: sigma 0.21 for the difference.
  r.restartArc(2);
  for (int k = 110; k < 120; ++k) r.addValue(2, e2, 3.0 + (k % 2 ? 0.6 : -0.6), at(k));
  EXPECT_FALSE(pairDetermined(r.arcs().at(1), r.arcs().at(2), opt));
}

TEST(PhaseBiasConsistency, DecidedByTheAnalysisCentresOfClocksAndBiases) {
  EXPECT_EQ(analysisCentreOfProductFile("/d/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"), "WUM");
  EXPECT_EQ(analysisCentreOfProductFile("IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"), "IGS");
  EXPECT_FALSE(analysisCentreOfProductFile("igs21000.clk").has_value());
  const auto ccj2 = checkPhaseBiasConsistency({"WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"},
                                              std::string("WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz"), true);
  EXPECT_TRUE(ccj2.consistent()) << ccj2.text();
  const auto zim2 = checkPhaseBiasConsistency({"IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"},
                                              std::string("COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz"), true);
  EXPECT_EQ(zim2.verdict, PhaseBiasConsistency::DifferentAnalysisCentres);
  EXPECT_EQ(zim2.text(), "no consistent phase biases: float (clocks IGS, biases COD)");
  EXPECT_EQ(checkPhaseBiasConsistency({"a.clk"}, std::nullopt, false).verdict, PhaseBiasConsistency::NoBiasProduct);
  EXPECT_EQ(checkPhaseBiasConsistency({"WUM0MGXRAP_x.CLK"}, std::string("WUM0MGXRAP_x.BIA"), false).verdict,
            PhaseBiasConsistency::NoPhaseBiases);
  EXPECT_EQ(checkPhaseBiasConsistency({"igs.clk"}, std::string("WUM0MGXRAP_x.BIA"), true).verdict,
            PhaseBiasConsistency::UnknownAnalysisCentre);
}

struct RealWideLanes {
  WideLaneResolution with_osb, without_osb;
  std::map<WideLaneBiasIssue, int> issues;
};

/// Runs signal selection (with the dataset's OSBs), arc tracking and MW
/// accumulation over a whole dataset; arcs are resolved at their end (all arcs
/// kept, so that arcs ended by slips count too).
RealWideLanes runRealWideLanes(const test::PppDataset& d, std::vector<GnssSystem> systems = {GnssSystem::GPS}) {
  test::LoadedDataset data(d);
  SignalSelectionOptions selection;
  selection.systems = std::move(systems);
  SignalSelector selector(data.reader->header(), selection, data.biases.get());
  ArcTracker tracker;
  WideLaneResolver with_osb, without_osb;
  RealWideLanes out;
  ObsEpoch epoch;
  while (data.reader->next(epoch)) {
    const SignalSelectionResult sel = selector.select(epoch);
    const ArcEpochResult arcs = tracker.process(epoch.time, sel.observations);
    if (!arcs.accepted) continue;
    for (std::size_t i = 0; i < arcs.satellites.size(); ++i) {
      const auto& s = arcs.satellites[i];
      if (!s.usable || s.arc == 0) continue;
      const auto& o = sel.observations[i];
      const auto issue = with_osb.add(s.arc, o, data.biases.get());
      ++out.issues[issue];
      without_osb.addValue(s.arc, o.satellite, melbourneWuebbena_cycles(o), o.time);
    }
  }
  out.with_osb = with_osb.resolve();
  out.without_osb = without_osb.resolve();
  return out;
}

std::string histogram(const WideLaneResolution& r) {
  int bins[5] = {0, 0, 0, 0, 0};  // |fraction| in [0,.1) [.1,.2) [.2,.3) [.3,.4) [.4,.5]
  for (const auto& f : r.arcs) ++bins[std::min(4, static_cast<int>(std::abs(f.fraction_cycles) * 10.0))];
  std::ostringstream s;
  s << "|fraction| <0.1: " << bins[0] << ", 0.1-0.2: " << bins[1] << ", 0.2-0.3: " << bins[2]
    << ", 0.3-0.4: " << bins[3] << ", 0.4-0.5: " << bins[4] << " (" << r.arcs.size() << " arcs, "
    << r.fixedCount() << " fixed)";
  return s.str();
}

double shareWithin(const WideLaneResolution& r, double limit_cycles) {
  int n = 0;
  for (const auto& f : r.arcs) n += std::abs(f.fraction_cycles) < limit_cycles ? 1 : 0;
  return r.arcs.empty() ? 0.0 : static_cast<double>(n) / r.arcs.size();
}

double rmsFraction(const WideLaneResolution& r) {
  double s = 0.0;
  for (const auto& f : r.arcs) s += f.fraction_cycles * f.fraction_cycles;
  return r.arcs.empty() ? 0.0 : std::sqrt(s / r.arcs.size());
}

double medianFraction(const WideLaneResolution& r) {
  std::vector<double> v;
  for (const auto& f : r.arcs) v.push_back(std::abs(f.fraction_cycles));
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

TEST(WideLaneAmbiguity, RealCcj2WideLanesAreIntegersWithWumPhaseOsbs) {
  PPP_REQUIRE_SHARED_DATA();
  const RealWideLanes r = runRealWideLanes(test::ccj2Dataset());
  std::cout << "CCJ2 WUM OSB: " << histogram(r.with_osb) << ", RMS fraction " << rmsFraction(r.with_osb)
            << "\nCCJ2 no OSB: " << histogram(r.without_osb) << ", RMS fraction " << rmsFraction(r.without_osb)
            << "\n";
  for (const auto& f : r.with_osb.arcs)
    std::cout << "  " << f.satellite.toString() << " arc " << f.arc << " WL " << f.float_cycles << " +- "
              << f.sigma_cycles << (f.fixed ? " fixed " : " float ") << f.integer_cycles << "\n";
  for (const auto& [issue, n] : r.issues) std::cout << "  MW samples, bias issue '" << toString(issue) << "': " << n << "\n";
  EXPECT_GT(r.issues.at(WideLaneBiasIssue::None), 1000);
  ASSERT_GE(r.with_osb.arcs.size(), 6u);
  // With the satellite biases the single differences sit at integers (phase
  // OSBs of WUM hold the satellite wide-lane bias), without them they spread
  // (uniform fractions would give an RMS of 0.29).
  EXPECT_GE(shareWithin(r.with_osb, 0.2), 0.8);
  EXPECT_LT(rmsFraction(r.with_osb), 0.5 * rmsFraction(r.without_osb));
  EXPECT_GE(r.with_osb.fixedCount(), static_cast<int>(r.with_osb.arcs.size()) * 3 / 4);
}

// Galileo E1/E5a with the WUM phase OSBs (L1C/L1X, L5Q/L5X in the ABS.BIA):
// the single differences between Galileo satellites sit at integers. Six
// Galileo arcs in the hour; one (E19, measured 0.49 cycle off) is not near an
// integer, so the median fraction is compared, not the RMS.
TEST(WideLaneAmbiguity, RealCcj2GalileoWideLanesAreIntegersWithWumPhaseOsbs) {
  PPP_REQUIRE_SHARED_DATA();
  const RealWideLanes r = runRealWideLanes(test::ccj2Dataset(), {GnssSystem::Galileo});
  std::cout << "CCJ2 Galileo WUM OSB: " << histogram(r.with_osb) << ", RMS fraction " << rmsFraction(r.with_osb)
            << "\nCCJ2 Galileo no OSB: " << histogram(r.without_osb) << ", RMS fraction "
            << rmsFraction(r.without_osb) << "\n";
  for (const auto& f : r.with_osb.arcs)
    std::cout << "  " << f.satellite.toString() << " arc " << f.arc << " WL " << f.float_cycles << " +- "
              << f.sigma_cycles << (f.fixed ? " fixed " : " float ") << f.integer_cycles << "\n";
  ASSERT_GE(r.with_osb.arcs.size(), 5u);
  EXPECT_EQ(r.with_osb.reference_satellite.system, GnssSystem::Galileo);
  EXPECT_GE(shareWithin(r.with_osb, 0.2), 0.8);
  EXPECT_LT(medianFraction(r.with_osb), 0.5 * medianFraction(r.without_osb));
  EXPECT_GE(r.with_osb.fixedCount(), 4);
}

TEST(WideLaneAmbiguity, RealZim2WideLanesWithCodeOsbsButNarrowLaneRefused) {
  PPP_REQUIRE_SHARED_DATA();
  const auto d = test::zim2Dataset();
  const RealWideLanes r = runRealWideLanes(d);
  std::cout << "ZIM2 CODE OSB: " << histogram(r.with_osb) << ", RMS fraction " << rmsFraction(r.with_osb)
            << "\nZIM2 no OSB: " << histogram(r.without_osb) << ", RMS fraction " << rmsFraction(r.without_osb)
            << "\n";
  ASSERT_GE(r.with_osb.arcs.size(), 6u);
  // The wide lane is clock free: CODE's OSBs serve it even with IGS clocks.
  EXPECT_GE(shareWithin(r.with_osb, 0.2), 0.8);
  EXPECT_LT(rmsFraction(r.with_osb), 0.6 * rmsFraction(r.without_osb));
  // The narrow lane is not: IGS combined clocks with CODE's biases.
  const auto check = checkPhaseBiasConsistency(d.clk, d.bia, true);
  EXPECT_FALSE(check.consistent());
  EXPECT_EQ(check.text(), "no consistent phase biases: float (clocks IGS, biases COD)");
}

}  // namespace
}  // namespace ppp

namespace ppp {
namespace {

/// A float state covariance [m^2] for the synthetic resolver tests: 1 cm sigma on
/// the bias states and 10 cm on the receiver part, with a 10 cm part common to all
/// biases (a receiver phase bias, which cancels in the single differences).
Eigen::MatrixXd floatCovariance(int receiver_dim, int n) {
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(receiver_dim + n, receiver_dim + n) * 1e-4;
  P.topLeftCorner(receiver_dim, receiver_dim) *= 100.0;
  P.bottomRightCorner(n, n) += Eigen::MatrixXd::Constant(n, n, 0.01);
  return P;
}

// The narrow lane end to end on a synthetic filter state: IF biases built from
// known integers, satellite phase OSBs and a receiver bias common to all arcs;
// MW samples with the same wide lanes. The resolver must fix, and the fixed copy
// must put every bias on its true value, while the float input is unchanged.
struct SyntheticArc {
  ArcId arc;
  int prn;
  int n1, nwl;
  double osb_l1_m, osb_l2_m;
};

TEST(AmbiguityResolver, FixesSyntheticNarrowLanesAndConstrainsACopy) {
  const std::vector<SyntheticArc> arcs = {{1, 3, 12, 5, 0.031, -0.044}, {2, 7, -40, 17, -0.12, 0.07},
                                          {3, 11, 7, -3, 0.2, 0.15},     {4, 19, 101, 44, -0.05, -0.2},
                                          {5, 22, -9, 0, 0.0, 0.09},     {6, 30, 55, -21, 0.11, 0.013}};
  TableBiases osb;
  const double lambda_nl = narrowLaneWavelength_m(kF1, kF2);
  const auto k_if = ionosphereFreeCoefficients(kF1, kF2);
  const int receiver_dim = 5;
  const int n = static_cast<int>(arcs.size());
  Eigen::VectorXd truth(receiver_dim + n);
  truth.head(receiver_dim) << 1.0, 2.0, 3.0, 0.1, 5.0;
  const double receiver_phase_bias_m = 0.4321, receiver_wl_cycles = 0.29;
  AmbiguityResolutionOptions opt;
  opt.enabled = true;
  // The synthetic covariance is the floats' true one (their errors are drawn
  // inside it): variance factor 1, not the default for real floats.
  opt.narrow_lane.success_rate_variance_factor = 1.0;
  AmbiguityResolver resolver(opt);
  std::mt19937 rng(9);
  std::normal_distribution<double> mw_noise(0.0, 0.2);
  for (int i = 0; i < n; ++i) {
    const auto& a = arcs[static_cast<std::size_t>(i)];
    const SatelliteId sat{GnssSystem::GPS, a.prn};
    osb.table[{sat, "L1C"}] = a.osb_l1_m;
    osb.table[{sat, "L2W"}] = a.osb_l2_m;
    osb.table[{sat, "C1W"}] = 0.0;
    osb.table[{sat, "C2W"}] = 0.0;
    truth(receiver_dim + i) = ionosphereFreeAmbiguity_m(kF1, kF2, a.n1, a.nwl) +
                              ionosphereFree(a.osb_l1_m, a.osb_l2_m, k_if) + receiver_phase_bias_m;
  }
  for (int k = 0; k < 60; ++k) {
    std::vector<DualFrequencyObservation> obs;
    std::vector<ArcId> ids;
    for (const auto& a : arcs) {
      const SatelliteId sat{GnssSystem::GPS, a.prn};
      // MW = nwl + receiver WL bias + satellite WL bias (from the OSBs) + noise:
      // built by putting the ambiguities and OSBs on the phases.
      DualFrequencyObservation o = makeObservation(sat, 2.2e7 + 1000.0 * k, a.n1, a.n1 - a.nwl);
      o.phase1_cycles += a.osb_l1_m * kF1 / kSpeedOfLight_mps + receiver_wl_cycles + mw_noise(rng);
      o.phase2_cycles += a.osb_l2_m * kF2 / kSpeedOfLight_mps;
      o.code1_osb_m = 0.0;
      o.code2_osb_m = 0.0;
      obs.push_back(o);
      ids.push_back(a.arc);
    }
    resolver.addEpoch(obs, ids, &osb);
  }
  // Float state: truth plus errors well inside its covariance (NL sigma ~0.05 cycles).
  const Eigen::MatrixXd P = floatCovariance(receiver_dim, n);
  Eigen::VectorXd x = truth;
  x(receiver_dim + 0) += 0.004;
  x(receiver_dim + 3) -= 0.003;
  x.tail(n).array() += 0.05;  // common error: cancels in the single differences
  std::vector<ArcId> bias_arcs;
  for (const auto& a : arcs) bias_arcs.push_back(a.arc);
  AmbiguityFixSummary summary;
  const Eigen::VectorXd x_before = x;
  const auto fixed = resolver.resolve(x, P, receiver_dim, bias_arcs, &osb, summary);
  ASSERT_TRUE(fixed.has_value()) << summary.text();
  EXPECT_EQ(summary.wide_lanes_fixed, n - 1);
  EXPECT_EQ(summary.narrow_lanes_fixed, n - 1);
  EXPECT_GE(summary.ratio, 3.0);
  // The single differences of the fixed biases equal the true ones (mm).
  for (int i = 1; i < n; ++i) {
    const double sd_fixed = fixed->x(receiver_dim + i) - fixed->x(receiver_dim);
    const double sd_truth = truth(receiver_dim + i) - truth(receiver_dim);
    EXPECT_NEAR(sd_fixed, sd_truth, 1e-6) << "arc " << arcs[static_cast<std::size_t>(i)].arc;
  }
  EXPECT_EQ(x, x_before);  // the float state is not touched
  EXPECT_LT(fixed->P(receiver_dim + 1, receiver_dim + 1), P(receiver_dim + 1, receiver_dim + 1));
  // No consistent phase biases: float with the reason.
  EXPECT_FALSE(resolver.resolve(x, P, receiver_dim, bias_arcs, nullptr, summary).has_value());
  EXPECT_EQ(summary.float_reason, AmbiguityFloatReason::NoConsistentPhaseBiases);
}

// GPS L1/L2 and Galileo E1/E5a together: each system has its own receiver
// wide-lane and phase bias (different per system, as receiver hardware delays
// and the inter-system clock difference are), so single differences are formed
// within a system against that system's reference; the Galileo ones refer to a
// Galileo satellite. Both resolve() and resolveAndHold() fix every arc but the
// two references and put the within-system single differences on the truth.
/// One arc of a synthetic multi-system run: its integers and satellite OSBs.
struct SystemArc {
  ArcId arc;
  SatelliteId sat;
  int n1, nwl;
  double osb1_m, osb2_m;
};
/// The receiver side of one system (per satellite for GLONASS: its channel's frequencies).
struct SystemReceiver {
  double f1_hz, f2_hz;
  const char *c1, *c2, *l1, *l2;
  double wl_cycles, phase_m;
};
using ReceiverOf = std::function<SystemReceiver(const SatelliteId&)>;

/// The true float state (receiver part, then one IF bias per arc) and the OSB table.
Eigen::VectorXd syntheticTruth(const std::vector<SystemArc>& arcs, const ReceiverOf& receiver, int receiver_dim,
                               TableBiases& osb) {
  const int n = static_cast<int>(arcs.size());
  Eigen::VectorXd truth(receiver_dim + n);
  truth.head(receiver_dim) << 1.0, 2.0, 3.0, 0.1, 5.0;
  for (int i = 0; i < n; ++i) {
    const SystemArc& a = arcs[static_cast<std::size_t>(i)];
    const SystemReceiver r = receiver(a.sat);
    osb.table[{a.sat, r.l1}] = a.osb1_m;
    osb.table[{a.sat, r.l2}] = a.osb2_m;
    osb.table[{a.sat, r.c1}] = 0.0;
    osb.table[{a.sat, r.c2}] = 0.0;
    truth(receiver_dim + i) = ionosphereFreeAmbiguity_m(r.f1_hz, r.f2_hz, a.n1, a.nwl) +
                              ionosphereFree(a.osb1_m, a.osb2_m, ionosphereFreeCoefficients(r.f1_hz, r.f2_hz)) +
                              r.phase_m;
  }
  return truth;
}

/// 60 epochs of MW samples of the arcs into the resolver (the ambiguities and OSBs on the phases).
void feedSyntheticEpochs(AmbiguityResolver& resolver, const std::vector<SystemArc>& arcs, const ReceiverOf& receiver,
                         const TableBiases& osb, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> mw_noise(0.0, 0.2);
  for (int k = 0; k < 60; ++k) {
    std::vector<DualFrequencyObservation> obs;
    std::vector<ArcId> ids;
    for (const SystemArc& a : arcs) {
      const SystemReceiver r = receiver(a.sat);
      DualFrequencyObservation o;
      o.satellite = a.sat;
      o.code1 = *ObservationCode::parse(r.c1);
      o.code2 = *ObservationCode::parse(r.c2);
      o.phase1 = *ObservationCode::parse(r.l1);
      o.phase2 = *ObservationCode::parse(r.l2);
      o.frequency1_hz = r.f1_hz;
      o.frequency2_hz = r.f2_hz;
      const double range_m = 2.4e7 + 1000.0 * k;
      o.code1_m = o.code2_m = range_m;
      o.phase1_cycles = range_m * r.f1_hz / kSpeedOfLight_mps + a.n1 + a.osb1_m * r.f1_hz / kSpeedOfLight_mps +
                        r.wl_cycles + mw_noise(rng);
      o.phase2_cycles = range_m * r.f2_hz / kSpeedOfLight_mps + (a.n1 - a.nwl) + a.osb2_m * r.f2_hz / kSpeedOfLight_mps;
      o.code1_osb_m = 0.0;
      o.code2_osb_m = 0.0;
      obs.push_back(o);
      ids.push_back(a.arc);
    }
    resolver.addEpoch(obs, ids, &osb);
  }
}

constexpr double kE1 = 1575.42e6, kE5a = 1176.45e6;  // Galileo OS SIS ICD 2.1, table 2

const std::vector<SystemArc> kGpsGalileoArcs = {
    {1, {GnssSystem::GPS, 3}, 12, 5, 0.031, -0.044},  {2, {GnssSystem::GPS, 7}, -40, 17, -0.12, 0.07},
    {3, {GnssSystem::GPS, 11}, 7, -3, 0.2, 0.15},     {4, {GnssSystem::GPS, 19}, 101, 44, -0.05, -0.2},
    {5, {GnssSystem::Galileo, 1}, 33, -8, 0.07, 0.02}, {6, {GnssSystem::Galileo, 4}, -17, 2, -0.09, 0.11},
    {7, {GnssSystem::Galileo, 12}, 5, 13, 0.15, -0.06}, {8, {GnssSystem::Galileo, 26}, 61, -1, 0.0, 0.04}};

SystemReceiver gpsGalileoGlonassReceiver(const SatelliteId& sat) {
  switch (sat.system) {
    case GnssSystem::GPS: return {kF1, kF2, "C1W", "C2W", "L1C", "L2W", 0.29, 0.4321};
    case GnssSystem::Galileo: return {kE1, kE5a, "C1C", "C5Q", "L1C", "L5Q", -0.37, -1.7391};
    default: {  // GLONASS: channel k = prn - 8 (a stand-in for the header's table)
      const int k = sat.prn - 8;
      return {*carrierFrequency_hz(GnssSystem::GLONASS, '1', k), *carrierFrequency_hz(GnssSystem::GLONASS, '2', k),
              "C1P", "C2P", "L1P", "L2P", 0.11, 0.9876};
    }
  }
}

/// The float inputs of a synthetic multi-system run.
struct SyntheticInputs {
  TableBiases osb;
  Eigen::VectorXd truth;
  Eigen::MatrixXd P;
  std::vector<ArcId> bias_arcs;
};

/// A synthetic run of `arcs` (gpsGalileoGlonassReceiver): the truth, the OSBs, the
/// float covariance, and a resolver (at least 3 narrow lanes) fed with 60 epochs.
struct SyntheticResolution {
  static constexpr int kReceiverDim = 5;
  SyntheticInputs inputs;
  AmbiguityResolver resolver;
  static AmbiguityResolutionOptions options() {
    AmbiguityResolutionOptions opt;
    opt.enabled = true;
    opt.narrow_lane.min_fixed = 3;
    opt.narrow_lane.success_rate_variance_factor = 1.0;  // the synthetic covariance is the true one
    return opt;
  }
  explicit SyntheticResolution(const std::vector<SystemArc>& arcs) : resolver(options()) {
    inputs.truth = syntheticTruth(arcs, gpsGalileoGlonassReceiver, kReceiverDim, inputs.osb);
    feedSyntheticEpochs(resolver, arcs, gpsGalileoGlonassReceiver, inputs.osb, 5);
    inputs.P = floatCovariance(kReceiverDim, static_cast<int>(arcs.size()));
    for (const SystemArc& a : arcs) inputs.bias_arcs.push_back(a.arc);
  }
};

TEST(AmbiguityResolver, GpsAndGalileoEachHaveTheirOwnReference) {
  const std::vector<SystemArc>& arcs = kGpsGalileoArcs;
  SyntheticResolution run(arcs);
  const int receiver_dim = SyntheticResolution::kReceiverDim, n = static_cast<int>(arcs.size());
  const TableBiases& osb = run.inputs.osb;
  const Eigen::VectorXd& truth = run.inputs.truth;
  const Eigen::MatrixXd& P = run.inputs.P;
  const std::vector<ArcId>& bias_arcs = run.inputs.bias_arcs;
  AmbiguityResolver& resolver = run.resolver;
  const auto checkWithinSystems = [&](const AmbiguityFixedState& fixed, const char* what) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        if (arcs[static_cast<std::size_t>(i)].sat.system != arcs[static_cast<std::size_t>(j)].sat.system) continue;
        EXPECT_NEAR(fixed.x(receiver_dim + i) - fixed.x(receiver_dim + j),
                    truth(receiver_dim + i) - truth(receiver_dim + j), 1e-6)
            << what << ": arcs " << i + 1 << " " << j + 1;
      }
  };
  AmbiguityFixSummary summary;
  const auto fixed = resolver.resolve(truth, P, receiver_dim, bias_arcs, &osb, summary);
  ASSERT_TRUE(fixed.has_value()) << summary.text();
  EXPECT_EQ(summary.wide_lanes_fixed, n - 2);
  EXPECT_EQ(summary.narrow_lanes_fixed, n - 2);
  ASSERT_EQ(summary.systems.size(), 2u);
  EXPECT_EQ(summary.systems[0].system, GnssSystem::GPS);
  EXPECT_EQ(summary.systems[0].reference_satellite.system, GnssSystem::GPS);
  EXPECT_EQ(summary.systems[1].system, GnssSystem::Galileo);
  EXPECT_EQ(summary.systems[1].reference_satellite.system, GnssSystem::Galileo);
  EXPECT_EQ(summary.systems[1].wide_lanes_fixed, 3);
  checkWithinSystems(*fixed, "resolve");

  // The same through validation and hold: every held single difference stays
  // within its system, and each system's integers are held.
  std::optional<AmbiguityFixedState> held;
  for (int k = 0; k < 30 && !(held && resolver.heldCount() == n - 2); ++k)
    held = resolver.resolveAndHold(truth, P, receiver_dim, bias_arcs, &osb, summary);
  ASSERT_TRUE(held.has_value()) << summary.text();
  EXPECT_EQ(resolver.heldCount(), n - 2);
  int held_galileo = 0;
  for (const NarrowLaneFloat& f : summary.narrow_lanes) {
    EXPECT_EQ(f.satellite.system, f.reference_satellite.system) << f.satellite.toString();
    if (f.held_cycles && f.satellite.system == GnssSystem::Galileo) ++held_galileo;
  }
  EXPECT_EQ(held_galileo, 3);
  ASSERT_EQ(summary.systems.size(), 2u);
  EXPECT_EQ(summary.systems[1].held, 3);
  checkWithinSystems(*held, "resolveAndHold");
  EXPECT_NE(summary.text().find(summary.systems[1].reference_satellite.toString()), std::string::npos)
      << summary.text();
}

// GLONASS (FDMA) arcs next to GPS and Galileo, with integer-consistent wide and
// narrow lanes and OSBs of their own: ambiguity resolution leaves them float. No
// GLONASS wide lane, reference, candidate or hold; GPS and Galileo fix as without them.
TEST(AmbiguityResolver, GlonassArcsStayFloatBesideGpsAndGalileo) {
  std::vector<SystemArc> arcs = kGpsGalileoArcs;
  arcs.push_back({9, {GnssSystem::GLONASS, 9}, 21, 4, 0.05, -0.03});    // k = 1
  arcs.push_back({10, {GnssSystem::GLONASS, 4}, -11, 7, -0.02, 0.08});  // k = -4
  arcs.push_back({11, {GnssSystem::GLONASS, 14}, 40, -2, 0.1, 0.0});    // k = 6
  SyntheticResolution run(arcs);
  const int receiver_dim = SyntheticResolution::kReceiverDim;
  const TableBiases& osb = run.inputs.osb;
  const Eigen::VectorXd& truth = run.inputs.truth;
  const Eigen::MatrixXd& P = run.inputs.P;
  const std::vector<ArcId>& bias_arcs = run.inputs.bias_arcs;
  AmbiguityResolver& resolver = run.resolver;
  AmbiguityFixSummary summary;
  const auto fixed = resolver.resolve(truth, P, receiver_dim, bias_arcs, &osb, summary);
  ASSERT_TRUE(fixed.has_value()) << summary.text();
  EXPECT_EQ(summary.wide_lanes_fixed, 6);  // 4 GPS + 4 Galileo arcs less the two references
  EXPECT_EQ(summary.narrow_lanes_fixed, 6);
  ASSERT_EQ(summary.systems.size(), 2u);
  EXPECT_EQ(summary.systems[0].system, GnssSystem::GPS);
  EXPECT_EQ(summary.systems[1].system, GnssSystem::Galileo);
  std::optional<AmbiguityFixedState> held;
  for (int k = 0; k < 30 && !(held && resolver.heldCount() == 6); ++k)
    held = resolver.resolveAndHold(truth, P, receiver_dim, bias_arcs, &osb, summary);
  ASSERT_TRUE(held.has_value()) << summary.text();
  EXPECT_EQ(resolver.heldCount(), 6);
  for (const NarrowLaneFloat& f : summary.narrow_lanes) {
    EXPECT_NE(f.satellite.system, GnssSystem::GLONASS) << f.satellite.toString();
    EXPECT_NE(f.reference_satellite.system, GnssSystem::GLONASS) << f.reference_satellite.toString();
  }
  for (const SystemAmbiguitySummary& sys : summary.systems)
    EXPECT_NE(sys.reference_satellite.system, GnssSystem::GLONASS);
}

TEST(AmbiguityResolver, WrongIntegerConstraintIsVisibleAgainstTheFloatState) {
  // A deliberately wrong integer (one NL cycle, 10.7 cm) applied to a precise
  // float state moves it by far more than its sigma: the squared norm of the
  // fix against the float covariance is large, so the ratio test refuses such a
  // candidate in favour of the right one; the float state stays intact for the
  // next epoch.
  const int dim = 3;
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(dim, dim) * 1e-4;
  P(2, 2) = 1e-2;
  const Eigen::VectorXd x = Eigen::Vector3d(0.0, 0.2140, 5.0);  // x1 = 2 NL cycles of 0.107 m
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(1, dim);
  A(0, 1) = 1.0 / 0.107;
  const auto right = applyIntegerConstraints(x, P, A, Eigen::VectorXd::Constant(1, 2.0));
  const auto wrong = applyIntegerConstraints(x, P, A, Eigen::VectorXd::Constant(1, 3.0));
  ASSERT_TRUE(right && wrong);
  EXPECT_NEAR(right->x(1), 0.214, 1e-9);
  EXPECT_NEAR(wrong->x(1), 0.321, 1e-9);
  const auto norm = [&](const Eigen::VectorXd& xf) {
    const Eigen::VectorXd d = xf - x;
    return d(1) * d(1) / P(1, 1);
  };
  EXPECT_LT(norm(right->x), 1e-6);
  EXPECT_GT(norm(wrong->x), 100.0);  // (0.107 / 0.01)^2
  EXPECT_NEAR(wrong->P(1, 1), 0.0, 1e-12);
}

}  // namespace
}  // namespace ppp

namespace ppp {
namespace {

// Comment lines as in the header of GRG0MGXFIN_20201770000_01D_30S_CLK.CLK
// (esbc-2020-177; the G01 value here is illustrative, the layout is the file's).
TEST(ClockWideLaneBiases, ParsesGrgHeaderCommentsAndReportsMalformedOnes) {
  const std::vector<std::string> comments = {
      "FRAME TX (COM-COF) USED :      -6.1 mm",
      "WIDELANE SATELLITE FRACTIONNAL BIASES FOR GALILEO",
      "WL E01 2020   6 25 12  0  0.000000  1   -4.400000E-01  0105",
      "WL G01 2020   6 25 12  0  0.000000  1   +1.200000E-01  0102",
      "WL G02 2020   6 25",
      "WL E02 2020   6 25 12  0  0.000000  1   +1.000000E-02  0107"};
  const ClockWideLaneBiases wl = parseClockWideLaneBiases(comments);
  ASSERT_EQ(wl.wide_lane_cycles.size(), 2u);
  EXPECT_DOUBLE_EQ(wl.wide_lane_cycles.at(*SatelliteId::parse("E01")), -0.44);
  EXPECT_DOUBLE_EQ(wl.wide_lane_cycles.at(*SatelliteId::parse("G01")), 0.12);
  ASSERT_EQ(wl.problems.size(), 2u);
  EXPECT_NE(wl.problems[0].find("comment 5"), std::string::npos) << wl.problems[0];
  // A Galileo wide lane of another pair (E1/E5b) is not the E1/E5a one used here.
  EXPECT_NE(wl.problems[1].find("comment 6"), std::string::npos) << wl.problems[1];
  EXPECT_NE(wl.problems[1].find("0105"), std::string::npos) << wl.problems[1];
}

/// ESBC 2020-177's wide lanes of `system` with the GRG clock header biases added
/// (the GRG sign), subtracted, and without them; every arc resolved at the end.
struct EsbcClockWideLanes {
  ClockWideLaneBiases parsed;
  WideLaneResolution added, subtracted, without;
};

EsbcClockWideLanes runEsbcClockWideLanes(GnssSystem system) {
  const std::string clk = test::dataPath("esbc-2020-177/GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz");
  RinexClockReadOptions clock_options;
  clock_options.keep_receiver_clocks = false;
  EsbcClockWideLanes out;
  out.parsed = parseClockWideLaneBiases(readRinexClock(clk, clock_options).header.comments);
  const ClockWideLaneBiasProvider grg(out.parsed.wide_lane_cycles, "GRG"),
      flipped(out.parsed.wide_lane_cycles, "GRG", 1.0);
  auto reader = RinexObsReader::open(test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz"));
  SignalSelectionOptions selection;
  selection.systems = {system};
  SignalSelector selector(reader.header(), selection, nullptr);
  ArcTracker tracker;
  WideLaneResolver with_grg, with_flipped, without;
  ObsEpoch epoch;
  while (reader.next(epoch)) {
    const SignalSelectionResult sel = selector.select(epoch);
    const ArcEpochResult arcs = tracker.process(epoch.time, sel.observations);
    if (!arcs.accepted) continue;
    for (std::size_t i = 0; i < arcs.satellites.size(); ++i) {
      const auto& s = arcs.satellites[i];
      if (!s.usable || s.arc == 0) continue;
      const auto& o = sel.observations[i];
      if (with_grg.add(s.arc, o, &grg) != WideLaneBiasIssue::None) continue;
      with_flipped.add(s.arc, o, &flipped);
      without.addValue(s.arc, o.satellite, melbourneWuebbena_cycles(o), o.time);
    }
  }
  out.added = with_grg.resolve();
  out.subtracted = with_flipped.resolve();
  out.without = without.resolve();
  const std::string name(systemName(system));
  std::cout << "ESBC " << name << " GRG WL (added): " << histogram(out.added) << "\nESBC " << name
            << " GRG WL (subtracted): " << histogram(out.subtracted) << "\nESBC " << name
            << " no WL bias: " << histogram(out.without) << "\n";
  return out;
}

// ESBC 2020-177 with the GRG integer-recovery clock file: the wide-lane
// satellite biases of its header, added to the Melbourne-Wuebbena means
// (GRG sign), put the between-satellite single differences at integers; with
// the opposite sign or without them the fractions spread.
TEST(ClockWideLaneBiases, RealEsbcWideLanesAreIntegersWithGrgHeaderBiases) {
  PPP_REQUIRE_SHARED_DATA();
  const EsbcClockWideLanes r = runEsbcClockWideLanes(GnssSystem::GPS);
  EXPECT_TRUE(r.parsed.problems.empty());
  ASSERT_GE(r.parsed.wide_lane_cycles.size(), 30u);
  ASSERT_GE(r.added.arcs.size(), 20u);
  EXPECT_GE(shareWithin(r.added, 0.2), 0.8);
  EXPECT_LT(rmsFraction(r.added), 0.5 * rmsFraction(r.subtracted));
  EXPECT_LT(rmsFraction(r.added), 0.5 * rmsFraction(r.without));
}

// The same for Galileo E1/E5a (header lines "WL Ennn ... 0105"): the GRG
// Galileo wide-lane biases with the GRG sign put the Galileo single differences
// at integers.
TEST(ClockWideLaneBiases, RealEsbcGalileoWideLanesAreIntegersWithGrgHeaderBiases) {
  PPP_REQUIRE_SHARED_DATA();
  const EsbcClockWideLanes r = runEsbcClockWideLanes(GnssSystem::Galileo);
  EXPECT_TRUE(r.parsed.problems.empty());
  int galileo = 0;
  for (const auto& [sat, w] : r.parsed.wide_lane_cycles) galileo += sat.system == GnssSystem::Galileo ? 1 : 0;
  ASSERT_GE(galileo, 20);
  ASSERT_GE(r.added.arcs.size(), 15u);
  EXPECT_EQ(r.added.reference_satellite.system, GnssSystem::Galileo);
  EXPECT_GE(shareWithin(r.added, 0.2), 0.8);
  EXPECT_LT(rmsFraction(r.added), 0.5 * rmsFraction(r.subtracted));
  EXPECT_LT(rmsFraction(r.added), 0.5 * rmsFraction(r.without));
}

TEST(ClockWideLaneBiases, GalileoE1E5aPhaseBiasesMoveOnlyTheWideLane) {
  constexpr double kE1 = 1575.42e6, kE5a = 1176.45e6;  // Galileo OS SIS ICD 2.1, table 2
  const SatelliteId e11 = *SatelliteId::parse("E11");
  const double w = -0.21;
  const ClockWideLaneBiasProvider p({{e11, w}}, "GRG test");
  const GnssTime t;
  const auto b1 = p.phaseBias(e11, *ObservationCode::parse("L1C"), t).value_m;
  const auto b5 = p.phaseBias(e11, *ObservationCode::parse("L5Q"), t).value_m;
  ASSERT_TRUE(b1 && b5);
  EXPECT_NEAR((kE1 * kE1 * *b1 - kE5a * kE5a * *b5) / (kE1 * kE1 - kE5a * kE5a), 0.0, 1e-12);
  // E5b is not the pair of the header's Galileo wide lanes (0105).
  EXPECT_FALSE(p.phaseBias(e11, *ObservationCode::parse("L7Q"), t).value_m);
  EXPECT_EQ(p.codeBias(e11, *ObservationCode::parse("C1C"), t).value_m, std::optional<double>(0.0));
  EXPECT_EQ(p.codeBias(e11, *ObservationCode::parse("C5Q"), t).value_m, std::optional<double>(0.0));
  EXPECT_FALSE(p.codeBias(e11, *ObservationCode::parse("C7Q"), t).value_m);
  // MW of clean E1/E5a observations with N1 - N5 = 9 moves by +w (GRG sign).
  DualFrequencyObservation o;
  o.satellite = e11;
  o.code1 = *ObservationCode::parse("C1C");
  o.code2 = *ObservationCode::parse("C5Q");
  o.phase1 = *ObservationCode::parse("L1C");
  o.phase2 = *ObservationCode::parse("L5Q");
  o.frequency1_hz = kE1;
  o.frequency2_hz = kE5a;
  const double range_m = 2.5e7;
  o.code1_m = o.code2_m = range_m;
  o.phase1_cycles = range_m * kE1 / kSpeedOfLight_mps + 20;
  o.phase2_cycles = range_m * kE5a / kSpeedOfLight_mps + 11;
  const CorrectedMelbourneWuebbena mw = correctedMelbourneWuebbena(o, &p);
  ASSERT_TRUE(mw.mw_cycles) << toString(mw.issue);
  EXPECT_NEAR(*mw.mw_cycles, 9.0 + w, 1e-6);
}

TEST(ClockWideLaneBiases, PhaseBiasesMoveOnlyTheWideLaneNotTheIonosphereFreeClock) {
  const SatelliteId g01 = *SatelliteId::parse("G01"), g02 = *SatelliteId::parse("G02");
  const double w = 0.3;
  const ClockWideLaneBiasProvider p({{g01, w}}, "GRG test");  // GRG sign: corrected MW = MW + w
  const GnssTime t;
  const auto b1 = p.phaseBias(g01, *ObservationCode::parse("L1C"), t).value_m;
  const auto b2 = p.phaseBias(g01, *ObservationCode::parse("L2W"), t).value_m;
  ASSERT_TRUE(b1 && b2);
  // Ionosphere-free combination zero: the integer-recovery clock holds it.
  EXPECT_NEAR((kF1 * kF1 * *b1 - kF2 * kF2 * *b2) / (kF1 * kF1 - kF2 * kF2), 0.0, 1e-12);
  // Reference codes (P1/P2) have zero code bias, other codes none; other satellites none.
  EXPECT_EQ(p.codeBias(g01, *ObservationCode::parse("C1W"), t).value_m, std::optional<double>(0.0));
  EXPECT_FALSE(p.codeBias(g01, *ObservationCode::parse("C1C"), t).value_m);
  EXPECT_FALSE(p.phaseBias(g02, *ObservationCode::parse("L1C"), t).value_m);
  // Melbourne-Wuebbena of clean observations with N1 - N2 = 13 moves by +w.
  DualFrequencyObservation o = makeObservation(g01, 2.2e7, 17, 4);
  const CorrectedMelbourneWuebbena mw = correctedMelbourneWuebbena(o, &p);
  ASSERT_TRUE(mw.mw_cycles) << toString(mw.issue);
  EXPECT_NEAR(*mw.mw_cycles, 13.0 + w, 1e-6);
}

}  // namespace
}  // namespace ppp
