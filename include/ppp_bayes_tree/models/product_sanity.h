#pragma once
// Product sanity checks: single bad values in precise orbit and clock products,
// found by leave-one-out prediction before the products are used, so that one
// wrong SP3 or CLK record can neither pull an estimate metres off under a
// centimetre sigma nor pass ppp_inspect as "problems: none". Orbit nodes are
// predicted by Lagrange interpolation from their neighbours (the worst outlier
// removed first, then the others predicted again); clock records by a line
// through their neighbours, less the epoch's common datum jump. Outliers are
// marked as bad values, never repaired, so the interpolation refuses them with a
// reason. The rules and thresholds: doc/offline_tools.md, "Bad product values".
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct OrbitCheckOptions {
  /// Nodes of the leave-one-out Lagrange window (degree + 1), at least 3.
  int window_nodes = 10;
  /// Threshold of the 3D leave-one-out miss [m] of a node with at least
  /// window_nodes / 2 - 1 window nodes on each side; a node nearer an end of the
  /// data (fewer on one side) gets `edge_threshold_m`; a node with none on one side
  /// (the first and last) would be an extrapolation and is not judged.
  double threshold_m = 0.30;
  double edge_threshold_m = 0.50;
  /// Orbits with an eccentricity above this (from the extreme radii of the
  /// nodes: the Galileo E14 and E18 at 0.16, QZSS IGSO at 0.075; GPS and nominal
  /// Galileo below 0.02) get both thresholds times eccentric_orbit_factor: a
  /// degree-9 fit over 15-min nodes follows them much less well (E18 near perigee
  /// misses clean nodes by 0.84 m inside the day and 17.7 m at its end, GRG day 177
  /// of 2020), so that for them only gross errors are found.
  double eccentricity_limit = 0.03;
  double eccentric_orbit_factor = 100.0;
  /// Largest spacing of the nodes around a checked node [s] (a gap ends the window).
  double max_spacing_s = 3600.0;
};

struct OrbitOutlier {
  SatelliteId satellite;
  GnssTime time;
  double miss_m = 0.0;       // |leave-one-out prediction - record| (3D)
  double threshold_m = 0.0;  // the threshold it exceeded
  std::string describe() const;
};

struct ClockCheckOptions {
  /// Threshold of the leave-one-out miss [s] (1 ns = 0.3 m of range).
  double threshold_s = 1.0e-9;
  /// Largest spacing between the records of a fit [s].
  double max_spacing_s = 900.0;
};

struct ClockOutlier {
  SatelliteId satellite;
  GnssTime time;
  double miss_s = 0.0;
  double threshold_s = 0.0;
  std::string describe() const;
};

/// Leave-one-out check of every satellite's SP3 positions (records already marked
/// bad are skipped).
std::vector<OrbitOutlier> findOrbitOutliers(const Sp3File& file, const OrbitCheckOptions& options = {});
/// The leave-one-out miss of every judged node (one pass, nothing removed), with
/// the threshold that applies to it: the margin of a file, for ppp_inspect and tests.
std::vector<OrbitOutlier> orbitLeaveOneOutMisses(const Sp3File& file, const OrbitCheckOptions& options = {});
/// Turns the outliers into bad-value markers (position_marked_bad, no position).
void markOrbitOutliers(Sp3File& file, const std::vector<OrbitOutlier>& outliers);

/// Leave-one-out check of every satellite's clock series (AS records).
std::vector<ClockOutlier> findClockOutliers(const RinexClockFile& file, const ClockCheckOptions& options = {});
/// Removes the outlying records (a clock file has no bad-value marker: a missing
/// record makes the interpolation refuse the time with a gap).
void markClockOutliers(RinexClockFile& file, const std::vector<ClockOutlier>& outliers);

}  // namespace ppp
