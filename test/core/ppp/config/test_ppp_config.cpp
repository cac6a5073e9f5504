// PppConfig: YAML loading. The defaults are the real-data values, the template
// config/ppp.yaml loads to exactly them, the preset config/method_table.yaml to
// the method's table, and malformed configurations (keys given
// twice, quoted numbers, unknown keys...) give errors naming the file, the key
// path (or lines) and the reason.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <vector>

#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "test_support.h"

using ppp::ConfigError;
using ppp::PppConfig;
using ppp::parsePppConfig;

namespace {

void expectSameNoise(const ppp::StateNoise& a, const ppp::StateNoise& b, const char* name) {
  EXPECT_EQ(a.initial_sigma_m, b.initial_sigma_m) << name;
  EXPECT_EQ(a.process_noise_m_per_sqrt_s, b.process_noise_m_per_sqrt_s) << name;
  EXPECT_EQ(a.kind, b.kind) << name;
}

/// Every bound value of two configurations is equal (the raw sections aside).
void expectSameConfig(const PppConfig& c, const PppConfig& d) {
  expectSameNoise(c.stochastic.position, d.stochastic.position, "position");
  expectSameNoise(c.stochastic.zwd, d.stochastic.zwd, "zwd");
  expectSameNoise(c.stochastic.clock, d.stochastic.clock, "clock");
  expectSameNoise(c.stochastic.phase_bias, d.stochastic.phase_bias, "phase_bias");
  expectSameNoise(c.stochastic.troposphere_gradient, d.stochastic.troposphere_gradient, "troposphere_gradient");
  EXPECT_EQ(c.stochastic.initial_zwd_m, d.stochastic.initial_zwd_m);
  EXPECT_EQ(c.stochastic.zwd_per_sqrt_height_m_per_sqrt_m, d.stochastic.zwd_per_sqrt_height_m_per_sqrt_m);
  EXPECT_EQ(c.stochastic.zwd_height_change_threshold_sigmas, d.stochastic.zwd_height_change_threshold_sigmas);
  EXPECT_EQ(c.stochastic.code_correlation_time_s, d.stochastic.code_correlation_time_s);
  EXPECT_EQ(c.estimator.screening.min_satellites, d.estimator.screening.min_satellites);
  EXPECT_EQ(c.estimator.iterations_per_epoch, d.estimator.iterations_per_epoch);
  EXPECT_EQ(c.estimator.screening.prefit_code_threshold_m, d.estimator.screening.prefit_code_threshold_m);
  EXPECT_EQ(c.estimator.screening.prefit_phase_sigmas, d.estimator.screening.prefit_phase_sigmas);
  EXPECT_EQ(c.estimator.screening.postfit_check, d.estimator.screening.postfit_check);
  EXPECT_EQ(c.estimator.screening.postfit_sigmas, d.estimator.screening.postfit_sigmas);
  EXPECT_EQ(c.estimator.screening.postfit_max_rejections, d.estimator.screening.postfit_max_rejections);
  EXPECT_EQ(c.estimator.screening.consistency_check, d.estimator.screening.consistency_check);
  EXPECT_EQ(c.estimator.screening.consistency_false_alarm, d.estimator.screening.consistency_false_alarm);
  EXPECT_EQ(c.estimator.screening.consistency_action, d.estimator.screening.consistency_action);
  EXPECT_EQ(c.estimator.screening.clock_from_code_median, d.estimator.screening.clock_from_code_median);
  EXPECT_EQ(c.estimator.screening.stale_arc_timeout_s, d.estimator.screening.stale_arc_timeout_s);
  EXPECT_EQ(c.start.max_iterations, d.start.max_iterations);
  EXPECT_EQ(c.start.convergence_m, d.start.convergence_m);
  EXPECT_EQ(c.start.min_satellites, d.start.min_satellites);
  EXPECT_EQ(c.start.outlier_threshold_m, d.start.outlier_threshold_m);
  EXPECT_EQ(c.smoother.robust, d.smoother.robust);
  EXPECT_EQ(c.smoother.huber_width_sigmas, d.smoother.huber_width_sigmas);
  EXPECT_EQ(c.smoother.relinearize_position_m, d.smoother.relinearize_position_m);
  EXPECT_EQ(c.smoother.relinearize_zwd_m, d.smoother.relinearize_zwd_m);
  EXPECT_EQ(c.smoother.relinearize_clock_m, d.smoother.relinearize_clock_m);
  EXPECT_EQ(c.smoother.relinearize_bias_m, d.smoother.relinearize_bias_m);
  EXPECT_EQ(c.smoother.relinearize_skip, d.smoother.relinearize_skip);
  EXPECT_EQ(c.smoother.wildfire_threshold_m, d.smoother.wildfire_threshold_m);
  EXPECT_EQ(c.smoother.exact_range, d.smoother.exact_range);
  EXPECT_EQ(c.smoother.fixed_lag_s, d.smoother.fixed_lag_s);
  const auto& ca = c.ambiguity_resolution;
  const auto& da = d.ambiguity_resolution;
  EXPECT_EQ(ca.enabled, da.enabled);
  EXPECT_EQ(ca.mode, da.mode);
  EXPECT_NEAR(ca.min_elevation_rad, da.min_elevation_rad, 1e-15);
  EXPECT_EQ(ca.narrow_lane.ratio_threshold, da.narrow_lane.ratio_threshold);
  EXPECT_EQ(ca.narrow_lane.min_success_rate, da.narrow_lane.min_success_rate);
  EXPECT_EQ(ca.narrow_lane.min_fixed, da.narrow_lane.min_fixed);
  EXPECT_EQ(ca.narrow_lane.partial, da.narrow_lane.partial);
  EXPECT_EQ(ca.wide_lane.min_samples, da.wide_lane.min_samples);
  EXPECT_EQ(ca.wide_lane.min_success_rate, da.wide_lane.min_success_rate);
  EXPECT_EQ(ca.wide_lane.correlation_time_s, da.wide_lane.correlation_time_s);
  EXPECT_EQ(ca.wide_lane.max_fraction_cycles, da.wide_lane.max_fraction_cycles);
  EXPECT_EQ(ca.hold.consistency_epochs, da.hold.consistency_epochs);
  EXPECT_EQ(ca.hold.max_float_spread_cycles, da.hold.max_float_spread_cycles);
  EXPECT_EQ(ca.hold.max_float_drift_sigmas, da.hold.max_float_drift_sigmas);
  EXPECT_EQ(ca.hold.validation_epochs, da.hold.validation_epochs);
  EXPECT_EQ(ca.hold.require_subset_success_rate, da.hold.require_subset_success_rate);
  EXPECT_EQ(ca.hold.small_subset_max_size, da.hold.small_subset_max_size);
  EXPECT_EQ(ca.hold.fast_validation_success_rate, da.hold.fast_validation_success_rate);
  EXPECT_EQ(ca.hold.fast_validation_epochs, da.hold.fast_validation_epochs);
  EXPECT_EQ(ca.hold.max_fraction_cycles, da.hold.max_fraction_cycles);
  EXPECT_EQ(ca.hold.max_sigma_cycles, da.hold.max_sigma_cycles);
  EXPECT_EQ(ca.hold.release_cycles, da.hold.release_cycles);
  EXPECT_EQ(ca.hold.release_sigma, da.hold.release_sigma);
  // The file holds degrees: equal to the rounding of deg -> rad.
  EXPECT_NEAR(c.model.elevation_cutoff_rad, d.model.elevation_cutoff_rad, 1e-15);
  EXPECT_EQ(c.model.phase_sigma_zenith_m, d.model.phase_sigma_zenith_m);
  EXPECT_EQ(c.model.code_phase_ratio, d.model.code_phase_ratio);
  EXPECT_EQ(c.model.scale_sigma_for_ionosphere_free, d.model.scale_sigma_for_ionosphere_free);
  EXPECT_EQ(c.model.dry_troposphere, d.model.dry_troposphere);
  EXPECT_EQ(c.model.mapping, d.model.mapping);
  EXPECT_EQ(c.model.estimate_troposphere_gradients, d.model.estimate_troposphere_gradients);
  EXPECT_EQ(c.model.solid_earth_tide, d.model.solid_earth_tide);
  EXPECT_EQ(c.model.ocean_loading, d.model.ocean_loading);
  EXPECT_EQ(c.model.phase_windup, d.model.phase_windup);
  EXPECT_EQ(c.model.satellite_antenna, d.model.satellite_antenna);
  EXPECT_EQ(c.model.receiver_antenna, d.model.receiver_antenna);
  EXPECT_EQ(c.model.shapiro, d.model.shapiro);
  EXPECT_EQ(c.model.exclude_eclipse, d.model.exclude_eclipse);
  EXPECT_EQ(c.model.yaw_manoeuvre, d.model.yaw_manoeuvre);
  EXPECT_EQ(c.signals.systems, d.signals.systems);
  EXPECT_EQ(c.signals.systems_from_products, d.signals.systems_from_products);
  EXPECT_EQ(c.signals.require_code_osb, d.signals.require_code_osb);
  EXPECT_EQ(c.signals.phase_shift, d.signals.phase_shift);
  for (const auto& row : ppp::signalTable()) {  // every system's row of the signal table
    const ppp::SystemSignalPriority* a = &c.signals.priorities[row.system];
    const ppp::SystemSignalPriority* b = &d.signals.priorities[row.system];
    EXPECT_EQ(a->band1, b->band1);
    EXPECT_EQ(a->band2, b->band2);
    EXPECT_EQ(a->code1_attributes, b->code1_attributes);
    EXPECT_EQ(a->code2_attributes, b->code2_attributes);
    EXPECT_EQ(a->phase1_attributes, b->phase1_attributes);
    EXPECT_EQ(a->phase2_attributes, b->phase2_attributes);
  }
  const ppp::CycleSlipOptions& x = c.cycle_slip_options;
  const ppp::CycleSlipOptions& y = d.cycle_slip_options;
  EXPECT_EQ(x.mw_sigma_factor, y.mw_sigma_factor);
  EXPECT_EQ(x.mw_min_threshold_cycles, y.mw_min_threshold_cycles);
  EXPECT_EQ(x.mw_initial_sigma_cycles, y.mw_initial_sigma_cycles);
  EXPECT_EQ(x.mw_min_samples, y.mw_min_samples);
  EXPECT_EQ(x.mw_window, y.mw_window);
  EXPECT_EQ(x.gf_threshold_base_m, y.gf_threshold_base_m);
  EXPECT_EQ(x.gf_threshold_rate_mps, y.gf_threshold_rate_mps);
  EXPECT_EQ(x.gf_threshold_max_m, y.gf_threshold_max_m);
  EXPECT_EQ(x.gf_fit_points, y.gf_fit_points);
  EXPECT_EQ(x.gf_drift_allowance_mps, y.gf_drift_allowance_mps);
  EXPECT_EQ(x.gf_sigma_factor, y.gf_sigma_factor);
  EXPECT_EQ(x.gf_min_samples, y.gf_min_samples);
  EXPECT_EQ(x.max_gap_s, y.max_gap_s);
  EXPECT_EQ(x.max_gap_intervals, y.max_gap_intervals);
  EXPECT_EQ(x.default_interval_s, y.default_interval_s);
  EXPECT_EQ(x.use_loss_of_lock, y.use_loss_of_lock);
  const ppp::SlipRepairOptions& r = x.slip_repair;
  const ppp::SlipRepairOptions& q = y.slip_repair;
  EXPECT_EQ(r.enabled, q.enabled);
  EXPECT_EQ(r.max_wide_lane_offset_cycles, q.max_wide_lane_offset_cycles);
  EXPECT_EQ(r.max_wide_lane_sigma_cycles, q.max_wide_lane_sigma_cycles);
  EXPECT_EQ(r.max_l1_fraction_cycles, q.max_l1_fraction_cycles);
  EXPECT_EQ(r.max_l1_sigma_cycles, q.max_l1_sigma_cycles);
  EXPECT_EQ(r.gf_fit_window_s, q.gf_fit_window_s);
  EXPECT_EQ(r.gf_fit_min_points, q.gf_fit_min_points);
  EXPECT_EQ(r.gf_fit_order, q.gf_fit_order);
  EXPECT_EQ(r.phase_sigma_m, q.phase_sigma_m);
  EXPECT_EQ(r.ionosphere_sigma_mps, q.ionosphere_sigma_mps);
  EXPECT_EQ(r.max_candidate_wide_lane_sigma_cycles, q.max_candidate_wide_lane_sigma_cycles);
  EXPECT_EQ(r.candidate_sigma_factor, q.candidate_sigma_factor);
  EXPECT_EQ(r.min_candidate_half_width_cycles, q.min_candidate_half_width_cycles);
  EXPECT_EQ(r.max_candidates, q.max_candidates);
  EXPECT_EQ(r.max_joint_misfit, q.max_joint_misfit);
}

void expectSameDefaults(const PppConfig& c) { expectSameConfig(c, PppConfig{}); }

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

TEST(PppConfig, EmptyDocumentGivesTheRealDataDefaults) {
  const PppConfig c = parsePppConfig("", "empty.yaml");
  expectSameDefaults(c);
  // The method's table except the start prior and the mapping
  // (the real-data values of the former config/ppp_real_data.yaml).
  EXPECT_EQ(c.stochastic.position.initial_sigma_m, 30.0);
  EXPECT_EQ(c.model.mapping, ppp::TroposphereMapping::Gmf);
  EXPECT_EQ(c.stochastic.position.process_noise_m_per_sqrt_s, 5.0);
  EXPECT_EQ(c.stochastic.zwd.initial_sigma_m, 0.3);
  EXPECT_EQ(c.stochastic.zwd.process_noise_m_per_sqrt_s, 1e-4);  // RTKLIB's; the table's 3e-5 below
  EXPECT_EQ(c.stochastic.clock.initial_sigma_m, 3e6);
  EXPECT_EQ(c.stochastic.clock.process_noise_m_per_sqrt_s, 2000.0);
  EXPECT_EQ(c.stochastic.phase_bias.initial_sigma_m, 100.0);
  EXPECT_EQ(c.stochastic.phase_bias.process_noise_m_per_sqrt_s, 0.0);
  EXPECT_EQ(c.source_name, "empty.yaml");
  EXPECT_TRUE(c.measurement_model.IsMap());
  EXPECT_EQ(c.measurement_model.size(), 0u);
}

TEST(PppConfig, MethodTablePresetIsTheMethodsTable) {
  const PppConfig m = ppp::methodTablePppConfig();
  // The method's table and the Hopfield mapping the method used.
  EXPECT_EQ(m.stochastic.position.initial_sigma_m, 1.0);
  EXPECT_EQ(m.stochastic.position.process_noise_m_per_sqrt_s, 5.0);
  EXPECT_EQ(m.stochastic.position.kind, ppp::ProcessKind::RandomWalk);
  EXPECT_EQ(m.stochastic.zwd.initial_sigma_m, 0.3);
  EXPECT_EQ(m.stochastic.zwd.process_noise_m_per_sqrt_s, 3e-5);
  EXPECT_EQ(m.stochastic.clock.initial_sigma_m, 3e6);
  EXPECT_EQ(m.stochastic.clock.process_noise_m_per_sqrt_s, 2000.0);
  EXPECT_EQ(m.stochastic.clock.kind, ppp::ProcessKind::White);
  EXPECT_EQ(m.stochastic.phase_bias.initial_sigma_m, 100.0);
  EXPECT_EQ(m.stochastic.phase_bias.process_noise_m_per_sqrt_s, 0.0);
  EXPECT_EQ(m.model.mapping, ppp::TroposphereMapping::ModifiedHopfield);
  EXPECT_EQ(m.model.dry_troposphere, ppp::DryTroposphereModel::ModifiedHopfield);
  // The preset file loads to exactly this configuration.
  expectSameConfig(ppp::loadPppConfig(std::string(PPP_REPO_DIR) + "/config/method_table.yaml"), m);
  // Apart from the start prior, the wet delay's random walk, the mapping and the gradients it is the defaults.
  EXPECT_FALSE(m.model.estimate_troposphere_gradients);  // the method estimates none
  PppConfig d;
  d.stochastic.position.initial_sigma_m = 1.0;
  d.stochastic.zwd.process_noise_m_per_sqrt_s = 3e-5;
  d.model.mapping = ppp::TroposphereMapping::ModifiedHopfield;
  d.model.estimate_troposphere_gradients = false;
  expectSameConfig(m, d);
}

TEST(PppConfig, RealDataFileIsTheDefaults) {
  // Kept for existing command lines: the defaults are the real-data values.
  expectSameDefaults(ppp::loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp_real_data.yaml"));
  expectSameDefaults(ppp::loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp_ros_zim2.yaml"));
}

// The nodes load these files with rosparam (PyYAML, YAML 1.1), where a number
// with an exponent needs a dot and a signed exponent (3.0e6 and 1e-4 are text
// there, refused by the strict binding): every exponent number is written 3.0e+6.
TEST(PppConfig, ExponentNumbersOfTheConfigFilesAreNumbersForRosparamToo) {
  int exponents = 0;
  for (const char* name : {"ppp.yaml", "method_table.yaml", "ppp_simulated.yaml", "ppp_real_data.yaml",
                           "ppp_ros_zim2.yaml", "simulation.yaml", "live.yaml"}) {
    const YAML::Node root = YAML::LoadFile(std::string(PPP_REPO_DIR) + "/config/" + name);
    std::vector<YAML::Node> stack{root};
    while (!stack.empty()) {
      const YAML::Node n = stack.back();
      stack.pop_back();
      if (n.IsMap()) {
        for (const auto& kv : n) stack.push_back(kv.second);
      } else if (n.IsSequence()) {
        for (const auto& item : n) stack.push_back(item);
      } else if (n.IsScalar() && n.Tag() != "!") {
        const std::string& t = n.Scalar();
        const auto e = t.find_first_of("eE");
        if (e == std::string::npos || t.find_first_not_of("0123456789.eE+-") != std::string::npos) continue;
        ++exponents;
        EXPECT_NE(t.find('.'), std::string::npos) << name << ": " << t << " (YAML 1.1 needs a dot)";
        EXPECT_TRUE(e + 1 < t.size() && (t[e + 1] == '+' || t[e + 1] == '-'))
            << name << ": " << t << " (YAML 1.1 needs a signed exponent: 3.0e+6)";
      }
    }
  }
  EXPECT_GT(exponents, 5);
}

TEST(PppConfig, KeyGivenTwiceIsAnErrorNamingTheFileAndBothLines) {
  const ConfigError top = errorOf(
      "measurement_model:\n  elevation_cutoff_deg: 10\nestimator:\n  min_satellites: 6\n"
      "measurement_model:\n  code_phase_ratio: 100\n");
  EXPECT_EQ(top.file(), "bad.yaml");
  EXPECT_EQ(top.keyPath(), "measurement_model");
  EXPECT_NE(top.reason().find("key given twice in one mapping, at line 1 and line 5"), std::string::npos)
      << top.what();
  const ConfigError nested = errorOf("stochastic:\n  clock:\n    initial_sigma_m: 1\n    initial_sigma_m: 2\n");
  EXPECT_EQ(nested.keyPath(), "stochastic.clock.initial_sigma_m");
  EXPECT_NE(nested.reason().find("at line 3 and line 4"), std::string::npos) << nested.what();
  const ConfigError flow = errorOf("ros: {frames: {map: a, map: b}}\n");
  EXPECT_EQ(flow.keyPath(), "ros.frames.map");
  // The same key in different mappings is fine.
  EXPECT_NO_THROW(parsePppConfig("stochastic:\n  position: {initial_sigma_m: 2}\n  zwd: {initial_sigma_m: 2}\n",
                                 "ok.yaml"));
  // A file: the error names its path.
  const std::string path = ::testing::TempDir() + "/ppp_twice.yaml";
  {
    std::ofstream out(path);
    out << "# comment\nstochastic: {}\nstochastic: {}\n";
  }
  try {
    ppp::loadPppConfig(path);
    ADD_FAILURE() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find(path + ": stochastic: key given twice in one mapping, at line 2 and line 3"),
              std::string::npos)
        << e.what();
  }
}

TEST(PppConfig, QuotedNumbersAndBoolsAreRefusedWithTheKeyPath) {
  const ConfigError number = errorOf("stochastic:\n  position:\n    initial_sigma_m: \"7\"\n");
  EXPECT_EQ(number.keyPath(), "stochastic.position.initial_sigma_m");
  EXPECT_NE(number.reason().find("expected a number, got the text \"7\" (quoted"), std::string::npos)
      << number.what();
  EXPECT_NE(number.reason().find("write a plain number (without quotes)"), std::string::npos) << number.what();
  // rosparam (YAML 1.1) reads 1e-4 as text: the error says how to write it.
  const ConfigError exponent = errorOf("smoother:\n  wildfire_threshold_m: \"1e-4\"\n");
  EXPECT_EQ(exponent.keyPath(), "smoother.wildfire_threshold_m");
  EXPECT_NE(exponent.reason().find("1.0e-4 or 3.0e+6"), std::string::npos) << exponent.what();
  const ConfigError integer = errorOf("estimator:\n  min_satellites: '6'\n");
  EXPECT_EQ(integer.keyPath(), "estimator.min_satellites");
  EXPECT_NE(integer.reason().find("expected an integer"), std::string::npos) << integer.what();
  const ConfigError yes = errorOf("estimator:\n  postfit_check: \"yes\"\n");
  EXPECT_EQ(yes.keyPath(), "estimator.postfit_check");
  EXPECT_NE(yes.reason().find("expected true or false"), std::string::npos) << yes.what();
  EXPECT_EQ(errorOf("smoother: {robust: on}\n").keyPath(), "smoother.robust");
  EXPECT_EQ(errorOf("smoother: {exact_range: \"false\"}\n").keyPath(), "smoother.exact_range");
  // The plain spellings are accepted.
  const PppConfig ok = parsePppConfig("smoother: {robust: True, exact_range: false}\nestimator: {min_satellites: 6}\n",
                                      "ok.yaml");
  EXPECT_TRUE(ok.smoother.robust);
  EXPECT_FALSE(ok.smoother.exact_range);
  EXPECT_EQ(ok.estimator.screening.min_satellites, 6);
}

TEST(PppConfig, TemplateLoadsAndRestatesEveryDefault) {
  // ppp_solve without --config uses the built-in defaults: config/ppp.yaml must
  // be exactly them.
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
  zwd: {process_noise_m_per_sqrt_m_of_height: 2.5e-3, height_change_threshold_sigmas: 4}
  clock: {process: random_walk, process_noise_m_per_sqrt_s: 10}
  code_correlation_time_s: 40
estimator:
  min_satellites: 6
  postfit_check: false
  start: {outlier_threshold_m: 12.5}
measurement_model:
  elevation_cutoff_deg: 10
cycle_slip:
  melbourne_wuebbena: {sigma_factor: 4}
ambiguity_resolution:
  wide_lane_correlation_time_s: 20
  small_subset_max_size: 1
  max_float_drift_sigmas: 0
)", "x.yaml");
  EXPECT_EQ(c.stochastic.code_correlation_time_s, 40.0);
  EXPECT_EQ(c.stochastic.zwd_per_sqrt_height_m_per_sqrt_m, 2.5e-3);
  EXPECT_EQ(c.stochastic.zwd_height_change_threshold_sigmas, 4.0);
  EXPECT_EQ(c.ambiguity_resolution.wide_lane.correlation_time_s, 20.0);
  EXPECT_EQ(c.ambiguity_resolution.hold.small_subset_max_size, 1);
  EXPECT_EQ(c.ambiguity_resolution.hold.max_float_drift_sigmas, 0.0);
  EXPECT_EQ(c.stochastic.position.initial_sigma_m, 2.5);
  EXPECT_EQ(c.stochastic.position.process_noise_m_per_sqrt_s, 0.0);
  EXPECT_EQ(c.stochastic.clock.kind, ppp::ProcessKind::RandomWalk);
  EXPECT_EQ(c.stochastic.clock.process_noise_m_per_sqrt_s, 10.0);
  EXPECT_EQ(c.stochastic.clock.initial_sigma_m, 3e6);  // untouched default
  EXPECT_EQ(c.estimator.screening.min_satellites, 6);
  EXPECT_FALSE(c.estimator.screening.postfit_check);
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

TEST(PppConfig, TroposphereGradientsAreBoundIntoTheModelAndTheEstimatorsState) {
  // Defaults: estimated, 1 mm a priori, 1e-5 m/sqrt(s) = 0.6 mm/sqrt(h) random walk (stochastic_model.h).
  const PppConfig defaults = parsePppConfig("", "x.yaml");
  EXPECT_TRUE(defaults.model.estimate_troposphere_gradients);
  EXPECT_TRUE(static_cast<ppp::EstimatorOptions>(defaults).troposphere_gradients);
  EXPECT_EQ(defaults.stochastic.troposphere_gradient.initial_sigma_m, 0.001);
  EXPECT_EQ(defaults.stochastic.troposphere_gradient.process_noise_m_per_sqrt_s, 1.0e-5);
  EXPECT_EQ(defaults.stochastic.troposphere_gradient.kind, ppp::ProcessKind::RandomWalk);

  const PppConfig off = parsePppConfig(R"(
stochastic:
  troposphere_gradient: {initial_sigma_m: 0.002, process_noise_m_per_sqrt_s: 3.0e-6}
measurement_model:
  troposphere: {estimate_gradients: false}
)", "x.yaml");
  EXPECT_FALSE(off.model.estimate_troposphere_gradients);
  const ppp::EstimatorOptions options = off;
  EXPECT_FALSE(options.troposphere_gradients);
  EXPECT_EQ(options.stochastic.troposphere_gradient.initial_sigma_m, 0.002);
  EXPECT_EQ(options.stochastic.troposphere_gradient.process_noise_m_per_sqrt_s, 3.0e-6);
  // The simulated flights' preset keeps them off (the simulator has none).
  EXPECT_FALSE(ppp::loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp_simulated.yaml")
                   .model.estimate_troposphere_gradients);

  // Zero, negative, absurd and wrongly typed values, and a `process` key (a random walk
  // by definition), name the key.
  const std::string sigma = "stochastic.troposphere_gradient.initial_sigma_m";
  const std::string noise = "stochastic.troposphere_gradient.process_noise_m_per_sqrt_s";
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"stochastic:\n  troposphere_gradient: {initial_sigma_m: 0}\n", sigma},
      {"stochastic:\n  troposphere_gradient: {initial_sigma_m: 0.5}\n", sigma},
      {"stochastic:\n  troposphere_gradient: {process_noise_m_per_sqrt_s: -1e-6}\n", noise},
      {"stochastic:\n  troposphere_gradient: {process_noise_m_per_sqrt_s: 0.01}\n", noise},
      {"stochastic:\n  troposphere_gradient: {process: white}\n", "stochastic.troposphere_gradient.process"},
      {"measurement_model:\n  troposphere: {estimate_gradients: 1}\n",
       "measurement_model.troposphere.estimate_gradients"}};
  for (const auto& [yaml, key] : bad) EXPECT_EQ(errorOf(yaml).keyPath(), key) << yaml;
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
      {"stochastic:\n  code_correlation_time_s: -1\n", "stochastic.code_correlation_time_s", "must be >= 0"},
      {"ambiguity_resolution:\n  wide_lane_correlation_time_s: -5\n",
       "ambiguity_resolution.wide_lane_correlation_time_s", "must be >= 0"},
      {"ambiguity_resolution:\n  small_subset_max_size: -1\n", "ambiguity_resolution.small_subset_max_size",
       "must be >= 0"},
      {"ambiguity_resolution:\n  max_float_drift_sigmas: -1\n", "ambiguity_resolution.max_float_drift_sigmas",
       "must be >= 0"},
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

TEST(PppConfig, SeveralFilesAreLaidOnOneAnotherAsTheNodesParameters) {
  // ppp_solve --config config/ppp.yaml config/live.yaml extra.yaml gives what the nodes
  // bind from the same files loaded into one parameter namespace: mappings merge key by
  // key, a later scalar or sequence replaces an earlier one.
  const std::string repo = PPP_REPO_DIR;
  const auto dir = ppp::test::tempDir("config_layers");
  const std::string extra = (dir / "extra.yaml").string();
  std::ofstream(extra) << "measurement_model:\n  signals:\n    systems: [GPS, Galileo]\n"
                          "smoother:\n  fixed_lag_s: 30.0\nros:\n  live:\n    expect_corrections: false\n";
  const PppConfig c = ppp::loadPppConfig(std::vector<std::string>{repo + "/config/ppp.yaml", repo + "/config/live.yaml", extra});
  EXPECT_EQ(c.smoother.fixed_lag_s, 30.0);             // extra.yaml over live.yaml's 60
  EXPECT_EQ(c.smoother.relinearize_position_m, 0.5);   // live.yaml over ppp.yaml's 0.01
  EXPECT_EQ(c.signals.systems, (std::vector<ppp::GnssSystem>{ppp::GnssSystem::GPS, ppp::GnssSystem::Galileo}));
  EXPECT_EQ(c.ros["smoothed"]["trajectory_csv"].as<std::string>(), "smoothed_trajectory.csv");  // live.yaml kept
  EXPECT_FALSE(c.ros["live"]["expect_corrections"].as<bool>());                                 // extra.yaml added
  EXPECT_EQ(c.source_name, repo + "/config/ppp.yaml + " + repo + "/config/live.yaml + " + extra);
  // One file alone is loadPppConfig(path); none is the defaults.
  EXPECT_EQ(ppp::loadPppConfig(std::vector<std::string>{repo + "/config/live.yaml"}).smoother.fixed_lag_s, 60.0);
  EXPECT_EQ(ppp::loadPppConfig(std::vector<std::string>{}).smoother.fixed_lag_s, PppConfig{}.smoother.fixed_lag_s);
  // A key written twice is refused naming the file that has it.
  const std::string twice = (dir / "twice.yaml").string();
  std::ofstream(twice) << "smoother:\n  fixed_lag_s: 1.0\n  fixed_lag_s: 2.0\n";
  try {
    ppp::loadPppConfig(std::vector<std::string>{repo + "/config/live.yaml", twice});
    ADD_FAILURE() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), twice) << e.what();
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

TEST(PppConfig, AmbiguityResolutionAndSystemsDefaultToAuto) {
  // Defaults: the products decide (product_assembly.h).
  const PppConfig d = ppp::parsePppConfig("", "defaults");
  EXPECT_EQ(d.ambiguity_resolution.mode, ppp::AmbiguityResolutionMode::Auto);
  EXPECT_FALSE(d.ambiguity_resolution.enabled);  // the assembly turns it on where it is sound
  EXPECT_TRUE(d.signals.systems_from_products);
  const auto mode = [](const std::string& value) {
    return ppp::parsePppConfig("ambiguity_resolution:\n  enabled: " + value + "\n", value).ambiguity_resolution;
  };
  EXPECT_EQ(mode("true").mode, ppp::AmbiguityResolutionMode::On);
  EXPECT_TRUE(mode("true").enabled);
  EXPECT_EQ(mode("false").mode, ppp::AmbiguityResolutionMode::Off);
  EXPECT_FALSE(mode("false").enabled);
  EXPECT_EQ(mode("auto").mode, ppp::AmbiguityResolutionMode::Auto);
  EXPECT_THROW(mode("yes"), ppp::ConfigError);
  // systems: a list is kept as written, `auto` (or no key) lets the products decide.
  const PppConfig listed = ppp::parsePppConfig("measurement_model:\n  signals:\n    systems: [GPS]\n", "list");
  EXPECT_FALSE(listed.signals.systems_from_products);
  EXPECT_EQ(listed.signals.systems, std::vector<ppp::GnssSystem>{ppp::GnssSystem::GPS});
  EXPECT_TRUE(ppp::parsePppConfig("measurement_model:\n  signals:\n    systems: auto\n", "auto")
                  .signals.systems_from_products);
  // config/ppp.yaml writes both as auto.
  const PppConfig file = ppp::loadPppConfig(std::vector<std::string>{std::string(PPP_REPO_DIR) + "/config/ppp.yaml"});
  EXPECT_EQ(file.ambiguity_resolution.mode, ppp::AmbiguityResolutionMode::Auto);
  EXPECT_TRUE(file.signals.systems_from_products);
}

namespace ppp {
namespace {

// An a priori sigma of 1e-300 m passes "> 0" but squares to a zero variance, so every
// epoch failed "covariance not positive definite": such values are refused with the key.
TEST(PppConfig, APrioriSigmasBelowAMeaningfulValueAreRefusedNamingTheKey) {
  // The smallest values with which ZIM2's hour still solves every epoch (1 mm for the
  // position and the wet delay; the clock and the phase biases need metres).
  const std::vector<std::pair<std::string, std::string>> smallest = {
      {"position", "0.001"}, {"zwd", "0.001"}, {"clock", "1"}, {"phase_bias", "1"}};
  for (const auto& [key, min] : smallest) {
    const std::string yaml = "stochastic:\n  " + key + ":\n    initial_sigma_m: 1e-300\n";
    try {
      parsePppConfig(yaml, "x.yaml");
      FAIL() << key << " initial_sigma_m 1e-300 accepted";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("stochastic." + key + ".initial_sigma_m: must be in [" + min + ", "), std::string::npos)
          << what;
    }
    EXPECT_NO_THROW(parsePppConfig("stochastic:\n  " + key + ":\n    initial_sigma_m: " + min + "\n", "x.yaml"));
  }
}

}  // namespace
}  // namespace ppp
