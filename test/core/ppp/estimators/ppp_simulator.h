#pragma once
// Small synthetic PPP measurement generator shared by the EKF and smoother tests
// (the real measurement model is separate): GPS-like circular orbits (radius
// 26 560 km, inclination 55 deg, 6 planes x 5 satellites, no Earth rotation),
// a receiver near ZIM2 (47 N, 7.5 E, spherical Earth), IF code and phase =
// range + clock + ZWD / sin(el) (+ arc bias for phase), noise-free or with
// Gaussian noise of the sigmas given to the filter (0.9 m and 9 mm at zenith,
// / sin(el)). addGalileo() adds a second constellation whose receiver clock is
// offset from GPS's (an inter-system bias), seen through its own clock column.
// Horizontal tropospheric gradients (G_N, G_E; Chen & Herring 1997,
// troposphere_gradient.h) add m_g(e) (G_N cos a + G_E sin a) to both observables;
// the model predicts them when the state's layout has the gradient block.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "ppp_bayes_tree/models/troposphere_gradient.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"
#include "ppp_bayes_tree/ppp/model/measurement_function.h"

namespace ppp::sim {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

struct SimSat {
  SatelliteId id;
  double raan_rad, anomaly0_rad;
};

inline Eigen::Vector3d satellitePosition(const SimSat& s, double t_s) {
  const double radius = 26.56e6, rate = 2.0 * kPi / 43082.0, inc = 55.0 * kDeg;
  const double u = s.anomaly0_rad + rate * t_s;
  const Eigen::Vector3d orbit(std::cos(u), std::sin(u) * std::cos(inc), std::sin(u) * std::sin(inc));
  const double c = std::cos(s.raan_rad), sn = std::sin(s.raan_rad);
  return radius * Eigen::Vector3d(c * orbit.x() - sn * orbit.y(), sn * orbit.x() + c * orbit.y(), orbit.z());
}

/// sin(elevation) of `sat` seen from `receiver` (spherical up).
inline double sinElevation(const Eigen::Vector3d& receiver, const Eigen::Vector3d& sat) {
  return (sat - receiver).normalized().dot(receiver.normalized());
}

/// Partials of the slant delay by the gradients (G_N, G_E) of `sat` seen from
/// `receiver` (spherical up, north towards the z axis).
inline GradientPartials simGradientPartials(const Eigen::Vector3d& receiver, const Eigen::Vector3d& sat) {
  const Eigen::Vector3d up = receiver.normalized();
  const Eigen::Vector3d east = Eigen::Vector3d::UnitZ().cross(up).normalized();
  const Eigen::Vector3d north = up.cross(east);
  const Eigen::Vector3d los = (sat - receiver).normalized();
  return gradientPartials(std::asin(los.dot(up)), std::atan2(los.dot(east), los.dot(north)));
}

struct SimObs {
  SatelliteId sat;
  ArcId arc;
  Eigen::Vector3d sat_pos;
  double code_m, phase_m, code_sigma_m, phase_sigma_m;
};

/// How the synthetic model predicts.
struct SimModelOptions {
  /// Also give the range geometry (SatelliteMeasurement::satellite_apc_ecef_m).
  bool geometry = false;
  /// Linear model: the predictions and Jacobian of the nonlinear model at
  /// `linear_about`, extended linearly (h0 + J0 (x - x_about)) to any state.
  bool linear = false;
  ReceiverState linear_about;
};

/// The synthetic "measurement model": predictions at any state, fixed observations.
inline MeasurementFunction modelOf(std::vector<SimObs> obs, SimModelOptions options = {}) {
  auto nonlinear = [](const std::vector<SimObs>& obs, const ReceiverState& s, bool geometry) {
    EpochMeasurements e;
    for (const auto& o : obs) {
      SatelliteMeasurement m;
      m.satellite = o.sat;
      m.arc = o.arc;
      const Eigen::Vector3d d = o.sat_pos - s.position_ecef_m;
      const double range = d.norm();
      double mapping = 1.0, sin_el = 1.0;
      if (s.position_ecef_m.norm() > 1e6) {  // near the surface; at the Earth centre: zenith
        sin_el = std::max(0.05, sinElevation(s.position_ecef_m, o.sat_pos));
        mapping = 1.0 / sin_el;
      }
      const int clock = s.layout.clock(o.sat.system);
      if (clock < 0) {
        e.rejected.push_back({o.sat, RejectionReason::NoReceiverClock, "no receiver clock for the system"});
        continue;
      }
      m.predicted_code_m = range + s.clock_m(o.sat.system) + s.zwd_m * mapping;
      m.jacobian = Eigen::RowVectorXd::Zero(s.layout.dim());
      if (s.layout.hasGradients()) {
        const GradientPartials g = simGradientPartials(s.position_ecef_m, o.sat_pos);
        m.predicted_code_m += g.north * s.gradient_north_m + g.east * s.gradient_east_m;
        m.jacobian(s.layout.gradientNorth()) = g.north;
        m.jacobian(s.layout.gradientEast()) = g.east;
      }
      m.predicted_phase_m = m.predicted_code_m;
      m.jacobian.segment<3>(s.layout.position()) = -d.transpose() / range;
      m.jacobian(s.layout.zwd()) = mapping;
      m.jacobian(clock) = 1.0;
      m.observed_code_m = o.code_m;
      m.observed_phase_m = o.phase_m;
      m.code_sigma_m = o.code_sigma_m;
      m.phase_sigma_m = o.phase_sigma_m;
      m.elevation_rad = std::asin(sin_el);
      if (geometry) m.satellite_apc_ecef_m = o.sat_pos;
      e.used.push_back(m);
    }
    return e;
  };
  if (!options.linear)
    return [obs = std::move(obs), nonlinear, geometry = options.geometry](const ReceiverState& s) {
      return nonlinear(obs, s, geometry);
    };
  const EpochMeasurements about = nonlinear(obs, options.linear_about, false);
  return [about, x0 = options.linear_about.vector()](const ReceiverState& s) {
    EpochMeasurements e = about;
    const Eigen::VectorXd dx = s.vector() - x0;
    for (auto& m : e.used) {
      m.predicted_code_m += m.jacobian.dot(dx);
      m.predicted_phase_m += m.jacobian.dot(dx);
    }
    return e;
  };
}

class Simulator {
 public:
  Eigen::Vector3d position = 6371000.0 * Eigen::Vector3d(std::cos(47 * kDeg) * std::cos(7.5 * kDeg),
                                                           std::cos(47 * kDeg) * std::sin(7.5 * kDeg),
                                                           std::sin(47 * kDeg));
  double zwd_m = 0.1;  // = the a priori value (StochasticModel::initial_zwd_m) unless a test says otherwise
  double clock_m = 12345.6;
  double galileo_clock_offset_m = 0.0;  // Galileo receiver clock - GPS receiver clock (addGalileo)
  double gradient_north_m = 0.0;        // true tropospheric gradients G_N, G_E
  double gradient_east_m = 0.0;
  double t_s = 0.0;
  bool noise = false;
  std::mt19937 rng{20260513};
  std::set<SatelliteId> hidden;  // left out by the test
  std::map<ArcId, double> bias_m;

