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
// never certified. The caller passes two convex polygons whose sums p + q
// are points of D: B's and A's sides of the facet (the reference face's
// vertices, and the incident face's within tol / 2 of the support level), so
// every sum lies at a height along u in [s, s + tol / 2]. Seen along u their
// sum is the 2D Minkowski sum M (merged edge by edge, O(n + m)). Then
//   * s >= 0: when the origin's projection lies inside M, some point of D
//     lies at distance <= s + tol / 2: the distance is at most that;
//   * s < 0: every sum moved toward D's support point along u (the apex)
//     onto the plane of the highest stays in D (D is convex) and moves
//     sideways by at most delta; when each side plane of the pyramid of M
//     (at that height) and the apex lies at least |s| - tol + delta from the
//     origin, and its base at least |s| - tol, the pyramid of the moved
//     points (inside D) holds the ball of radius |s| - tol: the depth is at
//     least that.
// Either way no axis separates by more than s + tol, so the axis is the one
// a cold query chooses (contact_choice.hpp's choose_axis: a challenger must beat
// the incumbent by the bias, >= tol). Fixed buffers, no allocation.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <hedra/hull/assert.hpp>
#include <limits>

namespace hedra::collision::detail {

inline constexpr std::size_t kFacetCapacity = 128;

// One side of the facet: a convex polygon in order (either orientation), 3D.
struct FacetSide {
  std::array<Eigen::Vector3d, kFacetCapacity> p;
  std::size_t count = 0;
};

// The 2D Minkowski sum of two convex polygons given counter-clockwise
// (x, y), with each vertex's height (the sum of the summands' heights):
// out holds at most n + m vertices, counter-clockwise.
struct PlanarSum {
  std::array<Eigen::Vector2d, 2 * kFacetCapacity> xy;
  std::array<double, 2 * kFacetCapacity> height;
  std::size_t count = 0;
};

inline std::size_t lowest_vertex(const Eigen::Vector2d* q, std::size_t n) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (q[i].y() < q[best].y() || (q[i].y() == q[best].y() && q[i].x() < q[best].x())) best = i;
  return best;
}

inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

inline void minkowski_sum(const Eigen::Vector2d* p, const double* hp, std::size_t n, const Eigen::Vector2d* q,
                          const double* hq, std::size_t m, PlanarSum& out) {
  const std::size_t i0 = lowest_vertex(p, n), j0 = lowest_vertex(q, m);
  std::size_t i = 0, j = 0;
  out.count = 0;
  while ((i < n || j < m) && out.count < out.xy.size()) {
    const std::size_t a = (i0 + i) % n, b = (j0 + j) % m;
    out.xy[out.count] = p[a] + q[b];
    out.height[out.count++] = hp[a] + hq[b];
    const Eigen::Vector2d ep = p[(a + 1) % n] - p[a], eq = q[(b + 1) % m] - q[b];
    const double turn = cross2(ep, eq);
    if (i == n)
      ++j;
    else if (j == m)
      ++i;
    else if (turn > 0.0)
      ++i;
    else if (turn < 0.0)
      ++j;
    else {
      ++i;
      ++j;
    }
  }
}

// The side's polygon seen along u (frame e1, e2), counter-clockwise, and
// its heights; false when it spans no area (then the sum is no polygon).
inline bool planar_side(const FacetSide& side, const Eigen::Vector3d& u, const Eigen::Vector3d& e1,
                        const Eigen::Vector3d& e2, std::array<Eigen::Vector2d, kFacetCapacity>& xy,
                        std::array<double, kFacetCapacity>& h) {
  const std::size_t n = side.count;
  double area = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    xy[i] = {e1.dot(side.p[i]), e2.dot(side.p[i])};
    h[i] = u.dot(side.p[i]);
  }
  for (std::size_t i = 0; i < n; ++i) area += cross2(xy[i], xy[(i + 1) % n]);
  if (area < 0.0) {
    std::reverse(xy.begin(), xy.begin() + static_cast<std::ptrdiff_t>(n));
    std::reverse(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(n));
  }
  return n == 1 || n == 2 || area != 0.0;
}

