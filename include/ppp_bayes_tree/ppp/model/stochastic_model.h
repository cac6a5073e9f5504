#pragma once
// StochasticModel: a priori sigmas and process noise of the PPP state
// (position, zenith wet delay, receiver clocks, IF phase biases, tropospheric
// gradients), shared by the EKF and the smoother. The defaults serve real
// receiver data; methodTableStochasticModel() gives the method's table (the
// preset config/method_table.yaml). Every process noise is scaled with the real
// elapsed time between processed epochs; the receiver clock is white. The code
// variances carry a time-correlation factor (time_correlated_noise.h).
// The values, why they differ from the method's, and the noise scaling:
// doc/estimators.md, "The stochastic model".
//
// References: Chen G., Herring T.A. (1997) JGR 102(B9) and Bar-Sever Y.E.,
// Kroger P.M., Borjesson J.A. (1998) JGR 103(B3) (gradients as random walks);
// RTKLIB (Takasu) for the position and wet-delay defaults.
#include <string>

namespace ppp {

enum class ProcessKind {
  RandomWalk,  // variance += q^2 dt, correlations kept
  White,       // correlations removed, variance = min(q^2 dt, sigma0^2)
};

/// Noise of one state component.
struct StateNoise {
  double initial_sigma_m = 0.0;              // a priori standard deviation [m]
  double process_noise_m_per_sqrt_s = 0.0;   // spectral density q [m/sqrt(s)]
  ProcessKind kind = ProcessKind::RandomWalk;

  /// Variance added by a random walk over dt [m^2] (q^2 dt), or the variance a
  /// white state is reset to (min(q^2 dt, sigma0^2)). dt < 0 is treated as 0.
  double processVariance_m2(double dt_s) const;
  double initialVariance_m2() const { return initial_sigma_m * initial_sigma_m; }
};

struct StochasticModel {
  /// Per ECEF axis (30 m: see above; the method's table has 1 m).
  StateNoise position{30.0, 5.0, ProcessKind::RandomWalk};
  StateNoise zwd{0.3, 1.0e-4, ProcessKind::RandomWalk};  // table: 3e-5
  StateNoise clock{3.0e6, 2000.0, ProcessKind::White};
  StateNoise phase_bias{100.0, 0.0, ProcessKind::RandomWalk};  // q = 0: constant per arc
  /// Each of the north and east tropospheric gradients (used only when estimated).
  StateNoise troposphere_gradient{0.001, 1.0e-5, ProcessKind::RandomWalk};
  /// Wet-delay process noise driven by the receiver's height change [m/sqrt(m)]:
  /// a random walk in height, variance q_h^2 |dh| added to the ZWD per epoch
  /// (zwdHeightVariance_m2), on top of the random walk in time; 0 = off. The
  /// standard atmosphere's modified Hopfield wet delay falls by 8.5e-5 m per m
  /// near the ground (1.0e-3 of itself per m); q_h = k sqrt(H) makes a change k H
  /// over a climb of H one sigma. The default 3.2e-3 removes the wrong holds of
  /// the simulated climbs; with the threshold below it leaves level flights and
  /// static stations unchanged (doc/studies/ins_outages.md, "Wet-delay process
  /// noise driven by the height change").
  double zwd_per_sqrt_height_m_per_sqrt_m = 3.2e-3;
  /// The height change that drives zwd_per_sqrt_height_m_per_sqrt_m is only its part
  /// beyond this many sigmas of the solved heights' own difference
  /// (zwdHeightChangeBeyondNoise_m): a level platform's float height noise drives
  /// nothing, a climb nearly all of its height. 0 = every solved height change counts.
  double zwd_height_change_threshold_sigmas = 3.0;
  /// A priori value of the zenith wet delay [m] (not in the method's table:
  /// a typical mid-latitude value; the 0.3 m a priori sigma covers it).
  double initial_zwd_m = 0.1;
  /// Correlation time of the code errors [s] (first-order Gauss-Markov); 0 =
  /// white (no inflation). See above and config/ppp.yaml.
  double code_correlation_time_s = 15.0;

  /// Variance factor (1 + rho) / (1 - rho) of a code sample dt_s after the
  /// previous solved epoch (>= 1; 1 for white code, dt_s <= 0 or a long gap).
  double codeVarianceFactor(double dt_s) const;

  /// Variance added to the ZWD for a height change dh_m [m^2]: q_h^2 |dh|
  /// (0 when the option is off or dh is not finite).
  double zwdHeightVariance_m2(double dh_m) const;
  /// The part of a solved height change dh_m [m] that the solutions' own noise does
  /// not explain [m]: max(0, |dh| - k sigma), k = zwd_height_change_threshold_sigmas,
  /// sigma [m] the standard deviation of the difference of the two solved heights
  /// (0 when dh or sigma is not finite).
  double zwdHeightChangeBeyondNoise_m(double dh_m, double dh_sigma_m) const;

  /// Empty when valid, else the first problem ("clock.initial_sigma_m must be > 0").
  std::string validate() const;
};

/// The method's table (position a priori 1 m): the Monte Carlo
/// study and the tests that reproduce the method use it.
StochasticModel methodTableStochasticModel();

std::string toString(ProcessKind kind);

}  // namespace ppp
