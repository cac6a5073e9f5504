#pragma once
// An analytic trajectory on the rotating Earth and its noise-free IMU readings,
// shared by the INS tests: constant speed in the local tangent plane, on a circle
// of constant turn rate, or on a straight line when the rate is zero.
// p(t) = p0 + C_en rho (sin wt, 1 - cos wt, 0) (straight: p0 + C_en (v t, 0, 0)),
// body x along the velocity, body z up: R_eb = C_en Rz(wt). The IMU reads
// w_ib = (0, 0, w) + R_eb^T w_ie and f_b = R_eb^T (a - g(p) + 2 w_ie x v)
// (Groves, 2nd ed., eq. 5.36 solved for the specific force).
#include <Eigen/Core>
#include <cmath>

#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/navigation/nav_state.h"
#include "ppp_bayes_tree/navigation/navigation_frame.h"
#include "ppp_bayes_tree/navigation/so3.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp::test {

/// R_ecef_enu at a point (the columns: east, north, up in ECEF).
inline Eigen::Matrix3d rotationEcefEnu(const Eigen::Vector3d& origin_ecef_m) {
  const Geodetic g = ecefToGeodetic(origin_ecef_m);
  return rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).transpose();
}

struct AnalyticTurn {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Matrix3d c_en = Eigen::Matrix3d::Identity();
  double speed_mps = 10.0;
  double rate_radps = 0.2;  // 0: a straight line

  /// A trajectory starting at `origin_ecef_m`, heading east.
  static AnalyticTurn at(const Eigen::Vector3d& origin_ecef_m, double speed_mps = 10.0, double rate_radps = 0.2) {
    return AnalyticTurn{origin_ecef_m, rotationEcefEnu(origin_ecef_m), speed_mps, rate_radps};
  }

  NavState state(double t) const {
    const double a = rate_radps * t;
    const Eigen::Vector3d along = rate_radps == 0.0
                                      ? Eigen::Vector3d(speed_mps * t, 0.0, 0.0)
                                      : (speed_mps / rate_radps) * Eigen::Vector3d(std::sin(a), 1.0 - std::cos(a), 0.0);
    NavState s;
    s.position_world_m = origin + c_en * along;
    s.velocity_world_mps = c_en * (speed_mps * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0));
    s.rotation_world_body = c_en * so3::expMap(Eigen::Vector3d(0.0, 0.0, a));
    return s;
  }
  /// The noise-free reading at t, time-tagged `stamp` (e.g. the start of the interval
  /// whose mid-point t is).
  ImuSample reading(double t, const GnssTime& stamp = GnssTime{}) const {
    const Eigen::Vector3d earth_rate(0.0, 0.0, kEarthRotationRate_radps);
    const NavState s = state(t);
    const double a = rate_radps * t;
    const Eigen::Vector3d accel = c_en * (speed_mps * rate_radps * Eigen::Vector3d(-std::sin(a), std::cos(a), 0.0));
    const Eigen::Vector3d force_ecef = accel - ecefNavigationFrame(s.position_world_m).gravity_world_mps2 +
                                       2.0 * earth_rate.cross(s.velocity_world_mps);
    ImuSample out;
    out.time = stamp;
    out.specific_force_mps2 = s.rotation_world_body.transpose() * force_ecef;
    out.angular_rate_radps = Eigen::Vector3d(0.0, 0.0, rate_radps) + s.rotation_world_body.transpose() * earth_rate;
    return out;
  }
};

}  // namespace ppp::test
