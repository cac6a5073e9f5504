#pragma once
// SO(3), the group of 3-D rotations, as the navigation code uses it: hat and vee,
// the exponential and logarithm maps, and the right Jacobian with its inverse
// (Forster et al. 2017, IEEE T-RO 33(1), eqs. (1)-(8); Chirikjian 2011, vol. 2,
// ch. 10). Rotations are Eigen matrices; tangent vectors are rotation vectors [rad].
// Perturbations are on the right: R Exp(dtheta).
#include <Eigen/Core>

namespace ppp {
namespace so3 {

/// The skew-symmetric matrix [w]x with [w]x v = w x v.
Eigen::Matrix3d hat(const Eigen::Vector3d& w);
/// The vector of a skew-symmetric matrix (inverse of hat; the symmetric part is ignored).
Eigen::Vector3d vee(const Eigen::Matrix3d& w_hat);

/// Exp: rotation vector [rad] -> rotation matrix (Rodrigues; Taylor series near zero).
Eigen::Matrix3d expMap(const Eigen::Vector3d& rotation_vector_rad);
/// Log: rotation matrix -> rotation vector [rad] with angle in [0, pi]
/// (stable near 0 and near pi).
Eigen::Vector3d logMap(const Eigen::Matrix3d& rotation);

/// Right Jacobian Jr(phi): Exp(phi + d) ~= Exp(phi) Exp(Jr(phi) d).
Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& rotation_vector_rad);
/// Inverse of the right Jacobian: Log(Exp(phi) Exp(d)) ~= phi + Jr^-1(phi) d.
Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& rotation_vector_rad);

/// Nearest rotation to a matrix that drifted from orthonormality (SVD projection).
Eigen::Matrix3d normalized(const Eigen::Matrix3d& almost_rotation);

}  // namespace so3
}  // namespace ppp
