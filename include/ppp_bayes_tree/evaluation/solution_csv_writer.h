#pragma once
// Per-epoch solution CSV: one header row, then one row per epoch (epochs
// without a solution keep their row, with empty position fields and status
// "no-solution"). Columns:
//   gps_week, tow_s, time_gpst (ISO 8601 text, GPST), x_m, y_m, z_m,
//   lat_deg, lon_deg, height_m (WGS 84 ellipsoidal),
//   [e_err_m, n_err_m, u_err_m, err3d_m  -- only when a truth position is given;
//    ENU axes at the truth],
//   sigma_e_m, sigma_n_m, sigma_u_m (from the ECEF covariance rotated to ENU),
//   sats_used, sats_rejected, zwd_m, clock_m, status
// The gps_week,tow_s,x_m,y_m,z_m names match what ../shared/peers/poserr.py reads.
// Absent values are empty fields, never 0.
#include <optional>
#include <ostream>
#include <string>

#include <Eigen/Core>

#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"

namespace ppp {

/// ISO 8601 text of a GPST instant with `decimals` fractional digits: "2026-05-13T00:00:30.000".
std::string isoTimeText(const GnssTime& time, int decimals = 3);

class SolutionCsvWriter {
 public:
  /// Writes the header row to `out` (which must outlive the writer).
  SolutionCsvWriter(std::ostream& out, std::optional<Eigen::Vector3d> truth_ecef_m = std::nullopt);
  void write(const SolutionEpoch& epoch);

  static std::string headerRow(bool with_truth);
  static std::string row(const SolutionEpoch& epoch, const std::optional<Eigen::Vector3d>& truth_ecef_m);

 private:
  std::ostream& out_;
  std::optional<Eigen::Vector3d> truth_ecef_m_;
};

}  // namespace ppp
