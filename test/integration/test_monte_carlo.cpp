// A small Monte Carlo (3 flights of 3 minutes): shape and finiteness of the
// outputs, JSON that parses, determinism (same seed -> same numbers, whatever
// the thread count), the flight-seed derivation and the in-memory pipeline.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/models/troposphere.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/random_stream.h"
#include "test_support.h"

using namespace ppp;

namespace {

MonteCarloOptions smallStudy() {
  MonteCarloOptions o;
  o.flights = 3;
  o.seed = 42;
  o.duration_s = 180.0;
  o.profiles = {FlightProfile::Loiter, FlightProfile::Figure8, FlightProfile::Survey};
  o.first_window_s = 60.0;  // a window shorter than the flights
  o.threads = 2;
  return o;
}

const MonteCarloResult& study() {
  static const MonteCarloResult r = runMonteCarlo(smallStudy());
  return r;
}

std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST(MonteCarlo, FlightSetupIsDerivedFromTheSeedAndIndex) {
  const MonteCarloOptions o = smallStudy();
  const MonteCarloFlightSetup a = monteCarloFlightSetup(o, 1), b = monteCarloFlightSetup(o, 1);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.seed, RandomStream(42).derive(1).seed());  // the documented derivation
  EXPECT_NE(a.seed, monteCarloFlightSetup(o, 2).seed);
  EXPECT_EQ(a.profile, FlightProfile::Figure8);  // round robin: profiles[1 % 3]
  EXPECT_EQ(monteCarloFlightSetup(o, 3).profile, FlightProfile::Loiter);
  EXPECT_TRUE(a.start == b.start);
  EXPECT_LE(std::abs(a.origin.latitude_rad), 60.0 * kDegToRad);
  // Independent of the number of flights.
  MonteCarloOptions more = o;
  more.flights = 50;
  EXPECT_EQ(monteCarloFlightSetup(more, 1).seed, a.seed);
}

TEST(MonteCarlo, TablesHaveEveryEstimatorAndWindowWithFiniteValues) {
  const MonteCarloResult& r = study();
  const MonteCarloSummary& s = r.summary;
  ASSERT_EQ(r.flights.size(), 3u);
  EXPECT_EQ(s.failed, 0) << (s.failures.empty() ? "" : s.failures.front());
  for (const auto& f : r.flights) {
    EXPECT_EQ(f.epochs, 181u);  // 3 min at 1 Hz, both ends
    for (const auto& e : f.error_3d_m) EXPECT_EQ(e.size(), f.epochs);
  }
  ASSERT_GE(s.representative, 0);
  for (int e = 0; e < kMonteCarloEstimators; ++e) {
    const auto ei = static_cast<std::size_t>(e);
    for (const ErrorSummary* t : {&s.all[ei], &s.first_window[ei], &s.after_window[ei], &s.representative_flight[ei]}) {
      EXPECT_GT(t->count, 0u) << monteCarloEstimatorKey(e);
      EXPECT_TRUE(std::isfinite(t->median_m) && std::isfinite(t->mean_m) && std::isfinite(t->std_m) &&
                  std::isfinite(t->max_m));
      EXPECT_LE(t->median_m, t->max_m);
      EXPECT_LT(t->max_m, 20.0) << "3D error beyond 20 m: the pipeline or the truth is broken";
    }
    EXPECT_LT(s.first_window[ei].count, s.all[ei].count);  // the window holds the first minute only
    EXPECT_EQ(s.first_window[ei].count + s.after_window[ei].count, s.all[ei].count);
    EXPECT_EQ(s.all[ei].count + s.epochs_without_solution[ei], 3u * 181u);
    EXPECT_FALSE(s.error_vs_time[ei].empty());
    EXPECT_FALSE(s.bias_vs_age[ei].empty());
    for (const auto& b : s.bias_vs_age[ei]) EXPECT_TRUE(std::isfinite(b.p50) && std::isfinite(b.abs_p90));
    ASSERT_EQ(s.cdf_all_m[ei].size(), s.cdf_levels.size());
    for (std::size_t j = 1; j < s.cdf_levels.size(); ++j) EXPECT_LE(s.cdf_all_m[ei][j - 1], s.cdf_all_m[ei][j]);
    EXPECT_EQ(s.convergence_median_s[ei].size(), r.options.convergence_thresholds_m.size());
  }
  EXPECT_GT(s.bias_arcs_compared, 0u);
  // The representative flight is the median of the EKF means.
  std::vector<double> means;
  for (const auto& f : r.flights) means.push_back(f.summary(0).mean_m);
  std::vector<double> sorted = means;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_DOUBLE_EQ(means[static_cast<std::size_t>(s.representative)], sorted[1]);
}

