#include "ppp_bayes_tree/ppp/config/config_bounds.h"

#include <map>

namespace ppp {
namespace {

constexpr double kDay_s = 86400.0;
constexpr double kWeek_s = 604800.0;

// Key path -> largest accepted value. Reasons name the physical or practical limit.
const std::map<std::string, ConfigUpperBound>& bounds() {
  static const std::map<std::string, ConfigUpperBound> table = {
      // stochastic: a priori sigmas past these make the filter's covariance ill-conditioned
      // against millimetre phase (the EKF then rejects every epoch) and mean nothing physically.
      {"stochastic.position.initial_sigma_m", {1.0e4, "the code start is within tens of metres"}},
      {"stochastic.position.process_noise_m_per_sqrt_s", {1.0e3, "1 km/sqrt(s) is no vehicle's motion"}},
      {"stochastic.zwd.initial_m", {2.0, "the zenith wet delay stays below 0.5 m on Earth"}},
      {"stochastic.zwd.initial_sigma_m", {10.0, "the zenith wet delay stays below 0.5 m on Earth"}},
      {"stochastic.zwd.process_noise_m_per_sqrt_s", {1.0, "the wet delay changes by millimetres per minute"}},
      {"stochastic.zwd.process_noise_m_per_sqrt_m_of_height",
       {0.1, "the wet delay changes by about 1e-4 m per metre of height"}},
      {"stochastic.zwd.height_change_threshold_sigmas", {10.0, "a height change beyond 10 sigmas is no noise"}},
      {"stochastic.clock.initial_sigma_m", {1.0e8, "a receiver clock is steered within 1 ms (3e5 m); 1e8 m = 0.33 s"}},
      {"stochastic.clock.process_noise_m_per_sqrt_s", {1.0e7, "the clock is re-estimated per epoch anyway"}},
      {"stochastic.phase_bias.initial_sigma_m", {1.0e4, "phase minus code is known to tens of metres"}},
      {"stochastic.phase_bias.process_noise_m_per_sqrt_s", {10.0, "an ambiguity is constant over its arc"}},
      {"stochastic.troposphere_gradient.initial_sigma_m", {0.1, "tropospheric gradients are millimetres"}},
      {"stochastic.troposphere_gradient.process_noise_m_per_sqrt_s",
       {1.0e-3, "gradients change by millimetres per hour (1e-3 m/sqrt(s) = 6 cm/sqrt(h))"}},
      {"stochastic.code_correlation_time_s", {3600.0, "multipath decorrelates within minutes"}},
      // estimator
      {"estimator.min_satellites", {100, "no receiver tracks more satellites at once"}},
      {"estimator.iterations_per_epoch", {20, "the linearisation converges in 2-3 iterations"}},
      {"estimator.prefit_code_threshold_m", {1.0e4, "larger residuals are no measurement"}},
      {"estimator.prefit_phase_sigmas", {1.0e3, "larger gates screen nothing"}},
      {"estimator.postfit_sigmas", {1.0e3, "larger gates screen nothing"}},
      {"estimator.postfit_max_rejections", {100, "no epoch has more signals to reject"}},
      {"estimator.stale_arc_timeout_s", {kDay_s, "an arc unused for a day is gone"}},
      {"estimator.start.max_iterations", {1000, "Gauss-Newton converges in a few iterations"}},
      {"estimator.start.convergence_m", {100.0, "a coarser step is no convergence"}},
      {"estimator.start.min_satellites", {100, "no receiver tracks more satellites at once"}},
      {"estimator.start.outlier_threshold_m", {1.0e4, "larger residuals are no measurement"}},
      // smoother
      {"smoother.huber_width_sigmas", {100.0, "wider is no robust kernel"}},
      {"smoother.relinearize_position_m", {100.0, "the range is linear to far less"}},
      {"smoother.relinearize_zwd_m", {1.0, "the zenith wet delay stays below 0.5 m"}},
      {"smoother.relinearize_clock_m", {1.0e6, "the clock enters linearly"}},
      {"smoother.relinearize_bias_m", {100.0, "the bias enters linearly"}},
      {"smoother.relinearize_skip", {1000, "past this the states are never relinearized"}},
      {"smoother.wildfire_threshold_m", {100.0, "larger thresholds never re-solve a state"}},
      {"smoother.fixed_lag_s",
       {3600.0, "the window's memory and update time grow with the lag (600 s: 22 ms per epoch at 1 Hz); "
                "for all states use 0 (the full smoother)"}},
      // measurement model
      {"measurement_model.phase_sigma_zenith_m", {1.0, "carrier phase is good to millimetres"}},
      {"measurement_model.code_phase_ratio", {1.0e4, "code is not 10^4 times worse than phase"}},
      // cycle slips
      {"cycle_slip.melbourne_wuebbena.sigma_factor", {100.0, "larger gates detect nothing"}},
      {"cycle_slip.melbourne_wuebbena.min_threshold_cycles", {100.0, "larger gates detect nothing"}},
      {"cycle_slip.melbourne_wuebbena.initial_sigma_cycles", {100.0, "larger gates detect nothing"}},
      {"cycle_slip.melbourne_wuebbena.min_samples", {100000, "more than a day of 1 Hz epochs"}},
      {"cycle_slip.melbourne_wuebbena.window", {100000, "more than a day of 1 Hz epochs"}},
      {"cycle_slip.geometry_free.threshold_base_m", {10.0, "larger gates detect nothing"}},
      {"cycle_slip.geometry_free.threshold_rate_m_per_s", {10.0, "larger gates detect nothing"}},
      {"cycle_slip.geometry_free.threshold_max_m", {100.0, "larger gates detect nothing"}},
      {"cycle_slip.geometry_free.fit_points", {100, "a longer fit follows the ionosphere no more"}},
      {"cycle_slip.geometry_free.drift_allowance_m_per_s", {10.0, "larger allowances detect nothing"}},
      {"cycle_slip.geometry_free.sigma_factor", {100.0, "larger gates detect nothing"}},
      {"cycle_slip.geometry_free.min_samples", {100000, "more than a day of 1 Hz epochs"}},
      {"cycle_slip.max_gap_s", {kDay_s, "an arc broken for a day is a new arc"}},
      {"cycle_slip.max_gap_intervals", {1000.0, "an arc broken for 1000 intervals is a new arc"}},
      {"cycle_slip.default_interval_s", {3600.0, "no GNSS data comes hourly"}},
      // SSR ages
      {"ssr.orbit_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ssr.clock_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ssr.high_rate_clock_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ssr.bias_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ssr.broadcast_orbit_sigma_m", {1000.0, "broadcast orbits are good to metres"}},
      {"ssr.broadcast_clock_sigma_m", {1000.0, "broadcast clocks are good to metres"}},
      {"ssr.min_ssr_satellites", {100, "no stream corrects more satellites"}},
      // ambiguity resolution
      {"ambiguity_resolution.min_elevation_deg", {90.0, "elevations end at the zenith"}},
      {"ambiguity_resolution.ratio_threshold", {1000.0, "no search passes a larger ratio"}},
      {"ambiguity_resolution.success_rate_variance_factor", {100.0, "a covariance 10 times too optimistic in sigma is no model"}},
      {"ambiguity_resolution.min_fixed", {100, "no epoch has more ambiguities"}},
      {"ambiguity_resolution.wide_lane_min_samples", {100000, "more than a day of 1 Hz epochs"}},
      {"ambiguity_resolution.wide_lane_correlation_time_s", {3600.0, "multipath decorrelates within minutes"}},
      {"ambiguity_resolution.small_subset_max_size", {100, "no epoch has more ambiguities"}},
      {"ambiguity_resolution.consistency_epochs", {100000, "more than a day of 1 Hz epochs"}},
      {"ambiguity_resolution.max_float_spread_cycles", {10.0, "a wider spread is no consistency"}},
      {"ambiguity_resolution.max_float_drift_sigmas", {100.0, "a wider gate is no consistency"}},
      {"ambiguity_resolution.narrow_lane_max_sigma_cycles", {10.0, "a wider sigma is no candidate"}},
      {"ambiguity_resolution.narrow_lane_max_fraction_sigmas", {100.0, "a wider gate is no gate"}},
      {"ambiguity_resolution.validation_epochs", {100000, "more than a day of 1 Hz epochs"}},
      {"ambiguity_resolution.fast_validation_epochs", {100000, "more than a day of 1 Hz epochs"}},
      {"ambiguity_resolution.release_sigma", {100.0, "a wider gate never releases"}},
      // ros: the node
      {"ros.attitude.max_age_s", {60.0, "an attitude a minute old is no attitude of the epoch"}},
      {"ros.datum.height_m", {1.0e5, "the datum is near the Earth's surface"}},
      {"ros.input.correction_wait_s",
       {600.0, "corrections come every 5-60 s; a longer wait only delays every fix (and buffers the epochs)"}},
      {"ros.input.correction_history_s", {kDay_s, "corrections of another day are not interpolated"}},
      {"ros.input.reset_backwards_threshold_s", {kDay_s, "a day back is a restart"}},
      {"ros.input.max_forward_step_s", {kWeek_s, "a week ahead is no next epoch"}},
      {"ros.input.time_jump_confirm_epochs", {100, "more epochs only delay the recovery"}},
      {"ros.input.max_pending_epochs", {100000, "more than a day of 1 Hz epochs in memory"}},
      {"ros.input.observation_queue_size", {1000000, "memory"}},
      {"ros.input.correction_queue_size", {1000000, "memory"}},
      {"ros.status.converged_horizontal_sigma_m", {100.0, "a 100 m sigma is not converged"}},
      {"ros.status.converged_vertical_sigma_m", {100.0, "a 100 m sigma is not converged"}},
      {"ros.diagnostics.expected_observation_rate_hz", {100.0, "receivers give at most 100 Hz"}},
      {"ros.diagnostics.max_correction_latency_s", {3600.0, "an hour late is no latency"}},
      {"ros.diagnostics.corrections_stale_warn_s", {kDay_s, "a day without corrections is stale"}},
      {"ros.diagnostics.corrections_stale_error_s", {kDay_s, "a day without corrections is stale"}},
      {"ros.diagnostics.path_publish_rate_hz", {100.0, "each publication carries the whole path"}},
      {"ros.diagnostics.path_max_poses", {1000000, "memory (a 20000-pose path is ~2 MB per publication)"}},
      {"ros.live.queue_size", {1000000, "memory"}},
      {"ros.live.ssr_orbit_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ros.live.ssr_clock_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ros.live.ssr_high_rate_clock_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ros.live.ssr_bias_max_age_s", {kDay_s, "older corrections are of another day"}},
      {"ros.live.correction_wait_s",
       {600.0, "corrections come every 5-60 s; a longer wait only delays every fix (and holds the epochs)"}},
      {"ros.live.stall_warn_s", {3600.0, "an hour without epochs is no stall"}},
      {"ros.live.stall_error_s", {kDay_s, "a day without epochs is no stall"}},
      {"ros.live.restart_jump_s", {kWeek_s, "a week back is a restart in any case"}},
      {"ros.live.max_held_epochs", {1000000, "memory"}},
      {"ros.live.keep_history_s", {kWeek_s, "a week of corrections and ephemerides"}},
  };
  return table;
}

const std::map<std::string, ConfigLowerBound>& lowerBounds() {
  static const std::map<std::string, ConfigLowerBound> table = {
      {"stochastic.position.initial_sigma_m", {1.0e-3, "no start is known better than a millimetre"}},
      {"stochastic.zwd.initial_sigma_m", {1.0e-3, "no model knows the wet delay better than a millimetre"}},
      {"stochastic.clock.initial_sigma_m", {1.0, "the code start knows the receiver clock to metres"}},
      {"stochastic.phase_bias.initial_sigma_m", {1.0, "phase minus code is known to the code noise, metres"}},
      {"stochastic.troposphere_gradient.initial_sigma_m", {1.0e-6, "gradients are not known to a micrometre"}},
  };
  return table;
}

}  // namespace

std::optional<ConfigLowerBound> configLowerBound(const std::string& key_path) {
  const auto it = lowerBounds().find(key_path);
  if (it == lowerBounds().end()) return std::nullopt;
  return it->second;
}

std::optional<ConfigUpperBound> configUpperBound(const std::string& key_path) {
  const auto it = bounds().find(key_path);
  if (it == bounds().end()) return std::nullopt;
  return it->second;
}

}  // namespace ppp
