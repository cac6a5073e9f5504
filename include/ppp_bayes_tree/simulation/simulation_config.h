#pragma once
// SimulationConfig: everything the simulator needs besides the seed, with the
// error model of the method (the method's varied parameters). Each error term has
// an `enabled` flag so that it can be switched on alone; ErrorModelConfig::none()
// gives the noise-free simulation. Loaded strictly from YAML (YamlSection: an
// unknown key, a wrong type or an out-of-range value throws ConfigError).
//
// YAML layout (every key optional; the defaults are those below):
//   flight:        { rate_hz, duration_min, start: "2026-05-13 10:00:00",
//                    origin: { latitude_deg, longitude_deg, height_m } }
//   constellation: { satellites, systems: G|GE, galileo_satellites, orbit_interval_s, clock_interval_s }
//   observations:  { elevation_mask_deg, loss_of_lock_flags, quantize, marker_name,
//                    outages: { start_s: [..], duration_s: [..], keeps_lock: [..] } }
//   errors:
//     thermal:        { enabled, code_sigma_m, phase: fixed|wavelength_fraction,
//                       phase_sigma_m, phase_sigma_cycles }
//     multipath:      { enabled, sigma_m, time_constant_s }
//     troposphere:    { enabled, dry_scale_min, dry_scale_max, wet_scale_min, wet_scale_max }
//     ionosphere:     { enabled, vtec_min_tecu, vtec_max_tecu, vtec_rate_max_tecu_per_h, shell_height_km }
//     receiver_clock: { enabled, initial_sigma_s, random_walk_sigma_s, drift_sigma_s_per_s,
//                       step_s, steps_per_hour, galileo_offset_sigma_s }
//     ambiguity:      { enabled, max_abs_cycles, satellite_phase_biases }
//     phase_breaks:   { enabled, body_elevation_mask_deg, reacquisition_s }
//     products:       { enabled, orbit_sigma_m, clock_sigma_m, scale_half_range }
//   imu:           { enabled, grade: consumer_mems|industrial_mems|tactical, rate_hz, errors }
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/simulation/flight_trajectory.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

enum class PhaseNoiseMode {
  FixedSigma,          // phase_sigma_m per frequency (default 3 mm, real receivers)
  WavelengthFraction,  // phase_sigma_cycles * lambda (0.16 lambda: the method's table as written)
};

