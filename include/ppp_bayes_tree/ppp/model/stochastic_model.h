#pragma once
// StochasticModel: a priori sigmas and process noise of the PPP state
// (position, zenith wet delay, receiver clock, IF phase biases), shared by the
// EKF and the smoother. The defaults serve real receiver data; they are the
// method's table (methodTableStochasticModel(), the preset
// config/method_table.yaml) except for the position a priori sigma and the
// zenith wet delay's process noise:
//
//   state            a priori sigma   process noise         process
//   position         30 m (table 1 m) 5 m/sqrt(s)           random walk (kinematic)
//   zenith wet delay 0.3 m            1e-4 m/sqrt(s)        random walk
//                                     (table 3e-5)
//   receiver clock   3e6 m            2000 m/sqrt(s)        white
//   IF phase bias    100 m            0                     constant per arc
//   tropo gradients  1 mm             1e-5 m/sqrt(s)        random walk (not the method's; when estimated)
//
// Horizontal tropospheric gradients G_N, G_E (troposphere_gradient.h; with
// measurement_model.troposphere.estimate_gradients): gradients are of the order
// of a millimetre, a few millimetres across weather fronts (Chen & Herring 1997,
// JGR 102(B9); Bar-Sever, Kroger & Borjesson 1998, JGR 103(B3), who estimate
// them as random walks from a single receiver). 1e-5 m/sqrt(s)
// = 0.6 mm/sqrt(h) and 1 mm a priori were best on real data (measured with
// ppp_solve, ZWD q 1e-4: ESBC PPP-AR fixed north RMS after the first hour, EKF /
// smoothed, q 2e-6: 0.58 / 0.60, 5e-6: 0.55 / 0.54, 1e-5: 0.54 / 0.50, 2e-5:
// 0.54 / 0.51, 5e-5: 0.62 / 0.57 cm; the a priori sigma leaves ESBC unchanged
// and costs CCJ2 its early fixes above 5 mm: first fix 18.5 min with 1-3 mm,
// 32.5 min with 10 mm).
//
// Position 30 m: both estimators start at a code least-squares solution of the
// SAME first-epoch codes, so a prior around it counts those codes twice. The
// table's 1 m claims 1 m where the ionosphere-free code leaves metres (CCJ2
// starts 3 m off) and the phase arcs then hang the trajectory on that start.
// 30 m (RTKLIB's VAR_POS) leaves the start as a linearisation point only. A
// sigma from the code solution's own covariance would count the codes twice
// as well, so the prior stays uninformative. Measured with ppp_solve (GMF, mean
// 3D EKF / smoothed, 1 m -> 30 m): CCJ2 35.2 / 8.70 -> 26.1 / 8.41 cm, ZIM2
// 19.7 / 3.64 -> 18.8 / 3.63 cm.
//
// Zenith wet delay 1e-4 m/sqrt(s) (RTKLIB's default prn[2]; 6 mm/sqrt(h)): the
// table's 3e-5 m/sqrt(s) (1.8 mm/sqrt(h)) holds the wet delay so stiff that its
// real hourly changes of a centimetre go into the height of a kinematic
// receiver. Measured with ppp_solve defaults + BLQ, 3e-5 -> 1e-4: ESBC day
// GPS + Galileo kinematic, fixed epochs after the first hour, scatter E/N/U
// about their mean 0.43 / 0.61 / 2.34 -> 0.41 / 0.62 / 1.84 cm (EKF); CCJ2
// smoothed mean 3D 2.65 -> 2.42 cm; ZIM2 mean 3D EKF / smoothed 18.66 / 3.95 ->
// 18.45 / 3.91 cm. The simulated flights keep the table's value (their wet
// delay is a constant scale of the Hopfield model).
//
// Every process noise is scaled with the real elapsed time dt between two
// processed epochs (data gaps and "no solution" epochs included):
//  - random walk with spectral density q [m/sqrt(s)]: variance grows by q^2 dt;
//  - white clock: the clock has no memory. At each prediction its correlations
//    with the other states are removed and its variance is SET to
//    min(q^2 dt, sigma0^2) (2000^2 m^2/s x dt, i.e. 11 km for 30 s; the a priori
//    3e6 m (10 ms) applies to the first epoch and caps long gaps). The value kept
//    as the predicted mean only serves as the linearisation point.
//
// Code noise correlation (time_correlated_noise.h): code multipath is a
// Gauss-Markov error with a correlation time of seconds to minutes, so code
// samples taken closer than that are not independent. Each code variance of
// the update (EKF) or code factor (smoother) is multiplied by (1 + rho) / (1 - rho),
// rho = exp(-dt / code_correlation_time_s), dt the interval since the last
// solved epoch (1 at the first epoch and after long gaps): the code then brings
// the same information per second at 1 Hz as at 30 s, and the float covariance
// holds the correlated code error instead of averaging it away at the sampling
// rate. The screening keeps the white sigma (one sample's variance is unchanged).
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
  /// A priori value of the zenith wet delay [m] (not in the method's table:
  /// a typical mid-latitude value; the 0.3 m a priori sigma covers it).
  double initial_zwd_m = 0.1;
  /// Correlation time of the code errors [s] (first-order Gauss-Markov); 0 =
  /// white (no inflation). See above and config/ppp.yaml.
  double code_correlation_time_s = 15.0;

  /// Variance factor (1 + rho) / (1 - rho) of a code sample dt_s after the
  /// previous solved epoch (>= 1; 1 for white code, dt_s <= 0 or a long gap).
  double codeVarianceFactor(double dt_s) const;

  /// Empty when valid, else the first problem ("clock.initial_sigma_m must be > 0").
  std::string validate() const;
};

/// The method's table (position a priori 1 m): the Monte Carlo
/// study and the tests that reproduce the method use it.
StochasticModel methodTableStochasticModel();

std::string toString(ProcessKind kind);

}  // namespace ppp
