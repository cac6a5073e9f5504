// PppConfig: YAML loading. Defaults equal the method's table (DEVELOPERS.md),
// the template config/ppp.yaml loads and restates the defaults, and malformed
// configurations give errors naming the file, the key path and the reason.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "ppp_bayes_tree/ppp/ppp_config.h"
#include "test_support.h"

using ppp::ConfigError;
using ppp::PppConfig;
using ppp::parsePppConfig;

namespace {

void expectSameDefaults(const PppConfig& c) {
  const PppConfig d;
  EXPECT_EQ(c.stochastic.position.initial_sigma_m, d.stochastic.position.initial_sigma_m);
  EXPECT_EQ(c.stochastic.position.process_noise_m_per_sqrt_s, d.stochastic.position.process_noise_m_per_sqrt_s);
  EXPECT_EQ(c.stochastic.position.kind, d.stochastic.position.kind);
  EXPECT_EQ(c.stochastic.zwd.initial_sigma_m, d.stochastic.zwd.initial_sigma_m);
  EXPECT_EQ(c.stochastic.zwd.process_noise_m_per_sqrt_s, d.stochastic.zwd.process_noise_m_per_sqrt_s);
  EXPECT_EQ(c.stochastic.initial_zwd_m, d.stochastic.initial_zwd_m);
  EXPECT_EQ(c.stochastic.clock.initial_sigma_m, d.stochastic.clock.initial_sigma_m);
  EXPECT_EQ(c.stochastic.clock.process_noise_m_per_sqrt_s, d.stochastic.clock.process_noise_m_per_sqrt_s);
  EXPECT_EQ(c.stochastic.clock.kind, d.stochastic.clock.kind);
  EXPECT_EQ(c.stochastic.phase_bias.initial_sigma_m, d.stochastic.phase_bias.initial_sigma_m);
  EXPECT_EQ(c.stochastic.phase_bias.process_noise_m_per_sqrt_s, d.stochastic.phase_bias.process_noise_m_per_sqrt_s);
  EXPECT_EQ(c.estimator.screening.min_satellites, d.estimator.screening.min_satellites);
  EXPECT_EQ(c.estimator.iterations_per_epoch, d.estimator.iterations_per_epoch);
  EXPECT_EQ(c.estimator.screening.prefit_code_threshold_m, d.estimator.screening.prefit_code_threshold_m);
  EXPECT_EQ(c.estimator.screening.prefit_phase_sigmas, d.estimator.screening.prefit_phase_sigmas);
  EXPECT_EQ(c.estimator.postfit_check, d.estimator.postfit_check);
  EXPECT_EQ(c.estimator.postfit_sigmas, d.estimator.postfit_sigmas);
  EXPECT_EQ(c.estimator.postfit_max_rejections, d.estimator.postfit_max_rejections);
  EXPECT_EQ(c.estimator.screening.clock_from_code_median, d.estimator.screening.clock_from_code_median);
  EXPECT_EQ(c.estimator.screening.stale_arc_timeout_s, d.estimator.screening.stale_arc_timeout_s);
  EXPECT_EQ(c.start.max_iterations, d.start.max_iterations);
  EXPECT_EQ(c.start.convergence_m, d.start.convergence_m);
  EXPECT_EQ(c.start.min_satellites, d.start.min_satellites);
  EXPECT_EQ(c.start.outlier_threshold_m, d.start.outlier_threshold_m);
}

/// The ConfigError of parsing `yaml`, or fails the test.
ConfigError errorOf(const std::string& yaml) {
  try {
    parsePppConfig(yaml, "bad.yaml");
  } catch (const ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "no ConfigError for:\n" << yaml;
  return ConfigError("", "", "");
}

}  // namespace

TEST(PppConfig, EmptyDocumentGivesTheMethodDefaults) {
  const PppConfig c = parsePppConfig("", "empty.yaml");
  expectSameDefaults(c);
  // The method's table (DEVELOPERS.md), restated in issue 3.
  EXPECT_EQ(c.stochastic.position.initial_sigma_m, 1.0);  // the method's table (DEVELOPERS.md)
  EXPECT_EQ(c.stochastic.position.process_noise_m_per_sqrt_s, 5.0);
  EXPECT_EQ(c.stochastic.zwd.initial_sigma_m, 0.3);
  EXPECT_EQ(c.stochastic.zwd.process_noise_m_per_sqrt_s, 3e-5);
  EXPECT_EQ(c.stochastic.clock.initial_sigma_m, 3e6);
  EXPECT_EQ(c.stochastic.clock.process_noise_m_per_sqrt_s, 2000.0);
  EXPECT_EQ(c.stochastic.phase_bias.initial_sigma_m, 100.0);
  EXPECT_EQ(c.stochastic.phase_bias.process_noise_m_per_sqrt_s, 0.0);
  EXPECT_EQ(c.source_name, "empty.yaml");
  EXPECT_TRUE(c.measurement_model.IsMap());
  EXPECT_EQ(c.measurement_model.size(), 0u);
}

TEST(PppConfig, TemplateLoadsAndRestatesEveryDefault) {
  const std::string path = std::string(PPP_REPO_DIR) + "/config/ppp.yaml";
  const PppConfig c = ppp::loadPppConfig(path);
  expectSameDefaults(c);
  EXPECT_EQ(c.source_name, path);
}

TEST(PppConfig, TemplateCommentsEveryKey) {
  // robot_localization style: every key line carries a comment with its default.
  std::ifstream in(std::string(PPP_REPO_DIR) + "/config/ppp.yaml");
  std::string line;
  int keys = 0;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos || line[first] == '#') continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    ++keys;
    const std::string rest = line.substr(colon + 1);
    const bool is_section = rest.find_first_not_of(' ') == std::string::npos || rest[rest.find_first_not_of(' ')] == '#';
    const bool opaque = rest.find("{}") != std::string::npos;
    if (is_section || opaque) continue;
    EXPECT_NE(line.find('#'), std::string::npos) << "no comment: " << line;
    EXPECT_NE(line.find("Default"), std::string::npos) << "no default stated: " << line;
  }
  EXPECT_GT(keys, 25);
}

