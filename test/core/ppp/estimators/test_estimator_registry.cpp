// The estimator registry (ppp/estimators/estimator_registry.h): every registered name
// round-trips through the option parser and the factory, an unknown name is
// refused with the registered names listed, every registered estimator solves a
// short simulated flight through the offline pipeline, the Monte Carlo studies
// the registry's estimators, and no source outside the registry and the
// estimators' own files constructs an estimator class directly.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

namespace ppp {
namespace {

TEST(EstimatorRegistry, NamesRoundTripThroughTheParserAndTheFactory) {
  ASSERT_FALSE(kEstimators.empty());
  std::set<std::string> tags;
  for (const EstimatorEntry& entry : kEstimators) {
    const std::string name(entry.name);
    SCOPED_TRACE(name);
    EXPECT_FALSE(entry.description.empty());
    EXPECT_EQ(findEstimator(name), &entry);
    const auto selected = selectEstimators(name);
    ASSERT_TRUE(selected.has_value());
    ASSERT_EQ(selected->size(), 1u);
    EXPECT_EQ(selected->front(), &entry);
    EXPECT_EQ(estimatorChoices().count(name), 1u);
    std::string why;
    const std::unique_ptr<PppEstimator> estimator = makeEstimator(name, PppConfig{}, &why);
    ASSERT_TRUE(estimator) << why;
    EXPECT_EQ(estimator->name(), name);
    // What the table says about the solutions is what the estimator gives.
    EXPECT_EQ(entry.smoothed(), estimator->smoothing() != nullptr);
    // makeEstimator is the row's factory: the same class.
    const std::unique_ptr<PppEstimator> from_row = entry.make(PppConfig{});
    ASSERT_TRUE(from_row);
    EXPECT_EQ(typeid(*from_row), typeid(*estimator));
    EXPECT_EQ(runsInAll(entry), entry.state == EstimatedState::GnssReceiver);
    EXPECT_FALSE(estimatedStateText(entry.state).empty());
    const std::vector<EstimatorSolution> solutions = solutionOutputs(entry);
    ASSERT_EQ(static_cast<int>(solutions.size()), entry.solutionCount());
    EXPECT_FALSE(solutions.front().smoothed);
    for (const EstimatorSolution& s : solutions) {
      EXPECT_EQ(s.tag.rfind(name, 0), 0u) << s.tag;  // file names start with the estimator's name
      EXPECT_TRUE(tags.insert(s.tag).second) << "tag " << s.tag << " given twice";
    }
  }
  // "both" selects the estimators of the GNSS receiver state, in the table's order:
  // the EKF and the smoother, not the GNSS/INS filter (it needs IMU readings).
  const auto all = selectEstimators(kAllEstimators);
  ASSERT_TRUE(all.has_value());
  std::vector<std::string_view> all_names;
  for (const EstimatorEntry* e : *all) all_names.push_back(e->name);
  EXPECT_EQ(all_names, (std::vector<std::string_view>{"ekf", "smoother"}));
  ASSERT_NE(findEstimator("ekf_ins"), nullptr);
  EXPECT_EQ(findEstimator("ekf_ins")->state, EstimatedState::GnssInertial);
  EXPECT_FALSE(runsInAll(*findEstimator("ekf_ins")));
  EXPECT_EQ(estimatorChoices().size(), kEstimators.size() + 1);
  EXPECT_EQ(kDefaultEstimator, kEstimators.front().name);
  EXPECT_EQ(registeredSolutionCount(), static_cast<int>(tags.size()));
}

/// `text` names every registered estimator.
void expectListsEveryEstimator(const std::string& text) {
  for (const EstimatorEntry& e : kEstimators)
    EXPECT_NE(text.find(std::string(e.name)), std::string::npos) << "'" << e.name << "' missing in: " << text;
}

/// What ppp_solve's entry point says refusing `estimator` on files that do not
/// exist (it must refuse before reading any); empty, with a failure, when it ran.
std::string refusalBeforeAnyFile(const std::string& estimator) {
  PppSolveRequest request;
  request.estimator = estimator;
  request.files.obs = "/nonexistent/obs.rnx";
  request.out_dir = "/nonexistent/out";
  try {
    solvePppEstimators(request);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "estimator '" << estimator << "' was accepted";
  return {};
}

TEST(EstimatorRegistry, UnknownNameIsRefusedWithTheRegisteredNames) {
  std::string why;
  EXPECT_FALSE(selectEstimators("kalman", &why).has_value());
  EXPECT_NE(why.find("unknown estimator 'kalman'"), std::string::npos) << why;
  expectListsEveryEstimator(why);
  EXPECT_NE(why.find(std::string(kAllEstimators)), std::string::npos) << why;
  EXPECT_FALSE(selectEstimators("", &why).has_value());
  EXPECT_FALSE(selectEstimators("EKF").has_value());  // names are case-sensitive

  why.clear();
  EXPECT_EQ(makeEstimator("kalman", PppConfig{}, &why), nullptr);
  expectListsEveryEstimator(why);
  // "both" is no single estimator: the caller runs one pipeline per estimator.
  why.clear();
  EXPECT_EQ(makeEstimator(std::string(kAllEstimators), PppConfig{}, &why), nullptr);
  EXPECT_NE(why.find("run by the caller as ekf and smoother (one pipeline each)"), std::string::npos) << why;

  // ppp_solve's entry point refuses it before reading any file.
  expectListsEveryEstimator(refusalBeforeAnyFile("kalman"));
}

// Each registered estimator of the GNSS receiver state, made by its factory, through the offline pipeline
// on a 4-minute simulated loiter flight (GPS, the Monte Carlo's error model and
// estimator configuration): it solves nearly every epoch and converges below
// 1 m (measured at seed 7: 241 of 241 epochs solved by both, mean 3D error of
// the last minute 0.643 m EKF, 0.644 m smoother filtered: the code-dominated
// start of a 4-minute flight); a smoothing estimator's smoothed trajectory
// covers the solved epochs.
TEST(EstimatorRegistry, EveryRegisteredEstimatorSolvesASimulatedFlight) {
  MonteCarloOptions o;
  o.flights = 1;
  o.seed = 7;
  o.duration_s = 240.0;
  o.profiles = {FlightProfile::Loiter};
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(o, 0);
  const SimulatedFlight f = simulateFlight(monteCarloSimulationConfig(o, setup), setup.seed);
  const PppConfig config = flightPppConfig(o.ppp, f);
  PppInMemoryInputs in;
  in.header = &f.header;
  in.epochs = &f.epochs;
  in.products = &f.products;
  for (const EstimatorEntry& entry : kEstimators) {
    SCOPED_TRACE(std::string(entry.name));
    if (entry.state == EstimatedState::GnssInertial) continue;  // needs IMU readings: test_ppp_ins_ekf
    PppPipeline pipeline(in, config);
    const std::unique_ptr<PppEstimator> estimator = makeEstimator(entry.name, config);
    ASSERT_TRUE(estimator);
    std::size_t k = 0, solved = 0;
    double last_minute_sum_m = 0.0;
    std::size_t last_minute_n = 0;
    pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
      const std::size_t e = k++;
      if (!rec.solution.position_ecef_m) return;
      ++solved;
      if (f.epochs[e].time - f.epochs.front().time < o.duration_s - 60.0) return;
      last_minute_sum_m += (*rec.solution.position_ecef_m - f.truth[e].trajectory.position_ecef_m).norm();
      ++last_minute_n;
    });
    ASSERT_EQ(k, f.epochs.size());
    EXPECT_GE(solved, k * 95 / 100);
    ASSERT_GT(last_minute_n, 0u);
    const double last_minute_mean_m = last_minute_sum_m / static_cast<double>(last_minute_n);
    std::printf("%s: %zu of %zu epochs solved, mean 3D error of the last minute %.3f m\n",
                std::string(entry.name).c_str(), solved, k, last_minute_mean_m);
    EXPECT_LT(last_minute_mean_m, 1.0);
    if (entry.smoothed()) {
      ASSERT_NE(estimator->smoothing(), nullptr);
      EXPECT_EQ(estimator->smoothing()->smoothedTrajectory().size(), solved);
    }
  }
}

// An estimator with inertial states is refused without IMU readings, before any
// file is read (ppp_solve --estimator ekf_ins needs --imu).
TEST(EstimatorRegistry, AnInertialEstimatorWithoutImuReadingsIsRefusedBeforeAnyFile) {
  const std::string why = refusalBeforeAnyFile("ekf_ins");
  EXPECT_NE(why.find("'ekf_ins' needs IMU readings (ppp_solve --imu FILE)"), std::string::npos) << why;
}

TEST(EstimatorRegistry, AsTheClassAskedForOrRefused) {
  std::string why;
  const std::unique_ptr<PppSmoother> smoother = makeEstimatorAs<PppSmoother>("smoother", PppConfig{}, &why);
  ASSERT_TRUE(smoother) << why;
  EXPECT_EQ(smoother->smoothing(), smoother.get());
  EXPECT_TRUE(makeEstimatorAs<PppEkf>("ekf", PppConfig{}, &why));
  why.clear();
  EXPECT_EQ(makeEstimatorAs<PppSmoother>("ekf", PppConfig{}, &why), nullptr);
  EXPECT_NE(why.find("'ekf' is not of the class asked for"), std::string::npos) << why;
  why.clear();
  EXPECT_EQ(makeEstimatorAs<PppEkf>("kalman", PppConfig{}, &why), nullptr);
  expectListsEveryEstimator(why);
}

// The Monte Carlo study runs the registry's rows marked for it, in registry
// order, and its columns are their solutions.
TEST(EstimatorRegistry, MonteCarloStudiesTheRegisteredEstimators) {
  std::vector<std::string_view> marked;
  int solutions = 0;
  for (const EstimatorEntry& e : kEstimators) {
    if (!e.monte_carlo_study) continue;
    marked.push_back(e.name);
    solutions += e.solutionCount();
  }
  ASSERT_EQ(kMonteCarloStudy.size(), marked.size());
  for (std::size_t i = 0; i < marked.size(); ++i) EXPECT_EQ(kMonteCarloStudy[i], marked[i]);
  EXPECT_EQ(kMonteCarloEstimators, solutions);
  ASSERT_FALSE(kMonteCarloStudy.empty());
  EXPECT_EQ(kMonteCarloStudy.front(), "ekf");  // the study's reference
  for (const std::string_view name : kMonteCarloStudy) {
    SCOPED_TRACE(std::string(name));
    const std::unique_ptr<PppEstimator> estimator = makeEstimator(name, PppConfig{});
    ASSERT_TRUE(estimator);
    EXPECT_EQ(estimator->name(), name);
  }
}

namespace fs = std::filesystem;

std::string readText(const fs::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The estimator classes: every class under include/ derived from PppEstimator,
/// directly or through another estimator class (`class X : public PppEkf`).
std::set<std::string> estimatorClasses(const fs::path& include_dir) {
  static const std::regex derived(R"(class\s+(\w+)\s*(final\s*)?:\s*public\s+(\w+)\b)");
  std::vector<std::pair<std::string, std::string>> class_base;
  for (const auto& entry : fs::recursive_directory_iterator(include_dir)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".h") continue;
    const std::string text = readText(entry.path());
    for (std::sregex_iterator it(text.begin(), text.end(), derived), end; it != end; ++it)
      class_base.emplace_back((*it)[1], (*it)[3]);
  }
  std::set<std::string> classes;
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [c, base] : class_base)
      if ((base == "PppEstimator" || classes.count(base)) && classes.insert(c).second) grew = true;
  }
  return classes;
}

