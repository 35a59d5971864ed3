// GJK (Gilbert, Johnson, Keerthi 1988) over support mappings, with the
// signed-volumes sub-algorithm of Montanari, Petrinic and Barbieri (ACM TOG
// 36(3), 2017). Both shapes are support types (`support(d) const`) in one
// common frame (the query layer uses A's core frame).
//
// The loop searches v, the point of D = A - B nearest the origin: w =
// s_A(-v) - s_B(v) goes into the simplex (at most 4 points w_i = a_i - b_i),
// which is replaced by its sub-simplex nearest the origin (chosen from the
// signs of signed volumes only, no threshold); v is the origin's projection
// on that sub-simplex's affine hull, computed from its normal.
// Invariants and bounds: v . w / |v| <= distance <= |v| (certified; the
// duality gap bounds the error); the simplex holds 1..3 points at the top of
// the loop; |v|^2 decreases strictly, except up to 4 steps "sideways" within
// 16 eps of itself, undone unless they lead below the best; every exit
// keeps finite outputs and a status (ok, stalled, max_iterations,
// degenerate), never reading a cap as "separated". gjk_intersect stops at
// the first separating axis (v . w > margin |v|; the start axis is tested
// too) or once |v| <= margin.
// Warm start: the caller's initial axis (a GjkCache's last v, or the centre
// difference). Derivations: docs/design.md, "GJK".
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <hedra/collision/detail/vector_math.hpp>
#include <hedra/collision/settings.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>

