// Pairs moving along smooth trajectories, for the frame-coherence benchmark
// and test: each frame B slides by 1 % of the pair's size across the
// normal and turns by 1 degree about a fixed random axis, then moves along
// penetration()'s normal (cold, outside any timing) so that its signed
// distance stays the family's target: separated (+2 % of the size),
// touching (0) or slightly penetrating (-1 % of the size). Seeded.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/query.hpp>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace hedra::trajectories {

using collision::Pose;
using collision::Shape;
using Vec = Eigen::Vector3d;

struct Trajectory {
  Shape a, b;
  Pose pose_a;
  std::vector<Pose> pose_b;  // one per frame
  double size = 0.0;         // bounding radii of A and B summed
};

inline Vec random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec(g(rng), g(rng), g(rng)).normalized();
}

inline std::shared_ptr<const collision::ConvexPolyhedron> ellipsoid_hull(std::mt19937_64& rng, int n,
                                                                         const Vec& radii) {
  std::vector<Vec> points;
  for (int i = 0; i < n; ++i) points.push_back(random_unit(rng).cwiseProduct(radii));
  return collision::ConvexPolyhedron::build(points).polyhedron;
}

inline Pose random_pose(std::mt19937_64& rng, const Vec& t) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized(), t);
}

// B moved along the normal until its signed distance is `target` (two
// corrections: the closest features may change after the first).
inline void place(const Trajectory& t, Pose& pose_b, double target) {
  for (int k = 0; k < 3; ++k) {
    const collision::PenetrationResult p = collision::penetration(t.a, t.pose_a, t.b, pose_b);
    if (p.status != collision::Status::ok) return;
    pose_b.translation += (target - p.distance) * p.normal;
  }
}

// `shape` names a family: box, box_resting, hull<n>, rounded_box, rounded_hull<n>.
inline Shape make_shape(const std::string& shape, std::mt19937_64& rng, bool first) {
  const double margin = shape.rfind("rounded", 0) == 0 ? 0.05 : 0.0;
  if (shape == "box" || shape == "rounded_box" || shape == "box_resting") {
    const double h = shape == "box_resting" && first ? 1.0 : 0.5;
    collision::Box box{Vec(h, h, shape == "box_resting" && first ? 0.25 : h)};
    box.margin = margin;
    return box;
  }
  const int n = std::stoi(shape.substr(shape.find("hull") + 4));
  collision::Polyhedron poly{ellipsoid_hull(rng, n, first ? Vec(1.0, 0.8, 0.6) : Vec(0.7, 0.9, 0.5))};
  poly.margin = margin;
  return poly;
}

// `count` trajectories of `frames` frames; target: the signed distance
// kept, as a fraction of the size.
inline std::vector<Trajectory> make_trajectories(const std::string& shape, double target, int count, int frames,
                                                 std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Trajectory> out;
  const bool resting = shape == "box_resting";
  for (int i = 0; i < count; ++i) {
    Trajectory t;
    t.a = make_shape(shape, rng, true);
    t.b = make_shape(shape, rng, false);
    t.size = collision::bounding_radius(t.a) + collision::bounding_radius(t.b);
    // A box resting on a plate's face, turning about the face normal;
    // otherwise random orientations and a random approach direction.
    t.pose_a = resting ? Pose::identity() : random_pose(rng, Vec::Zero());
    const Vec dir = resting ? Vec::UnitZ() : random_unit(rng);
    Pose pose = resting ? Pose::identity() : random_pose(rng, Vec::Zero());
    pose.translation = t.size * dir;
    const Vec axis = resting ? Vec::UnitZ() : random_unit(rng);
    const Vec slide = (resting ? Vec::UnitX() : dir.unitOrthogonal()).normalized();
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 180.0, axis).toRotationMatrix();
    for (int f = 0; f < frames; ++f) {
      if (f > 0) {
        // Slide back and forth (a triangle wave over 100 frames) so that
        // the pair keeps touching over long runs.
        const double sign = (f / 50) % 2 == 0 ? 1.0 : -1.0;
        pose.translation += sign * 0.01 * t.size * slide;
        pose.rotation = turn * pose.rotation;
      }
      place(t, pose, target * t.size);
      t.pose_b.push_back(pose);
    }
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace hedra::trajectories