/// The lines of `text` (comments left out) that construct one of `classes`
/// directly: a variable or member of the class (`PppEkf ekf(c);`), a temporary
/// (`PppEkf(c)`), make_unique / make_shared or new. References and pointers are fine.
std::vector<std::string> directConstructions(const std::string& text, const std::set<std::string>& classes) {
  // One pattern per class, built once; a line is matched only when it names a class.
  std::vector<std::pair<std::string, std::regex>> patterns;
  for (const std::string& c : classes)
    patterns.emplace_back(c, std::regex("(make_unique|make_shared)\\s*<\\s*(ppp::)?" + c + "\\s*>|\\bnew\\s+(ppp::)?" +
                                        c + "\\b|(^|[^\\w:~&*<])(ppp::)?" + c + "\\b\\s*(\\w+\\s*)?[({;]"));
  std::vector<std::string> hits;
  std::istringstream lines(text);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    ++n;
    const std::string code = line.substr(0, line.find("//"));
    for (const auto& [c, construct] : patterns) {
      if (code.find(c) == std::string::npos) continue;
      if (std::regex_search(code, construct)) hits.push_back(std::to_string(n) + ": " + line);
    }
  }
  return hits;
}

TEST(EstimatorRegistry, TheConstructionCheckFindsAPlantedConstruction) {
  const std::set<std::string> classes{"PppEkf", "PppSmoother"};
  EXPECT_EQ(directConstructions("  PppEkf ekf(config);\n", classes).size(), 1u);
  EXPECT_EQ(directConstructions("  ppp::PppSmoother sm{config};\n", classes).size(), 1u);
  EXPECT_EQ(directConstructions("  auto sm = std::make_unique<PppSmoother>(config);\n", classes).size(), 1u);
  EXPECT_EQ(directConstructions("  return PppEkf(model);\n", classes).size(), 1u);
  EXPECT_EQ(directConstructions("  PppEkf* e = new PppEkf;\n", classes).size(), 1u);
  // A longer name that starts with a class's name is another type.
  EXPECT_TRUE(directConstructions("struct PppSmootherOptions {\n  PppEkfOptions ekf;\n", classes).empty());
  // Reaching a made estimator, naming the class in a comment or a type: no construction.
  EXPECT_TRUE(directConstructions("  PppSmoother& sm = *made;\n  const PppEkf* e = nullptr;\n"
                                  "  // the EKF (PppEkf) is made by the registry\n"
                                  "  auto s = makeEstimatorAs<PppSmoother>(\"smoother\", c);\n"
                                  "  dynamic_cast<ppp::PppSmoother*>(&estimator);\n",
                                  classes)
                  .empty());
}