TEST(MonteCarlo, SmootherFilteredFollowsTheEkf) {
  // Same models and noise: the filtered solutions differ only by relinearization
  // (measured: < 1 mm on average on these flights; 2 cm is a loose bound).
  const MonteCarloSummary& s = study().summary;
  EXPECT_NEAR(s.all[0].mean_m, s.all[1].mean_m, 0.02);
  EXPECT_LT(s.filtered_minus_ekf.median_m, 0.02);
}

TEST(MonteCarlo, BiasTruthIsInTheEstimatorConvention) {
  // Noise-free observations with integer ambiguities and phase breaks: a new
  // bias starts at phase minus code = the true IF bias exactly, so every bias
  // error must be ~0; a wrong truth (arc or wind-up convention) would show as
  // whole IF wind-up wavelengths (10.7 cm) or ambiguity-sized errors. The
  // a-priori ZWD is set to the truth: a wrong one would move the position and,
  // through the precise phases, the biases.
  MonteCarloOptions o = smallStudy();
  o.simulation.errors = ErrorModelConfig::none();
  o.simulation.errors.ambiguity.enabled = true;
  o.simulation.errors.phase_breaks.enabled = true;
  o.profiles = {FlightProfile::Figure8};
  o.duration_s = 240.0;
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, 0);
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  ASSERT_FALSE(f.truth.empty());
  // The true ZWD in the study's convention: at the receiver, or at the ellipsoid
  // (measurement_model.troposphere.zwd_at_ellipsoid).
  const double height_m = ecefToGeodetic(f.truth.front().trajectory.position_ecef_m).height_m;
  o.ppp.stochastic.initial_zwd_m = o.ppp.model.zwd_at_ellipsoid
                                       ? f.truth.front().zwd_m / standardWetDelayHeightRatio(height_m)
                                       : f.truth.front().zwd_m;
  // Noise-free codes: the code least-squares start is exact, so the method's 1 m
  // start prior is right here (the study's 30 m, monte_carlo.h, is for noisy
  // codes). Without it the weakly determined height/ZWD pair (the true ZWD
  // follows the +-20 m height of the figure8, the estimated one is a slow random
  // walk) moves the biases by up to 1.1 cm.
  o.ppp.stochastic.position.initial_sigma_m = 1.0;
  // Noise-free codes carry no correlated error either: white code weighting (with
  // the default 15-s Gauss-Markov model the 1-Hz codes weigh 30x less, and the same
  // height/ZWD freedom moves the biases by up to 1.6 cm).
  o.ppp.stochastic.code_correlation_time_s = 0.0;
  EXPECT_GT(f.breaks.size(), 0u);  // arcs restart inside the flight
  for (double lag : {0.0, 60.0}) {
    o.smoother_filtered_lag_s = lag;
    const MonteCarloFlightRun r = runMonteCarloFlight(o, 0);
    ASSERT_TRUE(r.failure.empty()) << r.failure;
    EXPECT_GT(r.bias_arcs_compared, 5u);
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const auto& b = r.bias[static_cast<std::size_t>(e)];
      ASSERT_FALSE(b.empty());
      double worst = 0.0;
      for (const auto& x : b) worst = std::max(worst, std::abs(static_cast<double>(x.error_m)));
      EXPECT_LT(worst, 0.01) << monteCarloEstimatorKey(e) << " lag " << lag;
    }
  }
}

TEST(MonteCarlo, FixedLagFilteredAndBatchSmoothedMatchTheFullSmoother) {
  // The fast mode (filtered from a 60-s fixed-lag smoother, smoothed from the
  // batch solve of all factors) against one full iSAM2 smoother.
  MonteCarloOptions o = smallStudy();
  o.smoother_filtered_lag_s = 60.0;
  const MonteCarloFlightRun fast = runMonteCarloFlight(o, 0);
  const MonteCarloFlightRun& full = study().flights[0];
  ASSERT_TRUE(fast.failure.empty()) << fast.failure;
  EXPECT_EQ(fast.error_3d_m[0], full.error_3d_m[0]);  // the EKF is the same run
  for (int e = 1; e < kMonteCarloEstimators; ++e) {
    double worst = 0.0;
    for (std::size_t k = 0; k < full.epochs; ++k)
      worst = std::max(worst, std::abs(fast.error_3d_m[static_cast<std::size_t>(e)][k] -
                                       full.error_3d_m[static_cast<std::size_t>(e)][k]));
    EXPECT_LT(worst, 0.01) << monteCarloEstimatorKey(e);
  }
}

