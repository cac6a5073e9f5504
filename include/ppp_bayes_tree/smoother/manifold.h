#pragma once
// Manifold: how a variable that is not a plain vector moves. A variable of the smoother
// is stored as a dynamic vector; a vector-space variable (the default, no Manifold)
// retracts by addition and its tangent dimension is its size. A manifold variable
// (e.g. a navigation state with a rotation) names a Manifold that retracts its storage
// by a tangent vector, x (+) d, and gives the local coordinates y (-) x, the tangent d
// with x (+) d == y. Deltas, Jacobian columns and the linear system always live in the
// tangent space.
#include <Eigen/Core>

#include <memory>

namespace ppp::smoother {

class Manifold {
 public:
  using Ptr = std::shared_ptr<const Manifold>;
  virtual ~Manifold() = default;

  /// A short name for error messages ("nav_state").
  virtual const char* name() const = 0;
  /// Number of stored components.
  virtual int storageDim() const = 0;
  /// Dimension of the tangent space (the variable's dimension in the linear system).
  virtual int tangentDim() const = 0;
  /// x (+) delta (delta of tangentDim() components).
  virtual Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const = 0;
  /// The tangent vector d with x (+) d == y.
  virtual Eigen::VectorXd localCoordinates(const Eigen::VectorXd& x, const Eigen::VectorXd& y) const = 0;
};

}  // namespace ppp::smoother
