// Closed forms of penetration() for pairs that have one: a sphere whose
// centre lies inside a box's core (either order), where GJK would only find
// the cores overlapping and EPA would grow a polytope around the box. With p
// the centre in the box's frame (|p_i| <= h_i), the depth of the cores is
// the smallest h_i - |p_i|, along the axis of that face (ties: the first
// axis, and + when p_i = 0); the radii (the sphere's radius and margin, the
// box's margin) add to it. Exact in exact arithmetic. p is computed with a
// 64-bit significand where long double has one (x86's extended format), so
// that the answer is nearly correctly rounded, and in double elsewhere (never
// in a software-emulated quad long double: this is a per-query path); the
// error bound holds for double arithmetic (sphere_box_bound). Centres
// outside the core keep GJK's path: there penetration() equals distance()
// bit for bit.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <hedra/collision/pose.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/shapes.hpp>
#include <limits>
#include <type_traits>

namespace hedra::collision::closed_form {

// |computed - exact| of the signed distance in double arithmetic, u = eps /
// 2: p's coordinates carry at most 4u L each (L = |d|_1, d the centres'
// difference: one rounding of d, three products and two sums of the
// rotation), so p is off by at most 7u L and, the depth being 1-Lipschitz
// in p, so is the core depth; its own evaluation (one subtraction) adds u
// of its size, and adding the radii 2u of the sizes involved. 8 eps (L +
// |core| + radii) covers the sum with room.
inline double sphere_box_bound(double l1, double core, double radii) {
  return 8.0 * std::numeric_limits<double>::epsilon() * (l1 + std::abs(core) + radii);
}

// Sphere `s` at `pose_s`, box `b` at `pose_b`; `sphere_first`: the sphere is
// A (the normal points from A toward B). Answers (true, `out`) only when the
// sphere's centre is inside the core box (or on it): elsewhere the cores are
// apart, and penetration() keeps GJK's path, whose answer on separated pairs
// is distance()'s bit for bit.
inline bool sphere_box(const Sphere& s, const Pose& pose_s, const Box& b, const Pose& pose_b, bool sphere_first,
                       PenetrationResult& out) {
  // x86's extended precision where it is native; double (which the bound covers) elsewhere.
  using Wide = std::conditional_t<std::numeric_limits<long double>::digits == 64, long double, double>;
  const Eigen::Matrix3d& R = pose_b.rotation;
  const Eigen::Vector3d& h = b.half_extents;
  Wide d[3], p[3];
  for (int i = 0; i < 3; ++i) d[i] = Wide(pose_s.translation[i]) - Wide(pose_b.translation[i]);
  bool inside = true;
  for (int i = 0; i < 3; ++i) {  // the sphere's centre in the box frame
    p[i] = (Wide(R(0, i)) * d[0] + Wide(R(1, i)) * d[1]) + Wide(R(2, i)) * d[2];
    inside = inside && std::abs(p[i]) <= Wide(h[i]);
  }
  if (!inside) return false;
  // The face of least depth; its outward axis is -n.
  int axis = 0;
  Wide depth = Wide(h[0]) - std::abs(p[0]);
  for (int i = 1; i < 3; ++i)
    if (Wide(h[i]) - std::abs(p[i]) < depth) {
      depth = Wide(h[i]) - std::abs(p[i]);
      axis = i;
    }
  const double side = p[axis] >= 0 ? 1.0 : -1.0;
  Eigen::Vector3d n = Eigen::Vector3d::Zero();  // box frame, from the sphere toward the box
  n[axis] = -side;
  const Eigen::Vector3d at_p{static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])};
  Eigen::Vector3d on_b = at_p;  // the box core's witness, box frame: p moved onto that face
  on_b[axis] = side * h[axis];
  const Wide core_wide = -depth;  // signed distance of the cores
  const double core = double(core_wide);
  const double l1 = std::abs(pose_s.translation.x() - pose_b.translation.x()) +
                    std::abs(pose_s.translation.y() - pose_b.translation.y()) +
                    std::abs(pose_s.translation.z() - pose_b.translation.z());
  const double rs = s.radius + s.margin, rb = b.margin;
  out = PenetrationResult{};
  out.distance = double(core_wide - (Wide(rs) + Wide(rb)));
  out.intersecting = out.distance <= 0.0;
  out.error_bound = sphere_box_bound(l1, core, rs + rb);
  // Witnesses: the cores' points moved out by the radii, made consistent
  // (point on the box - point on the sphere = distance * n) about their
  // midpoint, then placed in the world.
  const Eigen::Vector3d mid = 0.5 * (at_p + on_b);
  const Eigen::Vector3d at_s = mid - (0.5 * core - rs) * n;
  const Eigen::Vector3d at_b = mid + (0.5 * core - rb) * n;
  const Eigen::Vector3d world_s = R * at_s + pose_b.translation;
  const Eigen::Vector3d world_b = R * at_b + pose_b.translation;
  const Eigen::Vector3d world_n = R * n;
  out.normal = sphere_first ? world_n : Eigen::Vector3d(-world_n);
  out.point_a = sphere_first ? world_s : world_b;
  out.point_b = sphere_first ? world_b : world_s;
  return true;
}

}  // namespace hedra::collision::closed_form
