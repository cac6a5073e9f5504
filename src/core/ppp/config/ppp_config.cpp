#include "ppp_bayes_tree/ppp/config/ppp_config.h"

#include <fstream>
#include <map>
#include <sstream>

#include "ppp_bayes_tree/ppp/config/yaml_document.h"

namespace ppp {
namespace {

void readNoise(YamlSection s, StateNoise& n, bool kind_configurable) {
  n.initial_sigma_m = s.number("initial_sigma_m", n.initial_sigma_m, Bound::Positive);
  n.process_noise_m_per_sqrt_s = s.number("process_noise_m_per_sqrt_s", n.process_noise_m_per_sqrt_s,
                                          Bound::NonNegative);
  if (kind_configurable) {
    const std::string kind = s.choice("process", toString(n.kind), {"random_walk", "white"});
    n.kind = kind == "white" ? ProcessKind::White : ProcessKind::RandomWalk;
    if (n.kind == ProcessKind::White && n.process_noise_m_per_sqrt_s <= 0.0)
      s.fail("process_noise_m_per_sqrt_s", "must be > 0 for a white process");
  }
  s.finish();
}

void readStochastic(YamlSection s, StochasticModel& m) {
  readNoise(s.section("position"), m.position, true);
  {
    YamlSection z = s.section("zwd");
    m.initial_zwd_m = z.number("initial_m", m.initial_zwd_m, Bound::NonNegative);
    m.zwd_per_sqrt_height_m_per_sqrt_m =
        z.number("process_noise_m_per_sqrt_m_of_height", m.zwd_per_sqrt_height_m_per_sqrt_m, Bound::NonNegative);
    m.zwd_height_change_threshold_sigmas =
        z.number("height_change_threshold_sigmas", m.zwd_height_change_threshold_sigmas, Bound::NonNegative);
    readNoise(z, m.zwd, true);
  }
  readNoise(s.section("clock"), m.clock, true);
  readNoise(s.section("phase_bias"), m.phase_bias, false);
  readNoise(s.section("troposphere_gradient"), m.troposphere_gradient, false);
  m.code_correlation_time_s = s.number("code_correlation_time_s", m.code_correlation_time_s, Bound::NonNegative);
  s.finish();
}

void readEstimator(YamlSection s, EkfOptions& o, CodeLeastSquaresOptions& start) {
  ScreeningOptions& sc = o.screening;
  sc.min_satellites = s.integer("min_satellites", sc.min_satellites, 1);
  o.iterations_per_epoch = s.integer("iterations_per_epoch", o.iterations_per_epoch, 1);
  sc.prefit_code_threshold_m = s.number("prefit_code_threshold_m", sc.prefit_code_threshold_m, Bound::Positive);
  sc.prefit_phase_sigmas = s.number("prefit_phase_sigmas", sc.prefit_phase_sigmas, Bound::Positive);
  sc.postfit_check = s.boolean("postfit_check", sc.postfit_check);
  sc.postfit_sigmas = s.number("postfit_sigmas", sc.postfit_sigmas, Bound::Positive);
  sc.postfit_max_rejections = s.integer("postfit_max_rejections", sc.postfit_max_rejections, 0);
  sc.consistency_check = s.boolean("consistency_check", sc.consistency_check);
  sc.consistency_false_alarm = s.number("consistency_false_alarm", sc.consistency_false_alarm, Bound::Positive);
  if (!(sc.consistency_false_alarm < 0.5)) s.fail("consistency_false_alarm", "must be < 0.5");
  {
    const std::string action = s.choice("consistency_action", toString(sc.consistency_action), {"inflate", "withhold"});
    sc.consistency_action = action == "withhold" ? ConsistencyAction::Withhold : ConsistencyAction::Inflate;
  }
  sc.clock_from_code_median = s.boolean("clock_from_code_median", sc.clock_from_code_median);
  sc.stale_arc_timeout_s = s.number("stale_arc_timeout_s", sc.stale_arc_timeout_s, Bound::NonNegative);
  {
    YamlSection t = s.section("start");
    start.max_iterations = t.integer("max_iterations", start.max_iterations, 1);
    start.convergence_m = t.number("convergence_m", start.convergence_m, Bound::Positive);
    start.min_satellites = t.integer("min_satellites", start.min_satellites, 4);
    start.outlier_threshold_m = t.number("outlier_threshold_m", start.outlier_threshold_m, Bound::Positive);
    t.finish();
  }
  s.finish();
}

void readAmbiguityResolution(YamlSection s, AmbiguityResolutionOptions& o) {
  {
    // true | false | auto (a YAML bool or the word auto).
    const std::string fallback = o.enabled ? "true" : toString(o.mode);
    const std::string v = s.choice("enabled", fallback, {"true", "false", "auto"});
    o.mode = v == "true" ? AmbiguityResolutionMode::On
                         : v == "false" ? AmbiguityResolutionMode::Off : AmbiguityResolutionMode::Auto;
    o.enabled = o.mode == AmbiguityResolutionMode::On;
  }
  o.min_elevation_rad =
      s.number("min_elevation_deg", o.min_elevation_rad / kDegToRad, Bound::NonNegative) * kDegToRad;
  o.narrow_lane.ratio_threshold = s.number("ratio_threshold", o.narrow_lane.ratio_threshold, Bound::Positive);
  o.narrow_lane.min_success_rate = s.number("min_success_rate", o.narrow_lane.min_success_rate, Bound::NonNegative);
  o.narrow_lane.success_rate_variance_factor = s.number(
      "success_rate_variance_factor", o.narrow_lane.success_rate_variance_factor, Bound::Positive);
  o.narrow_lane.min_fixed = s.integer("min_fixed", o.narrow_lane.min_fixed, 1);
  o.narrow_lane.partial = s.boolean("partial", o.narrow_lane.partial);
  o.wide_lane.min_samples = s.integer("wide_lane_min_samples", o.wide_lane.min_samples, 1);
  o.wide_lane.correlation_time_s =
      s.number("wide_lane_correlation_time_s", o.wide_lane.correlation_time_s, Bound::NonNegative);
  o.wide_lane.min_success_rate =
      s.number("wide_lane_min_success_rate", o.wide_lane.min_success_rate, Bound::NonNegative);
  o.wide_lane.max_fraction_cycles =
      s.number("wide_lane_max_fraction_cycles", o.wide_lane.max_fraction_cycles, Bound::Positive);
  o.hold.consistency_epochs = s.integer("consistency_epochs", o.hold.consistency_epochs, 1);
  o.hold.max_float_spread_cycles =
      s.number("max_float_spread_cycles", o.hold.max_float_spread_cycles, Bound::Positive);
  o.hold.max_float_drift_sigmas =
      s.number("max_float_drift_sigmas", o.hold.max_float_drift_sigmas, Bound::NonNegative);
  o.hold.require_subset_success_rate =
      s.boolean("require_subset_success_rate", o.hold.require_subset_success_rate);
  o.hold.small_subset_max_size = s.integer("small_subset_max_size", o.hold.small_subset_max_size, 0);
  o.hold.validation_epochs = s.integer("validation_epochs", o.hold.validation_epochs, 1);
  o.hold.fast_validation_success_rate =
      s.number("fast_validation_success_rate", o.hold.fast_validation_success_rate, Bound::NonNegative);
  o.hold.fast_validation_epochs = s.integer("fast_validation_epochs", o.hold.fast_validation_epochs, 1);
  o.hold.release_cycles = s.number("release_cycles", o.hold.release_cycles, Bound::Positive);
  o.hold.max_fraction_cycles = s.number("narrow_lane_max_fraction_cycles", o.hold.max_fraction_cycles, Bound::Positive);
  o.hold.max_sigma_cycles = s.number("narrow_lane_max_sigma_cycles", o.hold.max_sigma_cycles, Bound::Positive);
  o.hold.max_fraction_sigmas =
      s.number("narrow_lane_max_fraction_sigmas", o.hold.max_fraction_sigmas, Bound::NonNegative);
  o.hold.release_sigma = s.number("release_sigma", o.hold.release_sigma, Bound::Positive);
  o.hold.rereference_on_arc_end = s.boolean("rereference_held", o.hold.rereference_on_arc_end);
  o.allow_antenna_model_mismatch = s.boolean("allow_antenna_model_mismatch", o.allow_antenna_model_mismatch);
  s.finish();
}

void readSmoother(YamlSection s, const ScreeningOptions& screening, PppSmootherOptions& o) {
  o.screening = screening;  // both estimators screen alike
  o.robust = s.boolean("robust", o.robust);
  o.huber_width_sigmas = s.number("huber_width_sigmas", o.huber_width_sigmas, Bound::Positive);
  o.relinearize_position_m = s.number("relinearize_position_m", o.relinearize_position_m, Bound::Positive);
  o.relinearize_zwd_m = s.number("relinearize_zwd_m", o.relinearize_zwd_m, Bound::Positive);
  o.relinearize_clock_m = s.number("relinearize_clock_m", o.relinearize_clock_m, Bound::Positive);
  o.relinearize_bias_m = s.number("relinearize_bias_m", o.relinearize_bias_m, Bound::Positive);
  o.relinearize_skip = s.integer("relinearize_skip", o.relinearize_skip, 1);
  o.wildfire_threshold_m = s.number("wildfire_threshold_m", o.wildfire_threshold_m, Bound::NonNegative);
  o.exact_range = s.boolean("exact_range", o.exact_range);
  o.fixed_lag_s = s.number("fixed_lag_s", o.fixed_lag_s, Bound::NonNegative);
  s.finish();
}

void readSsr(YamlSection s, SsrStreamOptions& o) {
  o.orbit_max_age_s = s.number("orbit_max_age_s", o.orbit_max_age_s, Bound::Positive);
  o.clock_max_age_s = s.number("clock_max_age_s", o.clock_max_age_s, Bound::Positive);
  o.high_rate_clock_max_age_s = s.number("high_rate_clock_max_age_s", o.high_rate_clock_max_age_s, Bound::Positive);
  o.bias_max_age_s = s.number("bias_max_age_s", o.bias_max_age_s, Bound::Positive);
  o.antenna_model = s.text("antenna_model", o.antenna_model);
  BroadcastFallbackOptions& f = o.fallback;
  f.enabled = s.boolean("broadcast_fallback", f.enabled);
  f.orbit_sigma_m = s.number("broadcast_orbit_sigma_m", f.orbit_sigma_m, Bound::Positive);
  f.clock_sigma_m = s.number("broadcast_clock_sigma_m", f.clock_sigma_m, Bound::Positive);
  f.min_ssr_satellites = s.integer("min_ssr_satellites", f.min_ssr_satellites, 1);
  s.finish();
}

}  // namespace

PppConfig::operator EstimatorOptions() const {
  EstimatorOptions o;
  o.stochastic = stochastic;
  o.ekf = estimator;
  o.start = start;
  o.smoother = smoother;
  o.systems = signals.systems;
  o.troposphere_gradients = model.estimate_troposphere_gradients;
  o.ambiguity_resolution = ambiguity_resolution;
  o.ins = ins;
  return o;
}

PppConfig methodTablePppConfig() {
  PppConfig c;
  c.stochastic = methodTableStochasticModel();
  c.model.mapping = TroposphereMapping::ModifiedHopfield;
  c.model.estimate_troposphere_gradients = false;  // the method estimates none
  return c;
}

PppConfig bindPppConfig(const YAML::Node& root, const std::string& source_name) {
  PppConfig config;
  config.source_name = source_name;
  YamlSection top(root, source_name, "");
  readStochastic(top.section("stochastic"), config.stochastic);
  readEstimator(top.section("estimator"), config.estimator, config.start);
  readSmoother(top.section("smoother"), config.estimator.screening, config.smoother);
  readSsr(top.section("ssr"), config.ssr);
  readAmbiguityResolution(top.section("ambiguity_resolution"), config.ambiguity_resolution);
  config.measurement_model = top.rawMapping("measurement_model");
  config.cycle_slip = top.rawMapping("cycle_slip");
  config.ros = top.rawMapping("ros");
  top.finish();
  bindMeasurementModelOptions(config.measurement_model, source_name, config.model, config.signals);
  bindCycleSlipOptions(config.cycle_slip, source_name, config.cycle_slip_options);
  if (auto e = config.stochastic.validate(); !e.empty()) throw ConfigError(source_name, "stochastic", e);
  if (auto e = config.estimator.validate(); !e.empty()) throw ConfigError(source_name, "estimator", e);
  if (auto e = config.smoother.validate(); !e.empty()) throw ConfigError(source_name, "smoother", e);
  if (auto e = config.ambiguity_resolution.validate(); !e.empty())
    throw ConfigError(source_name, "ambiguity_resolution", e);
  return config;
}

PppConfig parsePppConfig(const std::string& yaml_text, const std::string& source_name) {
  return bindPppConfig(parseYamlDocument(yaml_text, source_name), source_name);
}

PppConfig loadPppConfig(const std::string& path) { return loadPppConfig(std::vector<std::string>{path}); }

namespace {

/// `over` laid on `base` as the ROS parameter server does with rosparam load:
/// mappings merge key by key, anything else (scalars, sequences) replaces.
YAML::Node layered(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string key = kv.first.as<std::string>();
    const YAML::Node existing = base[key];  // const lookup: inserts nothing
    out[key] = existing.IsDefined() ? layered(existing, kv.second) : YAML::Clone(kv.second);
  }
  return out;
}

}  // namespace

PppConfig loadPppConfig(const std::vector<std::string>& paths) {
  if (paths.empty()) return PppConfig{};
  YAML::Node root;
  std::string source;
  for (const auto& path : paths) {
    const YAML::Node document = loadYamlDocument(path);
    if (!document.IsNull() && !document.IsMap())
      throw ConfigError(path, "", "the document must be a mapping of sections");
    root = source.empty() ? document : (document.IsNull() ? root : layered(root, document));
    source += (source.empty() ? "" : " + ") + path;
  }
  return bindPppConfig(root, source);
}

}  // namespace ppp