namespace hedra::collision {

enum class GjkStatus {
  ok,              // converged: outputs valid
  max_iterations,  // the cap was hit: outputs are the best so far, not a verdict
  stalled,         // rounding stopped progress before the tolerance: best so far, see error_bound
  degenerate,      // a support point was not finite (NaN/inf input)
};

inline const char* to_string(GjkStatus status) {
  switch (status) {
    case GjkStatus::ok:
      return "ok";
    case GjkStatus::max_iterations:
      return "max_iterations";
    case GjkStatus::stalled:
      return "stalled";
    case GjkStatus::degenerate:
      return "degenerate";
  }
  return "unknown";
}

struct GjkSimplex {
  int size = 0;
  std::array<Eigen::Vector3d, 4> w;  // a - b
  std::array<Eigen::Vector3d, 4> a;
  std::array<Eigen::Vector3d, 4> b;
  std::array<double, 4> lambda{};  // barycentric weights of v, summing to 1
};

struct GjkResult {
  GjkStatus status = GjkStatus::ok;
  bool intersecting = false;                          // cores overlap or touch (gjk_intersect: distance <= margin)
  double distance = 0.0;                              // |v|; 0 when intersecting
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  // closest points, common frame
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // point_a - point_b: last search axis
  double lower_bound = 0.0;                     // certified: true distance >= lower_bound
  // Certified: the cores' signed distance (minus the depth when they
  // overlap) >= signed_lower_bound, the best v . w / |v| of all iterations
  // unclamped (-h(-v/|v|) of the difference, a lower bound whatever its
  // sign); -infinity before the first iteration. With |v| it brackets a
  // touching pair: |v| - signed_lower_bound within the tolerance means the
  // signed distance is known to it, overlapping or not.
  double signed_lower_bound = -std::numeric_limits<double>::infinity();
  double error_bound = 0.0;  // distance - lower_bound (duality gap / |v|)
  int iterations = 0;
  int support_calls = 0;  // evaluations of the Minkowski difference's support (one per iteration, plus the first)
  GjkSimplex simplex;
};

namespace gjk_detail {

// Strictly the same sign (0 matches nothing): the acceptance test of the
// signed-volumes method.
inline bool same_sign(double x, double y) { return (x > 0.0 && y > 0.0) || (x < 0.0 && y < 0.0); }

// A sub-simplex, the barycentric weights of its point nearest the origin,
// and that point (computed by projection: docs/design.md, "GJK").
struct Sub {
  int size = 0;
  std::array<int, 4> index{};
  std::array<double, 4> lambda{};
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

inline void vertex(const std::array<Eigen::Vector3d, 4>& w, int i, Sub& out) {
  out.size = 1;
  out.index[0] = i;
  out.lambda[0] = 1.0;
  out.point = w[i];
}

// Segment w[i0] w[i1].
inline void s1d(const std::array<Eigen::Vector3d, 4>& w, int i0, int i1, Sub& out) {
  const Eigen::Vector3d& p0 = w[i0];
  const Eigen::Vector3d& p1 = w[i1];
  const Eigen::Vector3d t = p1 - p0;
  const double tt = t.squaredNorm();
  int axis = 0;
  t.cwiseAbs().maxCoeff(&axis);
  const double mu = t[axis];
  if (!(tt > 0.0) || mu == 0.0) {
    // A point-like segment: the nearer end (NaN compares false: p1).
    vertex(w, p0.squaredNorm() < p1.squaredNorm() ? i0 : i1, out);
    return;
  }
  // Projection of the origin on the line, from the nearer end (the smaller
  // |base|, the smaller the cancellation); a second projection removes the
  // component along t the first left by rounding (eps |base|, large against
  // |p| near contact). Rotations of p about t are harmless; a tilt towards t
  // would lower every v . w_i by |w_i - p| times the tilt and spoil the
  // certified gap on a long segment near the origin (1e3 against 1e-3).
  // Then 1D signed lengths along the axis where the segment is longest.
  const Eigen::Vector3d& base = p0.squaredNorm() <= p1.squaredNorm() ? p0 : p1;
  Eigen::Vector3d p = base - (base.dot(t) / tt) * t;
  p -= (p.dot(t) / tt) * t;
  const double c0 = p1[axis] - p[axis];  // lambda_0 * mu
  const double c1 = p[axis] - p0[axis];  // lambda_1 * mu
  if (same_sign(mu, c0) && same_sign(mu, c1)) {
    out.size = 2;
    out.index[0] = i0;
    out.index[1] = i1;
    out.lambda[0] = c0 / mu;
    out.lambda[1] = c1 / mu;
    out.point = p;
  } else if (!same_sign(mu, c1)) {
    vertex(w, i0, out);  // the projection lies before p0
  } else {
    vertex(w, i1, out);  // beyond p1
  }
}

// Triangle w[i0] w[i1] w[i2]. `newest` (one of the three indices, or -1):
// the support point just added, whose edges are examined whatever the signs
// say (see s3d).
inline void s2d(const std::array<Eigen::Vector3d, 4>& w, int i0, int i1, int i2, Sub& out, int newest = -1) {
  const Eigen::Vector3d& p0 = w[i0];
  const Eigen::Vector3d& p1 = w[i1];
  const Eigen::Vector3d& p2 = w[i2];
  const Eigen::Vector3d n = area_vector(p0, p1, p2);
  const double nn = n.squaredNorm();
  // Which edges to examine when the projection is not strictly inside: the
  // edge opposite vertex m where the m-th coordinate has the wrong sign, or
  // all three for a collinear (or non-finite) triangle.
  std::array<bool, 3> outside = {true, true, true};
  if (nn > 0.0 && std::isfinite(nn)) {
    // The origin projected on the plane: along n, so v's direction is n's.
    const Eigen::Vector3d p = (((p0.dot(n) + p1.dot(n)) + p2.dot(n)) / (3.0 * nn)) * n;
    int k = 0;
    n.cwiseAbs().maxCoeff(&k);
    const int i = (k + 1) % 3;
    const int j = (k + 2) % 3;
    // Twice the signed area of the projection on the (i, j) plane, the one
    // where the triangle is largest; area(p0, p1, p2) = n_k.
    auto area = [i, j](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
      return (b[i] - a[i]) * (c[j] - a[j]) - (b[j] - a[j]) * (c[i] - a[i]);
    };
    const double mu = area(p0, p1, p2);
    const std::array<double, 3> c = {area(p, p1, p2), area(p0, p, p2), area(p0, p1, p)};
    for (int m = 0; m < 3; ++m) outside[m] = !same_sign(mu, c[m]);
    if (!outside[0] && !outside[1] && !outside[2]) {
      out.size = 3;
      out.index = {i0, i1, i2, 0};
      for (int m = 0; m < 3; ++m) out.lambda[m] = c[m] / mu;
      out.point = p;
      return;
    }
  }
  const std::array<int, 3> ids = {i0, i1, i2};
  double best = std::numeric_limits<double>::infinity();
  bool found = false;
  const bool has_newest = newest == i0 || newest == i1 || newest == i2;
  for (int m = 0; m < 3; ++m) {
    if (!outside[m] && !(has_newest && ids[m] != newest)) continue;
    // The first candidate is written straight into `out`, later ones into
    // `candidate`, copied only when closer.
    Sub candidate;
    Sub& target = found ? candidate : out;
    s1d(w, ids[(m + 1) % 3], ids[(m + 2) % 3], target);
    const double d2 = target.point.squaredNorm();
    if (!found) {
      best = d2;
      found = true;
    } else if (d2 < best) {
      best = d2;
      out = candidate;
    }
  }
}

// Tetrahedron w[0..3]. Returns true when the origin is strictly inside.
inline bool s3d(const std::array<Eigen::Vector3d, 4>& w, Sub& out) {
  auto det = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return dot3(a, cross3(b, c));
  };
  // c[m] = signed volume of the tetrahedron with w[m] replaced by the origin;
  // their sum is the tetrahedron's signed volume det[w1-w0, w2-w0, w3-w0].
  const std::array<double, 4> c = {det(w[1], w[2], w[3]), -det(w[0], w[2], w[3]), det(w[0], w[1], w[3]),
                                   -det(w[0], w[1], w[2])};
  const double mu = c[0] + c[1] + c[2] + c[3];
  std::array<bool, 4> outside;
  for (int m = 0; m < 4; ++m) outside[m] = !same_sign(mu, c[m]);
  if (!outside[0] && !outside[1] && !outside[2] && !outside[3]) {
    out.size = 4;
    out.index = {0, 1, 2, 3};
    for (int m = 0; m < 4; ++m) out.lambda[m] = c[m] / mu;
    out.point.setZero();
    return true;
  }
  // Faces opposite a vertex with a wrong-signed coordinate (all four for a
  // flat tetrahedron), and always the three faces through w[3], the support
  // point just added, keeping the closest answer. Why the extra faces: on a
  // nearly flat tetrahedron (support points clustering on a curved surface,
  // both rims of a cylinder-cone pair) the signs are rounding, a needed face
  // through w[3] could go unexamined, v would not decrease and the loop would
  // stop with the gap still large. Every candidate is a point of the simplex,
  // so the closest of a larger set is never worse.
  //
  // A face through w[3] whose coordinate has the sign of the total beyond
  // any rounding (and the total's sign too) is skipped: then the origin is
  // certainly on the tetrahedron's side of that face's plane, and the
  // closest point lies on a face whose plane separates (exact arithmetic,
  // Johnson's argument), so rounding cannot make that face the answer.
  // Bound on the rounding of det(a, b, c) = a . (b x c): below
  // 8 eps |a| |b| |c| (two roundings in each product of the cross product,
  // one in its difference, three in the dot); 32 eps is used, plus 1e-290
  // for products that underflow (points below ~1e-100: their subnormal
  // rounding is absolute, and then nothing is skipped). An overflowing or
  // NaN bound skips nothing either (the comparison fails).
  std::array<double, 4> nn;
  for (int m = 0; m < 4; ++m) nn[m] = dot3(w[m], w[m]);
  constexpr double kDetError = 32.0 * std::numeric_limits<double>::epsilon();
  constexpr double kDetFloor = 1e-290;
  std::array<double, 4> bound;
  static constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (int m = 0; m < 4; ++m)
    bound[m] = kDetError * std::sqrt(nn[kOthers[m][0]] * nn[kOthers[m][1]] * nn[kOthers[m][2]]) + kDetFloor;
  const bool total_certain = std::abs(mu) > bound[0] + bound[1] + bound[2] + bound[3];
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  double best = std::numeric_limits<double>::infinity();
  bool found = false;
  for (int m = 0; m < 4; ++m) {
    if (!outside[m] && (m == 3 || (total_certain && std::abs(c[m]) > bound[m]))) continue;
    Sub candidate;  // as in s2d: the first straight into `out`
    Sub& target = found ? candidate : out;
    s2d(w, kFace[m][0], kFace[m][1], kFace[m][2], target, 3);
    const double d2 = dot3(target.point, target.point);
    if (!found) {
      best = d2;
      found = true;
    } else if (d2 < best) {
      best = d2;
      out = candidate;
    }
  }
  return false;
}

// The sub-simplex of the first `count` points of `w` (1..4, the last one the
// support point just added) nearest the origin, its weights and its point
// nearest the origin; returns true when the origin is inside a tetrahedron.
inline bool signed_volumes(const std::array<Eigen::Vector3d, 4>& w, int count, Sub& sub) {
  switch (count) {
    case 1:
      vertex(w, 0, sub);
      return false;
    case 2:
      s1d(w, 0, 1, sub);
      return false;
    case 3:
      s2d(w, 0, 1, 2, sub, 2);
      return false;
    default:
      return s3d(w, sub);
  }
}

// Rewrites `s` as the sub-simplex `sub` of its points (indices distinct, in
// any order), with sub's weights. Increasing indices (index[i] >= i, the
// common case) move down in place: slot i is written after every source
// below it has been read; any other order goes through copies.
inline void adopt(GjkSimplex& s, const Sub& sub) {
  bool increasing = true;
  for (int i = 1; i < sub.size; ++i) increasing = increasing && sub.index[i - 1] < sub.index[i];
  if (increasing) {
    for (int i = 0; i < sub.size; ++i) {
      const int k = sub.index[i];
      if (k != i) {
        s.w[i] = s.w[k];
        s.a[i] = s.a[k];
        s.b[i] = s.b[k];
      }
      s.lambda[i] = sub.lambda[i];
    }
    s.size = sub.size;
    return;
  }
  std::array<Eigen::Vector3d, 4> w, a, b;
  for (int i = 0; i < sub.size; ++i) {
    w[i] = s.w[sub.index[i]];
    a[i] = s.a[sub.index[i]];
    b[i] = s.b[sub.index[i]];
  }
  for (int i = 0; i < sub.size; ++i) {
    s.w[i] = w[i];
    s.a[i] = a[i];
    s.b[i] = b[i];
    s.lambda[i] = sub.lambda[i];
  }
  s.size = sub.size;
}

inline Eigen::Vector3d weighted(const std::array<Eigen::Vector3d, 4>& p, const GjkSimplex& s) {
  Eigen::Vector3d x = s.lambda[0] * p[0];
  for (int i = 1; i < s.size; ++i) x += s.lambda[i] * p[i];
  return x;
}

// |v| from its squared length vv: sqrt(vv), unless vv is small enough to
// have lost bits to gradual underflow (|v| below about 1e-146), then Eigen's
// scaled stableNorm (v / sqrt(vv) is not unit there).
inline double length_of(const Eigen::Vector3d& v, double vv) {
  constexpr double kFullPrecision = std::numeric_limits<double>::min() / std::numeric_limits<double>::epsilon();
  return vv >= kFullPrecision ? std::sqrt(vv) : v.stableNorm();
}

// The first support point, against `initial_axis` (or +x when that is zero
// or not finite): a simplex of one point. False (status degenerate, every
// output zero) when it is not finite (NaN/inf parameters or poses).
template <class A, class B>
bool start(const A& a, const B& b, const Eigen::Vector3d& initial_axis, GjkResult& r) {
  Eigen::Vector3d axis = initial_axis;
  if (!axis.allFinite() || !(axis.squaredNorm() > 0.0)) axis = Eigen::Vector3d::UnitX();
  GjkSimplex& s = r.simplex;
  s.a[0] = a.support(-axis);
  s.b[0] = b.support(axis);
  r.support_calls = 1;
  s.w[0] = s.a[0] - s.b[0];
  if (!s.w[0].allFinite()) {
    r.status = GjkStatus::degenerate;
    s.size = 0;
    return false;
  }
  s.size = 1;
  s.lambda[0] = 1.0;
  return true;
}

// The outputs from the final simplex, v = its point nearest the origin
// (|v|^2 = vv), and the best lower bounds (clamped at 0, and signed).
inline void finish(const Eigen::Vector3d& v, double vv, double lower, double signed_lower, GjkResult& r) {
  const GjkSimplex& s = r.simplex;
  r.point_a = weighted(s.a, s);
  r.point_b = weighted(s.b, s);
  r.v = v;
  r.signed_lower_bound = std::min(signed_lower, length_of(v, vv));
  if (r.intersecting) {
    r.distance = 0.0;
    r.lower_bound = 0.0;
    r.error_bound = 0.0;
  } else {
    r.distance = length_of(v, vv);
    r.lower_bound = std::min(std::max(lower, 0.0), r.distance);
    r.error_bound = r.distance - r.lower_bound;
  }
}

template <bool kBoolean, class A, class B>
GjkResult run(const A& a, const B& b, const Eigen::Vector3d& initial_axis, double scale, double margin,
              const GjkSettings& settings) {
  GjkResult r;
  const double abs_tolerance = settings.absolute_tolerance * scale;
  const double zero = 16.0 * std::numeric_limits<double>::epsilon() * scale;

  GjkSimplex& s = r.simplex;
  if (!start(a, b, initial_axis, r)) return r;
  if (kBoolean) {
    // The start axis is a search axis too: w[0] = s(-axis), so axis . w[0]
    // > margin |axis| separates as the loop's own test does on v (an axis
    // that is zero, not finite or whose square is not is left to the loop;
    // start searched +x for the first two). Witnesses and distance are then
    // w[0]'s, v the separating axis (the cache's warm start).
    const double aa = dot3(initial_axis, initial_axis);
    if (aa > 0.0 && aa < std::numeric_limits<double>::infinity() &&
        dot3(initial_axis, s.w[0]) > margin * length_of(initial_axis, aa)) {
      finish(s.w[0], dot3(s.w[0], s.w[0]), 0.0, -std::numeric_limits<double>::infinity(), r);
      r.v = initial_axis;
      return r;
    }
  }
  Eigen::Vector3d v = s.w[0];
  double vv = dot3(v, v);
  double lower = 0.0;
  double signed_lower = -std::numeric_limits<double>::infinity();
  // Steps without a decrease beyond rounding (see below), and the best
  // simplex from before them.
  constexpr int kMaxSideways = 4;
  int sideways = 0;
  GjkSimplex best_simplex;
  Eigen::Vector3d best_v = v;
  double best_vv = vv;
#if HEDRA_ASSERTS_ENABLED
  // The smallest |v|^2 held so far: what the loop guarantees is that it
  // ends there (sideways steps only rise above it, and are undone).
  double least_vv = vv;
#endif

  for (;;) {
    if (vv <= zero * zero || (kBoolean && vv <= margin * margin)) {
      r.intersecting = true;
      break;
    }
    if (r.iterations >= settings.max_iterations) {
      r.status = GjkStatus::max_iterations;
      break;
    }
    HEDRA_ASSERT(s.size >= 1 && s.size <= 3);  // a tetrahedron has ended the loop
    ++r.iterations;
    const Eigen::Vector3d pa = a.support(-v);
    const Eigen::Vector3d pb = b.support(v);
    ++r.support_calls;
    const Eigen::Vector3d w = pa - pb;
    if (!w.allFinite()) {
      r.status = GjkStatus::degenerate;
      break;
    }
    const double vn = length_of(v, vv);
    const double vw = dot3(v, w);
    lower = std::max(lower, vw / vn);
    signed_lower = std::max(signed_lower, vw / vn);
    if (kBoolean && vw > margin * vn) break;  // a separating axis: done
    // The certified gap: upper bound |v| minus the best lower bound.
    const double tolerance = std::max(settings.relative_tolerance * vn, abs_tolerance);
    if (vn - lower <= tolerance) {
      // Converged. Without a positive lower bound (no axis separates the
      // cores, beyond the margin for the boolean query) the origin may be
      // inside: |v| <= tolerance is the cores touching within tolerance, not
      // a separation.
      if (lower <= (kBoolean ? margin : 0.0)) r.intersecting = true;
      break;
    }
    bool duplicate = false;
    for (int i = 0; i < s.size; ++i) duplicate = duplicate || s.w[i] == w;
    if (duplicate) {
      // Why: w is already a vertex, so the sub-algorithm would return the
      // same v; the gap above the tolerance is rounding in v or w.
      r.status = GjkStatus::stalled;
      break;
    }

    // w goes into the free slot s.size (a simplex of 4 has ended the loop:
    // inside, or reduced to at most 3); s itself is rewritten only when the
    // step is accepted, so a rejected step leaves the previous simplex, its
    // weights and v as they were.
    s.w[s.size] = w;
    s.a[s.size] = pa;
    s.b[s.size] = pb;
    Sub sub;
    if (signed_volumes(s.w, s.size + 1, sub)) {
      adopt(s, sub);  // v stays the last axis searched (r.v, the cache's warm start)
      r.intersecting = true;
      break;
    }
    const double vv_next = dot3(sub.point, sub.point);
    // Strict decrease, written so that NaN fails it: keep the previous,
    // better simplex and stop (the gap was above the tolerance).
    // Except for a few steps sideways: a step whose true decrease is below
    // the rounding of |v|^2 (a few eps) while the gap is still large (a
    // triangle across a wide flat face, tilted from it by rounding: see
    // docs/design.md, "GJK's sideways steps"). The best simplex so far is
    // kept aside and restored if the sideways steps end without going
    // below it.
    if (!(vv_next < vv)) {
      constexpr double kSidewaysRounding = 16.0 * std::numeric_limits<double>::epsilon();
      if (vv_next <= vv * (1.0 + kSidewaysRounding) && sideways < kMaxSideways) {
        if (sideways == 0) {
          best_simplex = s;
          best_v = v;
          best_vv = vv;
        }
        ++sideways;
        HEDRA_ASSERT(sideways <= kMaxSideways && best_vv <= vv_next);
        adopt(s, sub);
        v = sub.point;
        vv = vv_next;
        continue;
      }
      r.status = GjkStatus::stalled;
      break;
    }
    if (sideways > 0 && vv_next < best_vv) sideways = 0;  // below the best: progress again
    adopt(s, sub);
    v = sub.point;
    vv = vv_next;
#if HEDRA_ASSERTS_ENABLED
    least_vv = std::min(least_vv, vv);
#endif
  }
  // Sideways steps that found nothing better: back to the best simplex.
  if (sideways > 0 && !r.intersecting && best_vv < vv) {
    s = best_simplex;
    v = best_v;
    vv = best_vv;
  }

  HEDRA_ASSERT(r.intersecting || !(vv > least_vv));
  finish(v, vv, lower, signed_lower, r);
  return r;
}

}  // namespace gjk_detail

// Distance between two support types given in a common frame: intersecting
// flag, |v|, both witness points, a certified error bound. `scale` is the
// shapes' size (for the absolute tolerance and the zero threshold).
template <class A, class B>
GjkResult gjk_distance(const A& a, const B& b, const Eigen::Vector3d& initial_axis, double scale,
                       const GjkSettings& settings = {}) {
  return gjk_detail::run<false>(a, b, initial_axis, scale, 0.0, settings);
}

// Whether dist(A, B) <= margin (margin >= 0: the sum of the radii added
// around the cores). Stops at the first separating axis or as soon as |v|
// proves the overlap; distance and witnesses in the result are then only the
// state reached, not converged values.
template <class A, class B>
GjkResult gjk_intersect(const A& a, const B& b, const Eigen::Vector3d& initial_axis, double scale, double margin,
                        const GjkSettings& settings = {}) {
  return gjk_detail::run<true>(a, b, initial_axis, scale, margin, settings);
}

}  // namespace hedra::collision