TEST(MonteCarlo, SameSeedSameNumbersWhateverTheThreadCount) {
  MonteCarloOptions o = smallStudy();
  o.flights = 2;
  o.threads = 1;
  const MonteCarloResult a = runMonteCarlo(o);
  for (int i = 0; i < 2; ++i) {
    const auto& x = a.flights[static_cast<std::size_t>(i)];
    const auto& y = study().flights[static_cast<std::size_t>(i)];  // 2 threads, 3 flights
    EXPECT_EQ(x.setup.seed, y.setup.seed);
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const auto& ex = x.error_3d_m[static_cast<std::size_t>(e)];
      const auto& ey = y.error_3d_m[static_cast<std::size_t>(e)];
      ASSERT_EQ(ex.size(), ey.size());
      for (std::size_t k = 0; k < ex.size(); ++k)
        if (!(std::isnan(ex[k]) && std::isnan(ey[k]))) ASSERT_EQ(ex[k], ey[k]) << "flight " << i << " epoch " << k;
      ASSERT_EQ(x.bias[static_cast<std::size_t>(e)].size(), y.bias[static_cast<std::size_t>(e)].size());
    }
  }
  MonteCarloOptions other = o;
  other.seed = 43;
  const MonteCarloFlightRun z = runMonteCarloFlight(other, 0);
  EXPECT_NE(z.error_3d_m[0], a.flights[0].error_3d_m[0]);
}