TEST(PppConfig, ValuesAreBound) {
  const PppConfig c = parsePppConfig(R"(
stochastic:
  position: {initial_sigma_m: 2.5, process_noise_m_per_sqrt_s: 0.0}
  clock: {process: random_walk, process_noise_m_per_sqrt_s: 10}
estimator:
  min_satellites: 6
  postfit_check: false
  start: {outlier_threshold_m: 12.5}
measurement_model:
  elevation_cutoff_deg: 10
cycle_slip:
  melbourne_wuebbena: {sigma_factor: 4}
)", "x.yaml");
  EXPECT_EQ(c.stochastic.position.initial_sigma_m, 2.5);
  EXPECT_EQ(c.stochastic.position.process_noise_m_per_sqrt_s, 0.0);
  EXPECT_EQ(c.stochastic.clock.kind, ppp::ProcessKind::RandomWalk);
  EXPECT_EQ(c.stochastic.clock.process_noise_m_per_sqrt_s, 10.0);
  EXPECT_EQ(c.stochastic.clock.initial_sigma_m, 3e6);  // untouched default
  EXPECT_EQ(c.estimator.screening.min_satellites, 6);
  EXPECT_FALSE(c.estimator.postfit_check);
  EXPECT_EQ(c.start.outlier_threshold_m, 12.5);
  // The model sections are bound at load (ppp_options_binding.h); raw copies are kept.
  EXPECT_NEAR(c.model.elevation_cutoff_rad, 10.0 * ppp::kDegToRad, 1e-15);
  EXPECT_EQ(c.cycle_slip_options.mw_sigma_factor, 4.0);
  EXPECT_EQ(c.measurement_model["elevation_cutoff_deg"].as<double>(), 10.0);
  // An unknown key of a model section is an error at load.
  try {
    parsePppConfig("cycle_slip:\n  mw_threshold_cycles: 4\n", "x.yaml");
    ADD_FAILURE() << "expected an unknown-key error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "cycle_slip.mw_threshold_cycles");
  }
}