// The registry is the only place that makes an estimator: no tool, benchmark,
// node, study or part of the core constructs an estimator class directly.
// (The estimators' own files and the registry are where they are defined and made;
// the unit tests of one estimator class build it directly.)
TEST(EstimatorRegistry, NoSourceOutsideTheRegistryConstructsAnEstimator) {
  const fs::path repo = PPP_REPO_DIR;
  const std::set<std::string> classes = estimatorClasses(repo / "include" / "ppp_bayes_tree");
  EXPECT_EQ(classes, (std::set<std::string>{"PppEkf", "PppInsEkf", "PppInsSmoother", "PppSmoother"}));
  const std::set<std::string> own{"ppp_estimator", "ppp_ekf",          "ppp_ins_ekf",
                                  "ppp_smoother",  "ppp_ins_smoother", "estimator_registry"};
  std::vector<std::string> hits;
  std::size_t files = 0;
  for (const fs::path& root : {repo / "src", repo / "include" / "ppp_bayes_tree"}) {
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
      const fs::path& p = entry.path();
      if (!entry.is_regular_file() || (p.extension() != ".cpp" && p.extension() != ".h")) continue;
      if (p.parent_path().filename() == "estimators" && own.count(p.stem().string())) continue;
      ++files;
      for (const std::string& h : directConstructions(readText(p), classes)) hits.push_back(p.string() + ":" + h);
    }
  }
  EXPECT_GT(files, 100u);
  for (const std::string& h : hits) ADD_FAILURE() << "an estimator made outside the registry: " << h;
}

}  // namespace
}  // namespace ppp
