// The certificate of a cached face axis for a resting pair: is the face's
// separation s along its normal u (A's frame, A -> B) SAT's largest within
// tol, at the new poses, without running SAT or GJK/EPA?
//
// The Minkowski difference D = B - A holds every point b - a. A face axis's
// facet of D is the reference face against the other shape's support
// feature. For a body resting face on face that feature is a whole face,
// the facet is the Minkowski sum of the two faces (large), and the origin
// lies well inside it; taking one support vertex instead (a translate of the
// reference face) leaves the origin near or outside its rim and the axis was
// never certified. The caller passes the points b_j - a_i of the reference
// face's vertices and of the incident face's vertices within tol / 2 of the
// support level (so every point lies at height in [s, s + tol / 2] along u),
// and D's support point along u (the apex). Then
//   * s >= 0: when the origin's projection lies inside the 2D hull of the
//     points projected along u, some point of conv(points), inside D, lies
//     at distance <= s + tol / 2: the distance is at most that;
//   * s < 0: every point is moved toward the apex onto the plane of the
//     highest one (still in D: D is convex), their 2D hull with the apex
//     makes a pyramid inside D, and when each of its side planes and its
//     base lie at least |s| - tol from the origin, the depth is at least
//     that.
// Either way no axis separates by more than s + tol, so the axis is the one
// a cold query chooses (manifold.cpp's choose_axis: a challenger must beat
// the incumbent by the bias, >= tol). Fixed buffers, no allocation.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <hedra/hull/assert.hpp>

namespace hedra::collision::detail {

inline constexpr std::size_t kFacetCapacity = 256;

// Points of D near the facet plane (heights along u within [s, s + tol / 2]).
struct FacetPoints {
  std::array<Eigen::Vector3d, kFacetCapacity> p;
  std::size_t count = 0;
};

// The 2D convex hull (counter-clockwise about u, Andrew's monotone chain) of
// the points' coordinates (x, y) in a frame orthogonal to u; writes the
// hull's indices into `hull` and returns their count (0 when fewer than 3
// points span an area).
inline std::size_t planar_hull(const std::array<Eigen::Vector2d, kFacetCapacity>& q, std::size_t count,
                               std::array<std::size_t, kFacetCapacity + 1>& hull) {
  if (count < 3) return 0;
  std::array<std::size_t, kFacetCapacity> order;
  for (std::size_t i = 0; i < count; ++i) order[i] = i;
  std::sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(count), [&](std::size_t i, std::size_t j) {
    return q[i].x() < q[j].x() || (q[i].x() == q[j].x() && q[i].y() < q[j].y());
  });
  const auto cross = [&](std::size_t o, std::size_t a, std::size_t b) {
    return (q[a] - q[o]).x() * (q[b] - q[o]).y() - (q[a] - q[o]).y() * (q[b] - q[o]).x();
  };
  std::size_t k = 0;
  for (std::size_t i = 0; i < count; ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], order[i]) <= 0.0) --k;
    hull[k++] = order[i];
  }
  for (std::size_t i = count - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 2], hull[k - 1], order[i]) <= 0.0) --k;
    hull[k++] = order[i];
  }
  return k >= 4 ? k - 1 : 0;  // the last point repeats the first
}

// True when the face axis (unit u, separation s <= the points' heights) is
// certified to be SAT's largest within tol (see the top of the file).
// `apex`: D's support point along u (only read when s < 0).
inline bool facet_certifies(const FacetPoints& facet, const Eigen::Vector3d& u, double s, double tol,
                            const Eigen::Vector3d& apex) {
  using Vec = Eigen::Vector3d;
  HEDRA_ASSERT(std::abs(u.squaredNorm() - 1.0) <= 1e-9);
  if (facet.count < 3 || facet.count > kFacetCapacity) return false;
  const Vec e1 = (std::abs(u.x()) < 0.6 ? Vec::UnitX() : Vec::UnitY()).cross(u).normalized();
  const Vec e2 = u.cross(e1);
  std::array<Eigen::Vector2d, kFacetCapacity> q;
  std::array<std::size_t, kFacetCapacity + 1> hull;
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < facet.count; ++i) top = std::max(top, u.dot(facet.p[i]));
  if (!(top <= s + tol)) return false;
  if (s >= 0.0) {
    for (std::size_t i = 0; i < facet.count; ++i) q[i] = {e1.dot(facet.p[i]), e2.dot(facet.p[i])};
    const std::size_t n = planar_hull(q, facet.count, hull);
    if (n < 3) return false;
    for (std::size_t k = 0; k < n; ++k) {  // the origin's projection (0, 0) on the left of every edge
      const Eigen::Vector2d a = q[hull[k]], b = q[hull[k + 1 == n ? 0 : k + 1]];
      if ((b - a).x() * (-a).y() - (b - a).y() * (-a).x() < 0.0) return false;
    }
    return true;
  }
  // Moved toward the apex onto the plane u . x = top.
  const double apex_height = u.dot(apex);
  std::array<Vec, kFacetCapacity> lifted;
  for (std::size_t i = 0; i < facet.count; ++i) {
    const Vec& p = facet.p[i];
    const double h = u.dot(p), rise = apex_height - h;
    if (!(rise > 0.0)) return false;
    lifted[i] = p + ((top - h) / rise) * (apex - p);
    q[i] = {e1.dot(lifted[i]), e2.dot(lifted[i])};
  }
  const std::size_t n = planar_hull(q, facet.count, hull);
  if (n < 3) return false;
  const double need = -s - tol;  // the ball's radius
  if (!(-top >= need)) return false;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec& p = lifted[hull[k]];
    const Vec& r = lifted[hull[k + 1 == n ? 0 : k + 1]];
    // Counter-clockwise about u seen from above, the apex above: (r - p) x
    // (apex - p) points outward.
    const Vec side = (r - p).cross(apex - p);
    const double len = side.norm();
    if (!(len > 0.0)) return false;
    if (!(side.dot(p) >= need * len)) return false;  // the origin at least `need` inside this side
  }
  return true;
}

}  // namespace hedra::collision::detail