struct ErrorModelConfig {
  /// White thermal noise on each code and phase (not elevation-dependent).
  struct Thermal {
    bool enabled = true;
    double code_sigma_m = 0.32;
    PhaseNoiseMode phase_mode = PhaseNoiseMode::FixedSigma;
    double phase_sigma_m = 0.003;
    double phase_sigma_cycles = 0.16;
  } thermal;
  /// Code multipath: first-order Gauss-Markov per satellite and frequency,
  /// x_k = exp(-dt/tau) x_{k-1} + sqrt(1 - exp(-2 dt/tau)) sigma w_k, started
  /// from its stationary N(0, sigma^2) at each acquisition, scaled by
  /// 1/sin(elevation) (sigma is the zenith value).
  struct Multipath {
    bool enabled = true;
    double sigma_m = 0.4;
    double time_constant_s = 15.0;
  } multipath;
  /// True delay = s_dry * (a-priori modified Hopfield dry slant delay of the
  /// model) + m_wet * ZWD_true, ZWD_true = s_wet * Hopfield zenith wet delay of
  /// the standard atmosphere at the receiver height; s uniform in [min, max]
  /// per flight. Disabled: s_dry = s_wet = 1 (the delay equals the model).
  struct Troposphere {
    bool enabled = true;
    double dry_scale_min = 0.95, dry_scale_max = 1.05;
    double wet_scale_min = 0.5, wet_scale_max = 1.5;
  } troposphere;
  /// First-order ionosphere: I_f = 40.3 STEC / f^2 [m], added to code, subtracted
  /// from phase; STEC = VTEC(t) * single-layer mapping 1/cos(z') with
  /// sin z' = R cos(el) / (R + H) (IERS/IGS thin-shell model). VTEC(t) = VTEC0 +
  /// rate * (t - t0), VTEC0 uniform in [min, max], rate uniform in +-max rate.
  struct Ionosphere {
    bool enabled = true;
    double vtec_min_tecu = 5.0, vtec_max_tecu = 40.0;
    double vtec_rate_max_tecu_per_h = 5.0;
    double shell_height_km = 350.0;
  } ionosphere;
  /// Receiver clock dt(t) = dt0 + drift (t - t0) + random walk + steps: dt0 ~
  /// N(0, initial), drift ~ N(0, drift sigma), random-walk increments ~
  /// N(0, random_walk_sigma_s^2 * dt/1 s), steps of +-step_s at Poisson times.
  struct ReceiverClock {
    bool enabled = true;
    double initial_sigma_s = 1.0e-6;
    double random_walk_sigma_s = 30.0e-9;  // per sqrt(second)
    double drift_sigma_s_per_s = 1.0e-8;
    double step_s = 100.0e-9;
    double steps_per_hour = 2.0;
    /// Galileo's receiver clock = GPS's + a constant offset ~ N(0, sigma) per
    /// flight (the receiver's inter-system code bias and GGTO seen together),
    /// estimated as its own clock term (one clock per system).
    double galileo_offset_sigma_s = 30.0e-9;
  } receiver_clock;
  /// Integer ambiguities N1, N2 uniform in [-max, max] per arc (disabled: 0).
  /// With satellite_phase_biases, each satellite's phase carries a constant
  /// fractional bias per frequency (the uncalibrated phase delay, UPD), uniform in
  /// [-0.5, 0.5) cycle, which the "precise products" publish as phase OSBs
  /// (SimulatedFlight::phase_biases, consistent with the product clocks: the
  /// clocks carry no phase part), so that integer ambiguity resolution works on
  /// simulated data as on real products. Off by default (the float studies'
  /// observations stay bit-identical; the float biases absorb the UPD anyway).
  struct Ambiguity {
    bool enabled = true;
    int max_abs_cycles = 1000;
    bool satellite_phase_biases = false;
  } ambiguity;
  /// Airframe masking: a satellite whose elevation above the body's x-y plane is
  /// below the mask is not tracked; it is tracked again (new arc, new
  /// ambiguity: a cycle slip) after being visible for reacquisition_s.
  struct PhaseBreaks {
    bool enabled = true;
    double body_elevation_mask_rad = 5.0 * kDegToRad;
    double reacquisition_s = 2.0;
  } phase_breaks;
  /// Product errors written into the "precise products": per satellite an orbit
  /// error vector e ~ N(0, orbit_sigma^2) per ECEF component and a clock error
  /// c ~ N(0, clock_sigma^2) [m], each multiplied by a random linear scale over
  /// the flight 1 + k (t - t_mid) / T, k uniform in +-scale_half_range.
  /// How the product errors are drawn.
  enum class ProductErrorModel {
    /// Orbit error per ECEF component and clock error drawn independently
    /// (orbit_sigma_m, clock_sigma_m).
    Independent,
    /// As an analysis centre's products err: the orbit error in the satellite's
    /// radial / along-track / cross-track frame, and the clock estimated with the
    /// orbit absorbing its radial part (clock error = radial error + a residual):
    /// what stays in the range is (cos(nadir) - 1) dr + the along/cross part
    /// projected (sin(nadir) <= 0.24) + the residual.
    AnalysisCentre,
  };
  struct Products {
    bool enabled = true;
    ProductErrorModel model = ProductErrorModel::Independent;
    double orbit_sigma_m = 0.05;           // Independent: per ECEF component [m]
    double clock_sigma_m = 0.05;           // Independent: clock [m of c dt]
    double radial_sigma_m = 0.025;         // AnalysisCentre [m]
    double along_sigma_m = 0.035;          // AnalysisCentre [m]
    double cross_sigma_m = 0.025;          // AnalysisCentre [m]
    double clock_residual_sigma_m = 0.006; // AnalysisCentre: clock error beyond the radial [m]
    double scale_half_range = 0.5;
  } products;