  Simulator() {
    for (int p = 0; p < 6; ++p)
      for (int k = 0; k < 5; ++k)
        sats_.push_back({SatelliteId{GnssSystem::GPS, p * 5 + k + 1}, p * 60.0 * kDeg, (k * 72.0 + p * 17.0) * kDeg});
  }

  /// A Galileo-like constellation (3 planes x 4 satellites, same orbits shifted),
  /// its receiver clock `offset_m` from GPS's.
  void addGalileo(double offset_m) {
    galileo_clock_offset_m = offset_m;
    for (int p = 0; p < 3; ++p)
      for (int k = 0; k < 4; ++k)
        sats_.push_back({SatelliteId{GnssSystem::Galileo, p * 4 + k + 1}, (p * 120.0 + 30.0) * kDeg,
                         (k * 90.0 + p * 40.0 + 10.0) * kDeg});
  }

  GnssTime time() const { return GnssTime::fromGpsWeek(2418, 0.0) + t_s; }

  /// Observations at the current time; a satellite (re)appearing starts a new arc.
  std::vector<SimObs> epoch() {
    std::vector<SimObs> out;
    std::set<SatelliteId> now;
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(-50.0, 50.0);
    for (const auto& s : sats_) {
      const Eigen::Vector3d sp = satellitePosition(s, t_s);
      const double sin_el = sinElevation(position, sp);
      if (sin_el < std::sin(10 * kDeg) || hidden.count(s.id)) continue;
      now.insert(s.id);
      if (!visible_.count(s.id)) {
        arc_[s.id] = next_arc_++;
        bias_m[arc_[s.id]] = uniform(rng);
      }
      const ArcId arc = arc_[s.id];
      SimObs o{s.id, arc, sp, 0, 0, 0.9 / sin_el, 0.009 / sin_el};
      const double clock = clock_m + (s.id.system == GnssSystem::Galileo ? galileo_clock_offset_m : 0.0);
      const GradientPartials g = simGradientPartials(position, sp);
      const double geometric = (sp - position).norm() + clock + zwd_m / sin_el +
                               (g.north * gradient_north_m + g.east * gradient_east_m);
      o.code_m = geometric + (noise ? o.code_sigma_m * gauss(rng) : 0.0);
      o.phase_m = geometric + bias_m[arc] + (noise ? o.phase_sigma_m * gauss(rng) : 0.0);
      out.push_back(o);
    }
    visible_ = now;
    return out;
  }

