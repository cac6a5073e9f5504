#include "ppp_bayes_tree/ppp/model/ppp_factors.h"

#include <cmath>

namespace ppp {

using smoother::Matrix;
using smoother::Values;
using smoother::Vector;

smoother::Key stateKey(std::uint32_t epoch_index) { return smoother::symbolKey('x', epoch_index); }

smoother::Key biasKey(const SatelliteId& satellite, ArcId arc) {
  return smoother::symbolKey('b', satellite.toString(), arc);
}

SatellitePrediction::SatellitePrediction(const SatelliteMeasurement& m, const ReceiverState& x0, bool exact_range)
    : m_(m), layout_(x0.layout), x0_(x0.vector()), windup_m_(m.predicted_phase_m - m.predicted_code_m) {
  if (exact_range && m.satellite_apc_ecef_m) {
    offset_ = m.receiver_apc_offset_ecef_m;
    const Eigen::Vector3d d = *m.satellite_apc_ecef_m - (x0.position_ecef_m + offset_);
    range0_m_ = d.norm();
    if (range0_m_ > 0.0 && std::isfinite(range0_m_)) {
      satellite_ = m.satellite_apc_ecef_m;
      // The model's position partial is -e0 + (dry delay height term): keep the latter.
      dry_gradient_ =
          m.jacobian.segment<ReceiverStateLayout::kPositionSize>(layout_.position()).transpose() + d / range0_m_;
      const int rest = static_cast<int>(x0_.size()) - ReceiverStateLayout::kPositionSize;
      if (layout_.position() == 0 && m.jacobian.size() == x0_.size() && rest >= 0 && rest <= kMaxRest) {
        x0_position_ = x0_.head<ReceiverStateLayout::kPositionSize>();
        rest_count_ = rest;
        for (int i = 0; i < rest; ++i) {
          rest_x0_[static_cast<std::size_t>(i)] = x0_(ReceiverStateLayout::kPositionSize + i);
          rest_partial_[static_cast<std::size_t>(i)] = m.jacobian(ReceiverStateLayout::kPositionSize + i);
        }
      }
    }
  }
}

double SatellitePrediction::code_m(const Eigen::VectorXd& x, Row* jacobian) const {
  constexpr int kPos = ReceiverStateLayout::kPositionSize;
  const int p = layout_.position();
  if (!satellite_) {
    const Eigen::VectorXd dx = x - x0_;
    if (jacobian != nullptr) *jacobian = m_.jacobian;
    return m_.predicted_code_m + m_.jacobian.dot(dx);
  }
  if (rest_count_ >= 0 && x.size() == kPos + rest_count_) {
    // The same terms from the values held in the object (position first in the state).
    const Eigen::Vector3d d = *satellite_ - (x.head<kPos>() + offset_);
    const double range = d.norm();
    const Eigen::Vector3d dpos = x.head<kPos>() - x0_position_;
    double h = m_.predicted_code_m + (range - range0_m_) + dry_gradient_.dot(dpos);
    double rest = 0.0;
    for (int i = 0; i < rest_count_; ++i) {
      const auto k = static_cast<std::size_t>(i);
      rest += rest_partial_[k] * (x(kPos + i) - rest_x0_[k]);
    }
    h += rest;
    if (jacobian != nullptr) {
      jacobian->resize(1, kPos + rest_count_);
      jacobian->block<1, kPos>(0, 0) = (-d / range + dry_gradient_).transpose();
      for (int i = 0; i < rest_count_; ++i) (*jacobian)(0, kPos + i) = rest_partial_[static_cast<std::size_t>(i)];
    }
    return h;
  }
  // dx = x - x0 element by element where it is needed (no vector of it).
  const Eigen::Vector3d d = *satellite_ - (x.segment<kPos>(p) + offset_);
  const double range = d.norm();
  const Eigen::Vector3d dpos = x.segment<kPos>(p) - x0_.segment<kPos>(p);
  double h = m_.predicted_code_m + (range - range0_m_) + dry_gradient_.dot(dpos);
  // ZWD and clocks: the model's constant partials (in state order).
  double rest = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!layout_.isPosition(static_cast<int>(i))) rest += m_.jacobian(i) * (x(i) - x0_(i));
  h += rest;
  if (jacobian != nullptr) {
    jacobian->resize(1, m_.jacobian.size());
    jacobian->row(0) = m_.jacobian;
    jacobian->block<1, kPos>(0, p) = (-d / range + dry_gradient_).transpose();
  }
  return h;
}