TEST(PppConfig, MalformedConfigsNameFileKeyAndReason) {
  struct Case {
    const char* yaml;
    const char* key_path;
    const char* reason_part;
  };
  const Case cases[] = {
      {"stochastic:\n  positon: {initial_sigma_m: 1}\n", "stochastic.positon", "unknown key"},
      {"estimatr: {}\n", "estimatr", "unknown key"},
      {"stochastic:\n  clock:\n    initial_sigma_m: -3\n", "stochastic.clock.initial_sigma_m", "must be > 0"},
      {"stochastic:\n  zwd:\n    process_noise_m_per_sqrt_s: -1e-5\n", "stochastic.zwd.process_noise_m_per_sqrt_s",
       "must be >= 0"},
      {"stochastic:\n  position:\n    initial_sigma_m: abc\n", "stochastic.position.initial_sigma_m",
       "expected a number, got 'abc'"},
      {"stochastic:\n  position:\n    initial_sigma_m: [1, 2]\n", "stochastic.position.initial_sigma_m",
       "expected a single value"},
      {"stochastic:\n  position:\n    initial_sigma_m: .nan\n", "stochastic.position.initial_sigma_m",
       "finite"},
      {"estimator:\n  min_satellites: 4.5\n", "estimator.min_satellites", "expected an integer"},
      {"estimator:\n  iterations_per_epoch: 0\n", "estimator.iterations_per_epoch", "must be >= 1"},
      {"estimator:\n  postfit_check: maybe\n", "estimator.postfit_check", "expected true or false"},
      {"stochastic:\n  clock:\n    process: pink\n", "stochastic.clock.process", "expected one of"},
      {"stochastic: 3\n", "stochastic", "expected a mapping"},
      {"measurement_model: [a, b]\n", "measurement_model", "expected a mapping"},
      {"estimator:\n  start:\n    min_satellites: 3\n", "estimator.start.min_satellites", "must be >= 4"},
  };
  for (const auto& c : cases) {
    const ConfigError e = errorOf(c.yaml);
    EXPECT_EQ(e.file(), "bad.yaml") << c.yaml;
    EXPECT_EQ(e.keyPath(), c.key_path) << c.yaml;
    EXPECT_NE(e.reason().find(c.reason_part), std::string::npos) << c.yaml << " -> " << e.what();
    EXPECT_NE(std::string(e.what()).find(std::string("bad.yaml: ") + c.key_path), std::string::npos) << e.what();
  }
}

TEST(PppConfig, SyntaxErrorAndMissingFile) {
  const ConfigError syntax = errorOf("stochastic:\n  position: {initial_sigma_m: 1\n");
  EXPECT_EQ(syntax.keyPath(), "");
  EXPECT_NE(syntax.reason().find("YAML syntax error at line"), std::string::npos) << syntax.what();
  try {
    ppp::loadPppConfig("/nonexistent/ppp.yaml");
    ADD_FAILURE() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/ppp.yaml");
    EXPECT_NE(e.reason().find("cannot open"), std::string::npos);
  }
}

TEST(PppConfig, GarbageAndMutatedTemplatesOnlyEverThrowConfigError) {
  const std::string base = ppp::test::readFileBytes(std::string(PPP_REPO_DIR) + "/config/ppp.yaml");
  ASSERT_FALSE(base.empty());
  std::mt19937 rng(7);
  int errors = 0, loaded = 0;
  for (int i = 0; i < 300; ++i) {
    std::string text = base;
    if (i % 3 == 0) {  // random bytes
      text.assign(static_cast<std::size_t>(rng() % 300), '\0');
      for (auto& c : text) c = static_cast<char>(rng() % 256);
    } else {  // a few byte mutations of the template
      for (int k = 0; k < 1 + i % 5; ++k) text[rng() % text.size()] = static_cast<char>(rng() % 128);
    }
    try {
      parsePppConfig(text, "mutated.yaml");
      ++loaded;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), "mutated.yaml");
      ++errors;
    }
  }
  EXPECT_GT(errors, 50);  // the fuzzing did produce malformed documents
}
