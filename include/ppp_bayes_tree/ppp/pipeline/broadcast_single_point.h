#pragma once
// Broadcast single-point positioning: one epoch's code pseudoranges with
// broadcast orbits and clocks (BroadcastEphemerisStore), metre level. It needs
// no precise products, so a receiver recording (UBX, RTCM) with its own
// navigation data can be positioned on its own. Dual-frequency ionosphere-free
// code (optionally carrier-smoothed), Saastamoinen and Niell troposphere, one
// receiver clock per system, elevation weights, outlier removal while redundancy
// remains. The model's choices: doc/offline_tools.md, "Broadcast single-point
// positioning".
// References: RTKLIB pntpos.c (Takasu); Misra P., Enge P., Global Positioning
// System, ch. 6; Hatch R. (1982) The synergism of GPS code and carrier
// measurements; Galileo OS SIS ICD 5.1.5 (BGD).
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