PppCodeFactor::PppCodeFactor(smoother::Key state, SatellitePrediction prediction, smoother::NoiseModel::Ptr noise)
    : NoiseModelFactorN(std::move(noise), {state}), prediction_(std::move(prediction)) {}

Vector PppCodeFactor::evaluateError(const Vector& state, Matrix* h_state) const {
  Vector e(1);
  e(0) = prediction_.code_m(state, h_state) - prediction_.measurement().observed_code_m;
  return e;
}

PppPhaseFactor::PppPhaseFactor(smoother::Key state, smoother::Key bias, SatellitePrediction prediction,
                               smoother::NoiseModel::Ptr noise)
    : NoiseModelFactorN(std::move(noise), {state, bias}), prediction_(std::move(prediction)) {}

Vector PppPhaseFactor::evaluateError(const Vector& state, const double& bias_m, Matrix* h_state,
                                     Matrix* h_bias) const {
  Vector e(1);
  e(0) = prediction_.phase_m(state, h_state) + bias_m - prediction_.measurement().observed_phase_m;
  if (h_bias != nullptr) h_bias->setOnes(1, 1);
  return e;
}

namespace {

/// Sigmas of the random walk's components: position x3, ZWD[, gradient x2].
Vector randomWalkSigmas(const ReceiverStateLayout& layout, double position_sigma_m, double zwd_sigma_m,
                        double gradient_sigma_m) {
  constexpr int kPos = ReceiverStateLayout::kPositionSize;
  Vector sigmas(kPos + 1 + (layout.hasGradients() ? ReceiverStateLayout::kGradientSize : 0));
  sigmas.head<kPos>().setConstant(position_sigma_m);
  sigmas(kPos) = zwd_sigma_m;
  if (layout.hasGradients()) sigmas.tail<ReceiverStateLayout::kGradientSize>().setConstant(gradient_sigma_m);
  return sigmas;
}

}  // namespace

ReceiverRandomWalkFactor::ReceiverRandomWalkFactor(smoother::Key previous, smoother::Key next,
                                                   const ReceiverStateLayout& layout, double position_sigma_m,
                                                   double zwd_sigma_m, double gradient_sigma_m)
    : NoiseModelFactorN(
          smoother::NoiseModel::sigmas(randomWalkSigmas(layout, position_sigma_m, zwd_sigma_m, gradient_sigma_m)),
          {previous, next}),
      layout_(layout) {}

Vector ReceiverRandomWalkFactor::evaluateError(const Vector& previous, const Vector& next, Matrix* h_previous,
                                               Matrix* h_next) const {
  constexpr int kPos = ReceiverStateLayout::kPositionSize;
  constexpr int kGrad = ReceiverStateLayout::kGradientSize;
  const int rows = kPos + 1 + (layout_.hasGradients() ? kGrad : 0);
  const Vector d = next - previous;
  Vector e(rows);
  e.head<kPos>() = d.segment<kPos>(layout_.position());
  e(kPos) = d(layout_.zwd());
  if (layout_.hasGradients()) e.tail<kGrad>() = d.segment<kGrad>(layout_.gradientNorth());
  if (h_previous != nullptr || h_next != nullptr) {
    Matrix j = Matrix::Zero(rows, layout_.dim());
    j.block<kPos, kPos>(0, layout_.position()).setIdentity();
    j(kPos, layout_.zwd()) = 1.0;
    if (layout_.hasGradients()) j.block<kGrad, kGrad>(kPos + 1, layout_.gradientNorth()).setIdentity();
    if (h_previous != nullptr) *h_previous = -j;
    if (h_next != nullptr) *h_next = j;
  }
  return e;
}

ClockPriorFactor::ClockPriorFactor(smoother::Key state, int clock_index, double clock_m, double sigma_m)
    : NoiseModelFactorN(smoother::NoiseModel::isotropic(1, sigma_m), {state}),
      clock_index_(clock_index),
      clock_m_(clock_m) {}

Vector ClockPriorFactor::evaluateError(const Vector& state, Matrix* h_state) const {
  Vector e(1);
  e(0) = state(clock_index_) - clock_m_;
  if (h_state != nullptr) {
    Matrix j = Matrix::Zero(1, state.size());
    j(0, clock_index_) = 1.0;
    *h_state = j;
  }
  return e;
}

}  // namespace ppp
