#pragma once
// Epoch records for the tests of the node's outputs and diagnostics (test_node_*.cpp).
#include <Eigen/Core>

#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"

namespace node_test {

/// A point on the equator at longitude 0 (WGS84 a): there east = ECEF +Y, north = +Z, up = +X.
inline Eigen::Vector3d equator() { return Eigen::Vector3d(6378137.0, 0.0, 0.0); }

/// A solved GPS-only epoch at `position`: ECEF sigmas X 3 cm, Y 1 cm, Z 2 cm (so E 1 cm,
/// N 2 cm, U 3 cm at the equator point), ZWD 0.1 m and clock 3 m, both sigma 2 cm.
inline ppp::PppEpochRecord solvedRecord(const ppp::GnssTime& t, const Eigen::Vector3d& position, bool fixed) {
  ppp::PppEpochRecord rec;
  rec.status = ppp::EpochStatus::Ok;
  rec.solution.time = t;
  rec.solution.status = fixed ? ppp::SolutionStatus::PppFixed : ppp::SolutionStatus::PppFloat;
  rec.solution.position_ecef_m = position;
  rec.solution.covariance_ecef_m2 = Eigen::Vector3d(9e-4, 1e-4, 4e-4).asDiagonal();
  rec.solution.zwd_m = 0.1;
  rec.solution.receiver_clock_m = 3.0;
  rec.receiver_covariance = Eigen::MatrixXd::Identity(rec.state_layout.dim(), rec.state_layout.dim()) * 4e-4;
  rec.satellites_observed = 9;
  for (int prn = 1; prn <= 8; ++prn) rec.used.push_back(ppp::SatelliteId{ppp::GnssSystem::GPS, prn});
  ppp::AmbiguityFixSummary fix;
  fix.float_reason = fixed ? ppp::AmbiguityFloatReason::None : ppp::AmbiguityFloatReason::TooFewWideLanes;
  fix.held = fixed ? 7 : 0;
  fix.wide_lanes_fixed = fixed ? 9 : 2;
  fix.ratio = fixed ? 4.2 : 0.0;
  rec.ambiguity_fix = fix;
  return rec;
}

}  // namespace node_test