// Every k-th vertex of a side, at most `most` of them: still a convex
// polygon in order whose sums with the other side are points of D (the
// certificate over a subset holds for the whole), at a cost independent of
// a large face's degree.
inline void thin_side(const FacetSide& side, std::size_t most, FacetSide& out) {
  const std::size_t step = (side.count + most - 1) / most;
  out.count = 0;
  for (std::size_t i = 0; i < side.count; i += step) out.p[out.count++] = side.p[i];
}

inline bool facet_certifies_all(const FacetSide& first, const FacetSide& second, const Eigen::Vector3d& u, double s,
                                double tol, const Eigen::Vector3d& apex);

// True when the face axis (unit u, separation s <= every sum's height) is
// certified to be SAT's largest within tol (see the top of the file):
// first with each side thinned to 12 vertices (large faces), then whole.
// `apex`: D's support point along u (only read when s < 0).
inline bool facet_certifies(const FacetSide& first, const FacetSide& second, const Eigen::Vector3d& u, double s,
                            double tol, const Eigen::Vector3d& apex) {
  constexpr std::size_t kThin = 12;
  if (first.count > kThin || second.count > kThin) {
    FacetSide a, b;
    thin_side(first, kThin, a);
    thin_side(second, kThin, b);
    if (facet_certifies_all(a, b, u, s, tol, apex)) return true;
  }
  return facet_certifies_all(first, second, u, s, tol, apex);
}

inline bool facet_certifies_all(const FacetSide& first, const FacetSide& second, const Eigen::Vector3d& u, double s,
                                double tol, const Eigen::Vector3d& apex) {
  using Vec = Eigen::Vector3d;
  HEDRA_ASSERT(std::abs(u.squaredNorm() - 1.0) <= 1e-9);
  if (first.count == 0 || second.count == 0 || first.count + second.count < 3) return false;
  const Vec e1 = (std::abs(u.x()) < 0.6 ? Vec::UnitX() : Vec::UnitY()).cross(u).normalized();
  const Vec e2 = u.cross(e1);  // (e1, e2, u) right-handed: counter-clockwise seen from +u
  std::array<Eigen::Vector2d, kFacetCapacity> xy1, xy2;
  std::array<double, kFacetCapacity> h1, h2;
  if (!planar_side(first, u, e1, e2, xy1, h1) || !planar_side(second, u, e1, e2, xy2, h2)) return false;
  PlanarSum sum;
  minkowski_sum(xy1.data(), h1.data(), first.count, xy2.data(), h2.data(), second.count, sum);
  if (sum.count < 3) return false;
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < sum.count; ++k) top = std::max(top, sum.height[k]);
  if (!(top <= s + tol)) return false;
  if (s >= 0.0) {  // the origin's projection inside M
    for (std::size_t k = 0; k < sum.count; ++k) {
      const Eigen::Vector2d& a = sum.xy[k];
      if (cross2(sum.xy[(k + 1) % sum.count] - a, -a) < 0.0) return false;
    }
    return true;
  }
  const double need = -s - tol;  // the ball's radius
  if (!(-top >= need)) return false;
  const double apex_height = u.dot(apex);
  const Eigen::Vector2d apex_xy(e1.dot(apex), e2.dot(apex));
  double reach2 = 0.0;  // the largest sideways distance from the apex, squared
  for (std::size_t k = 0; k < sum.count; ++k) reach2 = std::max(reach2, (sum.xy[k] - apex_xy).squaredNorm());
  if (!(apex_height > top)) return false;
  const double delta = (top - s) / (apex_height - top) * std::sqrt(reach2);
  const double margin = need + delta;
  for (std::size_t k = 0; k < sum.count; ++k) {
    const Eigen::Vector2d& a = sum.xy[k];
    const Eigen::Vector2d& b = sum.xy[(k + 1) % sum.count];
    const Vec p = a.x() * e1 + a.y() * e2 + top * u;
    const Vec r = b.x() * e1 + b.y() * e2 + top * u;
    // Counter-clockwise seen from +u, the apex above: (r - p) x (apex - p)
    // points outward.
    const Vec side = (r - p).cross(apex - p);
    const double inside = side.dot(p);  // the origin's distance inside this side, times |side|
    const bool holds = margin > 0.0 ? inside > 0.0 && inside * inside >= margin * margin * side.squaredNorm()
                                    : inside >= margin * std::sqrt(side.squaredNorm());
    if (!holds) return false;
  }
  return true;
}

}  // namespace hedra::collision::detail
