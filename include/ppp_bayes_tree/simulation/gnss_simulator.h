#pragma once
// GNSS observation simulator for UAV flights: dual-frequency GPS L1/L2 (and,
// with config.systems GE, Galileo E1/E5a on the nominal Walker 24/3/1
// constellation) pseudoranges and carrier phases along a trajectory, with the
// error model of SimulationConfig, plus the "precise products" (truth + product
// error) and the truth (position, ZWD, clock, arc biases). The non-dispersive
// part of every observable is computed BY the project's PppMeasurementModel at
// the true state, so simulator and estimator share their physics. Deterministic:
// the same seed and configuration give bit-identical results and files;
// simulateFlight() has no shared state and can run on several threads.
// The observation equations, the products and in-process use: doc/evaluation.md,
// "How the observations are simulated".
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/simulation/flight_trajectory.h"
#include "ppp_bayes_tree/simulation/gps_constellation.h"
#include "ppp_bayes_tree/simulation/simulated_imu.h"
#include "ppp_bayes_tree/simulation/simulated_phase_biases.h"
#include "ppp_bayes_tree/simulation/simulation_config.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

/// Optional inputs that replace the built-in ones.
struct SimulationSources {
  /// User trajectory (e.g. readTrajectoryCsv); replaces the profile.
  std::optional<std::vector<TrajectorySample>> trajectory;
  /// Real orbits and clocks (GPS part used); replace the nominal constellation.
  std::optional<Sp3File> sp3;
  std::optional<RinexClockFile> clk;
};

/// The parameters drawn for one flight (printed by ppp_simulate).
struct DrawnParameters {
  double dry_scale = 1.0, wet_scale = 1.0;
  double vtec0_tecu = 0.0, vtec_rate_tecu_per_h = 0.0;
  double clock_initial_s = 0.0, clock_drift_s_per_s = 0.0;
  int clock_steps = 0;
  double galileo_clock_offset_s = 0.0;  // Galileo receiver clock - GPS receiver clock
  double phase_sigma_l1_m = 0.0, phase_sigma_l2_m = 0.0;
  double orbit_error_rms_m = 0.0, clock_error_rms_m = 0.0;  // over satellites, at the flight midpoint
  std::vector<std::string> describe() const;
};

/// One continuous carrier-phase arc of the simulation.
struct TruthArc {
  ArcId id = 0;  // 1, 2, ... in order of creation
  SatelliteId satellite;
  GnssTime first_time, last_time;
  std::size_t epochs = 0;
  std::int64_t n1_cycles = 0, n2_cycles = 0;
  double bias_if_m = 0.0;       // alpha lambda1 N1 + beta lambda2 N2
  bool after_phase_break = false;  // started on reacquisition after airframe masking
};

/// An injected cycle slip: the satellite was masked by the airframe and reacquired.
struct PhaseBreak {
  SatelliteId satellite;
  GnssTime last_tracked, reacquired;
  ArcId previous_arc = 0, new_arc = 0;
  double min_body_elevation_rad = 0.0;  // during the outage
  double max_roll_rad = 0.0;            // |roll| maximum during the outage
};

/// Error components of one observation (for tests and diagnostics) [m].
struct SignalTruth {
  SatelliteId satellite;
  ArcId arc = 0;
  double elevation_rad = 0.0, body_elevation_rad = 0.0;
  double nondispersive_m = 0.0;     // G
  double troposphere_error_m = 0.0; // (s_dry - 1) * dry slant
  double windup_cycles = 0.0;
  double ionosphere_l1_m = 0.0;     // I_1 (I_2 = gamma I_1)
  double multipath1_m = 0.0, multipath2_m = 0.0;
  double multipath_unit = 0.0;      // the Gauss-Markov state of frequency 1 before elevation scaling
  double code_noise1_m = 0.0, code_noise2_m = 0.0;
  double phase_noise1_m = 0.0, phase_noise2_m = 0.0;
};

struct TruthEpoch {
  TrajectorySample trajectory;  // time, position, velocity, attitude
  double zwd_m = 0.0;           // true zenith wet delay at the receiver
  double clock_m = 0.0;         // c * receiver clock offset (GPS)
  double galileo_clock_m = 0.0; // c * Galileo receiver clock offset (Galileo simulated; else 0)
  std::vector<SignalTruth> signals;  // tracked satellites, same order as the ObsEpoch
};

struct SimulatedFlight {
  SimulationConfig config;
  std::uint64_t seed = 0;
  DrawnParameters drawn;
  /// Observations: header + epochs (what the RINEX file holds).
  RinexObsHeader header;
  std::vector<ObsEpoch> epochs;
  /// File texts of the products (SP3-c, RINEX clock 3.00): truth and with error.
  std::string truth_sp3_text, truth_clk_text, products_sp3_text, products_clk_text;
  /// The same read back by our readers: what the estimator must use (`products`)
  /// and the truth the observations were generated with.
  PreciseEphemeris products, truth_products;
  std::vector<TruthEpoch> truth;
  std::vector<TruthArc> arcs;       // index = id - 1
  std::vector<PhaseBreak> breaks;
  /// The satellite phase OSBs of the products (errors.ambiguity.satellite_phase_biases;
  /// empty otherwise): what PPP-AR needs besides orbits and clocks.
  SimulatedPhaseBiases phase_biases;
  /// The measurement-model options the observations were generated with
  /// (elevation cutoff aside): estimators must use the same.
  MeasurementModelOptions model_options;
  /// The IMU readings along the trajectory (config.imu.enabled; empty otherwise),
  /// from their own sub-stream of the seed: the GNSS draws do not change with them.
  SimulatedImu imu;

  /// Truth of satellite `sat` at epoch `epoch_index` (index into epochs/truth),
  /// nullptr when it was not tracked then.
  const SignalTruth* signal(std::size_t epoch_index, const SatelliteId& sat) const {
    if (epoch_index >= truth.size()) return nullptr;
    for (const auto& s : truth[epoch_index].signals)
      if (s.satellite == sat) return &s;
    return nullptr;
  }
  /// Truth IF phase bias [m] of the simulated arc holding `sat` at an epoch.
  /// An estimator arc that starts where a simulated arc starts has this bias;
  /// if the estimator restarts an arc inside a simulated one (false alarm), its
  /// wind-up restarts too and the bias may differ by an integer number of
  /// narrow-lane wavelengths (10.7 cm) times the wind-up cycles accumulated.
  std::optional<double> truthBias_m(std::size_t epoch_index, const SatelliteId& sat) const {
    const SignalTruth* s = signal(epoch_index, sat);
    if (s == nullptr) return std::nullopt;
    return arcs[s->arc - 1].bias_if_m;
  }
};

/// The dual-frequency pair (RINEX bands) the simulator transmits for a system
/// and the estimator combines ionosphere-free: GPS L1/L2 ('1', '2'), Galileo
/// E1/E5a ('1', '5').
struct SimulatedBands {
  char band1 = '1', band2 = '2';
};
SimulatedBands simulatedIonosphereFreeBands(GnssSystem system);

/// Measurement-model options matching the simulation physics (elevation cutoff
/// 7 deg as the estimator default; no ANTEX, tides or ocean loading; no eclipse
/// exclusion; wind-up, Shapiro on; modified Hopfield dry delay and mapping).
MeasurementModelOptions simulationModelOptions();

/// Simulates one flight (throws std::invalid_argument on an impossible setup,
/// e.g. products that do not cover the flight).
SimulatedFlight simulateFlight(const SimulationConfig& config, std::uint64_t seed,
                               const SimulationSources& sources = {});

}  // namespace ppp