  /// A cycle slip of `jump_m` on `sat`: a new arc (as the arc tracker would report).
  ArcId slip(SatelliteId sat, double jump_m) {
    const ArcId old_arc = arc_.at(sat);
    arc_[sat] = next_arc_++;
    bias_m[arc_[sat]] = bias_m[old_arc] + jump_m;
    return arc_[sat];
  }
  ArcId arcOf(SatelliteId sat) const { return arc_.at(sat); }

 private:
  std::vector<SimSat> sats_;
  std::set<SatelliteId> visible_;
  std::map<SatelliteId, ArcId> arc_;
  ArcId next_arc_ = 1;
};


/// Chi-square quantile (Wilson-Hilferty approximation, accurate to <1% for k > 50).
inline double chiSquareQuantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

/// Runs `epochs` epochs every `dt_s` seconds through an estimator (PppEkf or
/// PppSmoother), expecting each to be Ok; returns every epoch's result.
template <class Estimator>
auto runEpochs(Estimator& estimator, Simulator& sim, int epochs, double dt_s = 30.0, SimModelOptions model = {}) {
  std::vector<decltype(estimator.processEpoch(sim.time(), modelOf(sim.epoch(), model)))> out;
  for (int i = 0; i < epochs; ++i) {
    if (estimator.initialised()) sim.t_s += dt_s;
    out.push_back(estimator.processEpoch(sim.time(), modelOf(sim.epoch(), model)));
    EXPECT_EQ(out.back().status, EpochStatus::Ok) << out.back().reason;
  }
  return out;
}

/// The NEES experiment of the consistency tests: `runs` independent runs (seeds
/// seed0, seed0 + 1, ...; a different geometry each) with a random-walk truth
/// (the estimators' process model, q = 5 m/sqrt(s), white clock of 1 km) and
/// Gaussian noise; returns, per check epoch, the sum over the runs of the
/// filtered position NEES (chi-square with 3 x runs degrees of freedom).
/// `make()` returns a fresh estimator.
template <class Make>
std::map<int, double> positionNeesSums(Make make, int runs, unsigned seed0, const std::vector<int>& check_epochs,
                                       SimModelOptions model = {}) {
  std::map<int, double> nees_sum;
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (int run_index = 0; run_index < runs; ++run_index) {
    Simulator sim;
    sim.noise = true;
    sim.rng.seed(seed0 + static_cast<unsigned>(run_index));
    sim.t_s = 1800.0 * run_index;  // different geometry per run
    auto estimator = make();
    for (int i = 0; i <= check_epochs.back(); ++i) {
      if (i > 0) {
        sim.t_s += 30.0;
        for (int a = 0; a < 3; ++a) sim.position(a) += 5.0 * std::sqrt(30.0) * gauss(sim.rng);
        sim.clock_m = 1000.0 * gauss(sim.rng);
      }
      const auto r = estimator.processEpoch(sim.time(), modelOf(sim.epoch(), model));
      EXPECT_EQ(r.status, EpochStatus::Ok) << r.reason;
      if (r.status != EpochStatus::Ok) return {};
      const Eigen::Vector3d e = r.solution->state.position_ecef_m - sim.position;
      const Eigen::Matrix3d P = r.solution->positionCovariance_m2();
      for (int c : check_epochs)
        if (i == c) nees_sum[c] += e.dot(P.ldlt().solve(e));
    }
  }
  return nees_sum;
}

}  // namespace ppp::sim