  /// All terms off: noise-free observations, products = truth, zero clock,
  /// zero ambiguities, no phase breaks, troposphere equal to the model.
  static ErrorModelConfig none();
};

struct SimulationConfig {
  FlightProfile profile = FlightProfile::Loiter;
  double rate_hz = 1.0;
  /// Flight length; nullopt = the profile's default (loiter 40, survey 45,
  /// figure8 30, climb 60 min).
  std::optional<double> duration_s;
  /// First epoch; nullopt = 2026-05-13 10:00:00 GPST with the nominal
  /// constellation, or 10 min after the start of given products.
  std::optional<GnssTime> start;
  Geodetic origin = defaultSimulationOrigin();
  int satellites = 30;                 // nominal constellation: 24..32
  /// Simulated systems: GPS L1/L2 always; Galileo E1/E5a (nominal Walker
  /// 24/3/1, galileoWalkerOptions) when listed. Real SP3 sources: GPS only.
  std::vector<GnssSystem> systems{GnssSystem::GPS};
  int galileo_satellites = 24;
  bool simulates(GnssSystem system) const;
  double orbit_interval_s = 300.0;     // written products
  double clock_interval_s = 30.0;
  double elevation_mask_rad = 5.0 * kDegToRad;  // local elevation below which nothing is tracked
  /// Set RINEX LLI bit 0 at the first epoch of every arc after a phase break.
  bool loss_of_lock_flags = false;
  /// Round observations to the RINEX resolution (1 mm, 0.001 cycle) so that the
  /// in-process observations equal those read back from the file.
  bool quantize = true;
  std::string marker_name = "SIM1";
  /// GNSS outages (none by default): from start_s after the first epoch for
  /// duration_s no satellite is tracked and no epoch is written. Afterwards each
  /// satellite is reacquired as after any loss of lock (new arc, new ambiguities,
  /// once visible for errors.phase_breaks.reacquisition_s); epochs before the
  /// first reacquisition are not written either. An outage that keeps lock
  /// (keeps_lock: a blockage of the observations shorter than the receiver's
  /// loss-of-lock time) writes no epoch either, but each satellite still visible
  /// stays tracked: after it the same arc goes on with the same ambiguities,
  /// observed at once (no reacquisition time). keeps_lock is one flag per outage
  /// or a single flag for all (default false).
  struct Outage {
    double start_s = 0.0, duration_s = 0.0;
    bool keeps_lock = false;
  };
  std::vector<Outage> outages;
  /// The outage at since_start_s [s after the first epoch]; nullptr outside outages.
  const Outage* outageAt(double since_start_s) const;
  bool inOutage(double since_start_s) const { return outageAt(since_start_s) != nullptr; }
  ErrorModelConfig errors;
  /// IMU readings along the flight (simulated_imu.h), off by default: the grade's
  /// datasheet preset (imu_noise.h), the reading rate, and whether the grade's
  /// noise and biases are added (false: the true readings).
  struct Imu {
    bool enabled = false;
    ImuGrade grade = ImuGrade::IndustrialMems;
    double rate_hz = 200.0;
    bool errors = true;
  } imu;

  double durationOrDefault_s() const;
};

double defaultProfileDuration_s(FlightProfile profile);

/// Applies the keys of a YAML text on top of `base` (throws ConfigError).
SimulationConfig parseSimulationConfig(const std::string& yaml_text, const std::string& source_name,
                                       SimulationConfig base = {});
SimulationConfig loadSimulationConfig(const std::string& path, SimulationConfig base = {});

}  // namespace ppp