TEST(MonteCarlo, OutputsAreWrittenAndTheJsonParses) {
  const MonteCarloResult& r = study();
  const std::filesystem::path dir = ppp::test::tempDir("monte_carlo");
  writeMonteCarloOutputs(r, dir.string());
  for (const char* f : {"summary.md", "summary.json", "flights.csv", "representative_flight.csv", "error_vs_time.csv",
                        "bias_convergence.csv", "error_cdf.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  // JSON is YAML 1.2: yaml-cpp parses it.
  const YAML::Node j = YAML::Load(readText(dir / "summary.json"));
  EXPECT_EQ(j["flights"].as<int>(), 3);
  for (const char* window : {"all_epochs", "first_window", "after_window", "representative"})
    for (int e = 0; e < kMonteCarloEstimators; ++e) {
      const YAML::Node t = j[window][monteCarloEstimatorKey(e)];
      ASSERT_TRUE(t.IsMap()) << window << " " << monteCarloEstimatorKey(e);
      for (const char* k : {"median_cm", "mean_cm", "sigma_cm", "max_cm"})
        EXPECT_TRUE(std::isfinite(t[k].as<double>())) << window << " " << k;
    }
  EXPECT_EQ(j["flight_table"].size(), 3u);
  const std::string md = readText(dir / "summary.md");
  for (int e = 0; e < kMonteCarloEstimators; ++e) EXPECT_NE(md.find(monteCarloEstimatorLabel(e)), std::string::npos);
  EXPECT_NE(md.find("First 1 minutes"), std::string::npos);
  // Representative flight CSV: header + one line per epoch.
  std::ifstream rep(dir / "representative_flight.csv");
  std::string line;
  int lines = 0;
  while (std::getline(rep, line)) ++lines;
  EXPECT_EQ(lines, 1 + 181);
}

TEST(MonteCarlo, InMemoryPipelineAndBatchSmootherRefuseMissingInputs) {
  EXPECT_THROW(PppPipeline(PppInMemoryInputs{}, PppConfig{}), std::invalid_argument);
  const PppSmoother not_recording;
  EXPECT_THROW(not_recording.batchSmoothedValues(), std::logic_error);
}

// A median convergence time that is never reached (most flights never stay below
// the threshold) reads "never (N of M flights)", not "inf min".
TEST(MonteCarlo, ConvergenceNeverReachedIsPrintedAsNeverWithTheCount) {
  EXPECT_EQ(convergenceTimeText(std::numeric_limits<double>::infinity(), 7, 10), "never (7 of 10 flights)");
  EXPECT_EQ(convergenceTimeText(750.0, 3, 10), "12.5 min (never: 3)");
  EXPECT_EQ(convergenceTimeText(std::nan(""), 0, 0), "no flights");
  // On the study: a threshold of 1 micrometre is never reached by any flight.
  MonteCarloResult r = study();
  r.options.convergence_thresholds_m = {1e-6, 100.0};
  r.summary = summarizeMonteCarlo(r.flights, r.options);
  for (int e = 0; e < kMonteCarloEstimators; ++e) {
    const auto ei = static_cast<std::size_t>(e);
    EXPECT_TRUE(std::isinf(r.summary.convergence_median_s[ei][0]));
    EXPECT_EQ(r.summary.convergence_never[ei][0], 3);
    EXPECT_TRUE(std::isfinite(r.summary.convergence_median_s[ei][1]));
  }
  const std::string md = monteCarloMarkdown(r);
  EXPECT_EQ(md.find("inf min"), std::string::npos) << md;
  EXPECT_NE(md.find("| never (3 of 3 flights) |"), std::string::npos) << md;
  EXPECT_NE(md.find(" min (never: 0) |"), std::string::npos) << md;
}

// The study's estimators run the method's preset (config/method_table.yaml) with
// the 30 m start prior of config/ppp_simulated.yaml, not the real-data defaults.
TEST(MonteCarlo, DefaultConfigIsTheMethodPresetWithTheSimulatedStartPrior) {
  const PppConfig study_config = MonteCarloOptions{}.ppp;
  const PppConfig method = methodTablePppConfig();
  EXPECT_EQ(study_config.stochastic.position.initial_sigma_m, 30.0);
  EXPECT_EQ(study_config.stochastic.position.process_noise_m_per_sqrt_s, method.stochastic.position.process_noise_m_per_sqrt_s);
  EXPECT_EQ(study_config.stochastic.zwd.initial_sigma_m, method.stochastic.zwd.initial_sigma_m);
  EXPECT_EQ(study_config.stochastic.clock.initial_sigma_m, method.stochastic.clock.initial_sigma_m);
  EXPECT_EQ(study_config.stochastic.phase_bias.initial_sigma_m, method.stochastic.phase_bias.initial_sigma_m);
  EXPECT_EQ(study_config.model.mapping, TroposphereMapping::ModifiedHopfield);
  // A flight's measurement model is the simulator's physics (Hopfield), whatever the config's.
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(smallStudy(), monteCarloFlightSetup(smallStudy(), 0)),
                                           monteCarloFlightSetup(smallStudy(), 0).seed);
  EXPECT_EQ(flightPppConfig(PppConfig{}, f).model.mapping, TroposphereMapping::ModifiedHopfield);
}

// The study relinearizes a state when its position moved by more than 0.5 m
// (config/ppp_simulated.yaml), not 0.01 m: without the Huber kernel the factors
// are nonlinear in the position only through the range, linear to
// 0.25 m^2 / (2 x 2e7 m) = 6e-9 m over 0.5 m. A flight's smoothed errors agree
// with the tight threshold's to below a micrometre (measured: 6e-8 m); the
// filtered ones to below the tables' millimetre (measured: 0.17 mm in the first
// minute of the figure8, when the position still moves by metres per epoch and
// its error is 1-2 m; 1e-5 m or less after it).
TEST(MonteCarlo, StudyRelinearizationThresholdChangesNoError) {
  MonteCarloOptions o = smallStudy();
  o.smoother_filtered_lag_s = 60.0;  // the study's fast mode: fixed lag + batch smoothed
  o.duration_s = 600.0;
  ASSERT_EQ(o.ppp.smoother.relinearize_position_m, 0.5);
  ASSERT_FALSE(o.ppp.smoother.robust);
  MonteCarloOptions tight = o;
  tight.ppp.smoother.relinearize_position_m = 0.01;
  for (int flight : {0, 1}) {  // loiter and figure8 (phase breaks in every turn)
    const MonteCarloFlightRun a = runMonteCarloFlight(o, flight);
    const MonteCarloFlightRun b = runMonteCarloFlight(tight, flight);
    ASSERT_TRUE(a.failure.empty() && b.failure.empty()) << a.failure << b.failure;
    EXPECT_EQ(a.error_3d_m[0], b.error_3d_m[0]);  // the EKF does not relinearize
    for (int e = 1; e < kMonteCarloEstimators; ++e) {
      const auto& x = a.error_3d_m[static_cast<std::size_t>(e)];
      const auto& y = b.error_3d_m[static_cast<std::size_t>(e)];
      ASSERT_EQ(x.size(), y.size());
      double worst = 0.0;
      std::size_t compared = 0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        ASSERT_EQ(std::isfinite(x[k]), std::isfinite(y[k])) << "epoch " << k;
        if (!std::isfinite(x[k])) continue;
        worst = std::max(worst, std::abs(x[k] - y[k]));
        ++compared;
      }
      EXPECT_GT(compared, x.size() / 2) << monteCarloEstimatorKey(e);
      const bool filtered = monteCarloEstimatorKey(e) == "smoother_filtered";
      EXPECT_LT(worst, filtered ? 1e-3 : 1e-6) << monteCarloEstimatorKey(e) << " flight " << flight;
    }
  }
}

