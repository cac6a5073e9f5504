#pragma once
// Broadcast single-point positioning: one epoch's code pseudoranges with
// broadcast orbits and clocks (BroadcastEphemerisStore), metre level. It needs
// no precise products, so a receiver recording (UBX, RTCM) with its own
// navigation data can be positioned on its own.
//
// Model (choices documented, after the standard SPP of e.g. RTKLIB pntpos.c and
// Misra & Enge, "Global Positioning System", ch. 6):
//  - Dual-frequency ionosphere-free code, so no ionosphere model is needed:
//    GPS/QZSS C1C + the first of C2L, C2S, C2X, C2W, C5Q, C5I, C5X present;
//    Galileo C1C (or C1B, C1X) + the first of C5Q, C5I, C5X, C7Q, C7I, C7X.
//    The GPS broadcast clock refers to the L1/L2 P(Y) combination; the C/A and
//    L2C inter-signal corrections (ISC, a few dm at most) are not applied.
//    A Galileo I/NAV clock refers to E1/E5b; for an E1/E5a pair it is moved with
//    the BGDs: clock - BGD(E1,E5b) + BGD(E1,E5a) (OS SIS ICD 5.1.5).
//  - Transmission time t_rx - P/c - dt_sat (the receiver clock cancels), Earth
//    rotation during the signal's flight (Sagnac), broadcast clock with its
//    relativistic term.
//  - Troposphere: Saastamoinen zenith delays of a standard atmosphere at the
//    current height, Niell mapping.
//  - Optionally the IF code smoothed with the IF carrier phase
//    (IonosphereFreeCodeSmoother: Hatch filter, R. Hatch 1982, "The synergism of
//    GPS code and carrier measurements"), which takes the code noise (tripled by
//    the IF combination) down to the multipath level.
//  - Unknowns: position and one receiver clock per system (so an inter-system
//    bias is absorbed). Weights 1 / sin^2(elevation). Elevation mask after the
//    first iteration; the worst residual above `outlier_threshold_m` is removed
//    while redundancy remains.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

struct BroadcastSinglePointOptions {
  double elevation_mask_rad = 10.0 * 3.14159265358979323846 / 180.0;
  int max_iterations = 10;
  double convergence_m = 1e-4;
  double outlier_threshold_m = 15.0;
};

struct BroadcastSinglePointResult {
  bool ok = false;
  std::string reason;  // why not ok
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  std::map<GnssSystem, double> receiver_clock_m;
  std::vector<SatelliteId> used;
  std::vector<double> residuals_m;  // of `used`, same order
  int iterations = 0;
};

/// The code and phase observations of a satellite's ionosphere-free pair
/// (signals chosen as above); null members when absent.
struct IonosphereFreePair {
  const Observation* code1 = nullptr;
  const Observation* code2 = nullptr;
  const Observation* phase1 = nullptr;  // same signals as the codes
  const Observation* phase2 = nullptr;
  double f1_hz = 0.0, f2_hz = 0.0;
  bool hasCode() const { return code1 != nullptr && code2 != nullptr; }
  double code_m() const;   // (f1^2 P1 - f2^2 P2) / (f1^2 - f2^2)
  std::optional<double> phase_m() const;  // the same with the phases in metres
};
IonosphereFreePair ionosphereFreePair(const ObsEpoch& epoch, const SatelliteId& satellite);

/// Hatch filter of the IF code per satellite: smoothed = P/k + (k-1)/k (previous
/// smoothed + IF phase change), k = number of epochs in the arc up to `window`. An
/// arc restarts on a loss-of-lock indicator, a missing phase or a gap above max_gap_s.
class IonosphereFreeCodeSmoother {
 public:
  explicit IonosphereFreeCodeSmoother(int window_epochs = 100, double max_gap_s = 2.0)
      : window_(window_epochs), max_gap_s_(max_gap_s) {}
  /// The smoothed IF code [m] of each satellite of the epoch with an IF code pair.
  std::map<SatelliteId, double> update(const ObsEpoch& epoch);

 private:
  struct Arc {
    GnssTime last;
    double smoothed_m = 0.0;
    double phase_m = 0.0;
    int epochs = 0;
  };
  int window_;
  double max_gap_s_;
  std::map<SatelliteId, Arc> arcs_;
};

/// Solves one epoch. With `smoothed_codes` (IonosphereFreeCodeSmoother::update of
/// this epoch) the smoothed IF code replaces the raw one. `start` is the a-priori position (e.g. the previous epoch's;
/// the Earth centre when absent).
BroadcastSinglePointResult broadcastSinglePoint(const ObsEpoch& epoch, const BroadcastEphemerisStore& ephemerides,
                                                const std::optional<Eigen::Vector3d>& start = std::nullopt,
                                                const BroadcastSinglePointOptions& options = {},
                                                const std::map<SatelliteId, double>* smoothed_codes = nullptr);

}  // namespace ppp
