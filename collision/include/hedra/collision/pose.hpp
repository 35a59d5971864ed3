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

// A rigid motion: x_world = rotation * x_local + translation. `rotation`
// must be orthonormal with determinant +1 (from_quaternion normalises).
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
  // What queries accept: finite, with every translation coordinate within
  // max_coordinate (squared distances between bodies must not overflow).
  // Written out: x - x is 0 for every finite x and NaN otherwise, so the sum
  // over the rotation is 0 exactly when all nine are finite; a NaN or
  // infinite translation fails its comparison.
  bool valid() const {
    const double* r = rotation.data();
    const double rotation_rounding = (((r[0] - r[0]) + (r[1] - r[1])) + ((r[2] - r[2]) + (r[3] - r[3]))) +
                                     (((r[4] - r[4]) + (r[5] - r[5])) + ((r[6] - r[6]) + (r[7] - r[7]))) +
                                     (r[8] - r[8]);
    return rotation_rounding == 0.0 && std::abs(translation.x()) <= max_coordinate &&
           std::abs(translation.y()) <= max_coordinate && std::abs(translation.z()) <= max_coordinate;
  }
};

}  // namespace hedra::collision
