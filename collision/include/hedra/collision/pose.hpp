// A rigid motion of a shape: x_world = rotation * x_local + translation, and
// the bound on translations that queries accept. Every query takes one Pose
// per shape; Pose::valid() is what they check before anything else.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace hedra::collision {

// The largest |coordinate| of a pose's translation that queries accept.
constexpr double max_coordinate = 1e60;

// How far a pose's rotation may be from a rotation and still be accepted:
// max_ij |(R^T R - I)_ij| <= rotation_tolerance, with det R > 0. Rotations
// built from quaternions, and a simulator's float or double transforms with
// their accumulated drift, are orthonormal to 1e-7 or better; a rotation
// scaled, sheared or reflected is not a rigid motion, and queries answer
// invalid_input for it (the tolerance of the Python module's pose check).
constexpr double rotation_tolerance = 1e-6;

// A rigid motion: x_world = rotation * x_local + translation. `rotation`
// must be orthonormal with determinant +1 within rotation_tolerance
// (from_quaternion normalises); valid() checks it.
struct Pose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  static Pose identity() { return {}; }
  static Pose from_translation(const Eigen::Vector3d& t) { return {Eigen::Matrix3d::Identity(), t}; }
  // Normalises q after scaling by its largest coefficient, so that tiny or
  // huge quaternions normalise to full precision (at 1e-155 the squared
  // norm is subnormal). A zero or non-finite q gives a pose that is not
  // valid() (NaN rotation), so queries answer invalid_input instead of
  // guessing.
  static Pose from_quaternion(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
    const double largest = q.coeffs().cwiseAbs().maxCoeff();
    if (!(largest > 0.0) || !std::isfinite(largest))
      return {Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN()), t};
    const Eigen::Vector4d c = q.coeffs() / largest;
    return {Eigen::Quaterniond(c / c.norm()).toRotationMatrix(), t};
  }
  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  bool finite() const { return rotation.allFinite() && translation.allFinite(); }
  // The rotation is one: every entry of R^T R - I (the columns' dot
  // products) within rotation_tolerance and det R = (c0 x c1) . c2 > 0.
  // Every comparison fails for NaN, and an infinite or overflowing entry
  // makes a squared norm infinite, so this also checks finiteness. About 40
  // instructions, once per query at the API's edge (docs/embedding.md).
  bool is_rotation() const {
    const Eigen::Vector3d c0 = rotation.col(0), c1 = rotation.col(1), c2 = rotation.col(2);
    const double t = rotation_tolerance;
    const bool orthonormal = (std::abs(c0.squaredNorm() - 1.0) <= t) & (std::abs(c1.squaredNorm() - 1.0) <= t) &
                             (std::abs(c2.squaredNorm() - 1.0) <= t) & (std::abs(c0.dot(c1)) <= t) &
                             (std::abs(c0.dot(c2)) <= t) & (std::abs(c1.dot(c2)) <= t);
    return orthonormal && c0.cross(c1).dot(c2) > 0.0;
  }
  // What queries accept: a rotation (is_rotation()) and every translation
  // coordinate within max_coordinate (squared distances between bodies must
  // not overflow; a NaN or infinite translation fails its comparison).
  bool valid() const {
    return is_rotation() && std::abs(translation.x()) <= max_coordinate &&
           std::abs(translation.y()) <= max_coordinate && std::abs(translation.z()) <= max_coordinate;
  }
};

}  // namespace hedra::collision