// The study's smoothed solution through the registry's interface
// (SmoothedTrajectoryProvider::finalSmoothedSolution): a fixed-lag smoother that
// keeps its whole graph (record_graph) gives the full smoother's solution, states
// and arc biases; a filter gives none (smoothing() is nullptr).
TEST(MonteCarlo, FinalSmoothedSolutionOfAFixedLagSmootherWithItsGraphIsTheFullSmoothers) {
  const MonteCarloOptions o = smallStudy();
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, 1);  // figure8: phase breaks in the turns
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  const PppConfig full_config = flightPppConfig(o.ppp, f);
  PppConfig lag_config = full_config;
  lag_config.smoother.fixed_lag_s = 30.0;
  lag_config.smoother.record_graph = true;
  std::string why;
  std::vector<std::unique_ptr<PppEstimator>> runs;
  std::vector<std::set<std::pair<SatelliteId, ArcId>>> arcs;
  for (const PppConfig* c : {&full_config, static_cast<const PppConfig*>(&lag_config)}) {
    runs.push_back(makeEstimator("smoother", *c, &why));
    ASSERT_TRUE(runs.back()) << why;
    PppPipeline pipeline(in, *c);
    std::set<std::pair<SatelliteId, ArcId>>& seen = arcs.emplace_back();
    pipeline.run(*runs.back(), [&](const PppEpochRecord& rec) {
      for (const auto& r : rec.residuals) seen.insert({r.satellite, r.arc});
    });
  }
  ASSERT_EQ(arcs[0], arcs[1]);
  const SmoothedSolution full = runs[0]->smoothing()->finalSmoothedSolution();
  const SmoothedSolution lag = runs[1]->smoothing()->finalSmoothedSolution();
  ASSERT_GT(full.trajectory.size(), 150u);
  ASSERT_EQ(full.trajectory.size(), lag.trajectory.size());
  double worst_m = 0.0;
  for (std::size_t k = 0; k < full.trajectory.size(); ++k) {
    ASSERT_EQ(full.trajectory[k].time, lag.trajectory[k].time);
    worst_m = std::max(worst_m, (full.trajectory[k].state.position_ecef_m - lag.trajectory[k].state.position_ecef_m).norm());
  }
  EXPECT_LT(worst_m, 1e-4);
  // Every arc's bias, also those of the arcs the lag marginalized long before the end.
  ASSERT_GT(arcs[0].size(), 20u);
  double worst_bias_m = 0.0;
  for (const auto& [satellite, arc] : arcs[0]) {
    const std::optional<double> a = full.bias_m(satellite, arc), b = lag.bias_m(satellite, arc);
    ASSERT_TRUE(a && b) << satellite.toString() << " arc " << arc;
    worst_bias_m = std::max(worst_bias_m, std::abs(*a - *b));
  }
  EXPECT_LT(worst_bias_m, 1e-4);
  // Without its graph the fixed-lag smoother holds only the arcs of its window.
  PppConfig window_only = lag_config;
  window_only.smoother.record_graph = false;
  const std::unique_ptr<PppEstimator> windowed = makeEstimator("smoother", window_only, &why);
  PppPipeline(in, window_only).run(*windowed, [](const PppEpochRecord&) {});
  const SmoothedSolution w = windowed->smoothing()->finalSmoothedSolution();
  std::size_t held = 0;
  for (const auto& [satellite, arc] : arcs[0]) held += w.bias_m(satellite, arc) ? 1 : 0;
  EXPECT_LT(held, arcs[0].size());
  // A filter smooths nothing.
  EXPECT_EQ(makeEstimator("ekf", full_config, &why)->smoothing(), nullptr);
}
