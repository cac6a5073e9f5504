#pragma once
// Factors of the PPP factor graph on the generic smoother (ppp::smoother).
// Variables: x<k>, the receiver state of the k-th solved epoch (position ECEF,
// ZWD, one clock per system, optionally the tropospheric gradients), and b(sat,
// arc), the IF phase bias of one satellite arc. Factors: one IF code factor on
// x<k> and one IF phase factor on (x<k>, b) per satellite and epoch, evaluated
// from the single measurement model with its sigmas and re-evaluating the exact
// geometric range at a new linearisation point; random-walk between factors of
// position, ZWD and gradients; a unary prior per epoch for the white clocks
// (ClockPriorFactor), so the filtered solution equals the EKF's; priors on the
// first state and each new bias. The equations: doc/estimators.md, "The factors".
// References: Kaess M. et al. (2012) Int. J. Robotics Research 31(2) (iSAM2);
// Watson R.M., Gross J.N. (2018) IEEE/ION PLANS (the PPP graph).
#include <Eigen/Core>
#include <array>
#include <optional>

#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"
#include "ppp_bayes_tree/smoother/key.h"
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"

namespace ppp {

/// x<epoch_index>.
smoother::Key stateKey(std::uint32_t epoch_index);
/// b(<sat>,<arc>), e.g. b(G05,3).
smoother::Key biasKey(const SatelliteId& satellite, ArcId arc);

/// The prediction of one satellite's IF code (and phase, which adds the wind-up)
/// at any receiver state of its epoch, from the model's evaluation at x0 (see top).
class SatellitePrediction {
 public:
  /// A Jacobian row (1 x state dimension), as the smoother's factors take it.
  using Row = Eigen::MatrixXd;
  SatellitePrediction(const SatelliteMeasurement& m, const ReceiverState& x0, bool exact_range);

  /// Predicted IF code [m] at x (state vector in x0's layout), and its Jacobian when
  /// `jacobian` is non-null (resized to 1 x dim; its storage is reused when it has that size).
  double code_m(const Eigen::VectorXd& x, Row* jacobian) const;
  /// Predicted IF phase without the bias [m] (code + wind-up).
  double phase_m(const Eigen::VectorXd& x, Row* jacobian) const { return code_m(x, jacobian) + windup_m_; }

  const SatelliteMeasurement& measurement() const { return m_; }
  const ReceiverStateLayout& layout() const { return layout_; }
  bool exactRange() const { return satellite_.has_value(); }

 private:
  /// The state components after the position (ZWD, clocks): at most this many.
  static constexpr int kMaxRest = 1 + kNumGnssSystems;

  SatelliteMeasurement m_;
  ReceiverStateLayout layout_;
  Eigen::VectorXd x0_;
  // What the exact range needs at every call, held in the object itself (no further
  // memory to reach): x0's position, and x0 and the model's partials of the components
  // after the position, in state order (rest_count_ of them; -1: not held).
  Eigen::Vector3d x0_position_ = Eigen::Vector3d::Zero();
  int rest_count_ = -1;
  std::array<double, kMaxRest> rest_x0_{};
  std::array<double, kMaxRest> rest_partial_{};
  double windup_m_ = 0.0;                  // predicted phase - predicted code at x0
  std::optional<Eigen::Vector3d> satellite_;  // s: set when the range is re-evaluated
  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();    // o
  double range0_m_ = 0.0;                  // rho(x0)
  Eigen::Vector3d dry_gradient_ = Eigen::Vector3d::Zero();  // g
};

/// IF pseudorange: error = code(x) - observed code; sigma = code_sigma_m.
class PppCodeFactor : public smoother::NoiseModelFactor1<smoother::Vector> {
 public:
  PppCodeFactor(smoother::Key state, SatellitePrediction prediction, smoother::NoiseModel::Ptr noise);
  smoother::Vector evaluateError(const smoother::Vector& state, smoother::Matrix* h_state) const override;
  const SatellitePrediction& prediction() const { return prediction_; }

  /// Affine in the ZWD and clock components (constant coefficients); in the
  /// position too when the range is not re-evaluated (linear factors).
  bool affineIn(smoother::Key) const override { return !prediction_.exactRange(); }
  bool affineInComponent(smoother::Key key, int component) const override {
    return affineIn(key) || !prediction_.layout().isPosition(component);
  }

 private:
  SatellitePrediction prediction_;
};

/// IF carrier phase: error = phase(x) + bias - observed phase; sigma = phase_sigma_m.
class PppPhaseFactor : public smoother::NoiseModelFactor2<smoother::Vector, double> {
 public:
  PppPhaseFactor(smoother::Key state, smoother::Key bias, SatellitePrediction prediction,
                 smoother::NoiseModel::Ptr noise);
  smoother::Vector evaluateError(const smoother::Vector& state, const double& bias_m, smoother::Matrix* h_state,
                                 smoother::Matrix* h_bias) const override;
  const SatellitePrediction& prediction() const { return prediction_; }
  /// The bias enters with coefficient +1, the state's ZWD and clock with constant
  /// coefficients (the mapping frozen at x0); the range alone is nonlinear.
  bool affineIn(smoother::Key key) const override { return key == this->key<1>() || !prediction_.exactRange(); }
  bool affineInComponent(smoother::Key key, int component) const override {
    return affineIn(key) || !prediction_.layout().isPosition(component);
  }

 private:
  SatellitePrediction prediction_;
};

/// Random walk of position and ZWD (and of the tropospheric gradients when the
/// layout has them) between two states: error = (position, ZWD[, G_N, G_E]) of
/// x2 - x1, sigmas (position x3, ZWD[, gradient x2]) [m] over the time step.
class ReceiverRandomWalkFactor : public smoother::NoiseModelFactor2<smoother::Vector, smoother::Vector> {
 public:
  /// `gradient_sigma_m` is used only when layout.hasGradients().
  ReceiverRandomWalkFactor(smoother::Key previous, smoother::Key next, const ReceiverStateLayout& layout,
                           double position_sigma_m, double zwd_sigma_m, double gradient_sigma_m = 0.0);
  smoother::Vector evaluateError(const smoother::Vector& previous, const smoother::Vector& next,
                                 smoother::Matrix* h_previous, smoother::Matrix* h_next) const override;
  bool affineIn(smoother::Key) const override { return true; }  // a difference of states

 private:
  ReceiverStateLayout layout_;
};

/// Prior on one clock component (state index `clock_index`) of one state:
/// error = clock - clock_m.
class ClockPriorFactor : public smoother::NoiseModelFactor1<smoother::Vector> {
 public:
  ClockPriorFactor(smoother::Key state, int clock_index, double clock_m, double sigma_m);
  smoother::Vector evaluateError(const smoother::Vector& state, smoother::Matrix* h_state) const override;
  double clock_m() const { return clock_m_; }
  int clockIndex() const { return clock_index_; }
  bool affineIn(smoother::Key) const override { return true; }

 private:
  int clock_index_;
  double clock_m_;
};

}  // namespace ppp
