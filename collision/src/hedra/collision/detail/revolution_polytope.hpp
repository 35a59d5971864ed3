// Penetration of a polytope core (box, hull, segment, point) and a curved
// core of revolution (cylinder, cone), certified, by branch and bound over
// one angle.
//
// A small peg deep inside a large cylinder or cone, near its axis, sees a
// ring of nearly equal depths (the hole's radius plus a small variation
// from the peg), which EPA's inscribed polytope resolves only with about
// size / peg faces. With k the axis (oriented so that the revolution core
// contributes f(k . n)) and q_j the polytope's vertices placed in D = A - B
// relative to the axis' centre, h_D(n) = f(k . n) + max_j q_j . n, f the
// profile max_i (s_i c + rho_i sqrt(1 - c^2)). Writing n = cos(theta) k +
// sin(theta) u(phi), theta in [0, pi]: h_D is the support function, in the
// direction (sin theta, cos theta), of the 2D points (rho_i + q_j . u(phi),
// s_i + q_j . k), so for each azimuth phi the minimum over theta is exact
// (the right convex chain of those points: its edges, both poles, and a
// vertex's own minimum). Over an interval of phi each point's first
// coordinate is bounded below by its sinusoid's minimum there; h_D grows
// with it (sin theta >= 0), so the chain of the lowered points bounds the
// minimum from below: a certified lower bound, exact where a vertex's
// sinusoid has its minimum, first order elsewhere. Upper bounds: h_D at the
// chain's minimiser for the interval's middle, and the caller's hints.
// Depth first over phi with a fixed stack and a cap on intervals (then
// max_iterations with the bracket so far); polytopes of more than
// kRevolutionPolytopeMaxVertices vertices are not handled (false). Minima
// where a face of the peg meets the wall are kinks in phi (100 to 500
// intervals); where an edge of the peg meets a rim circle the minimum is
// smooth and the first-order bound needs intervals as 1/sqrt(tolerance)
// (18 000 seen, a few ms). Where it runs: docs/design.md, "Why
// penetration() tries what it tries"; figures: docs/accuracy.md.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <hedra/collision/detail/epa.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/detail/tilted_revolution.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>

namespace hedra::collision {

inline constexpr int kRevolutionPolytopeMaxVertices = 128;

struct RevolutionPolytopeSettings {
  int max_intervals = 65536;  // intervals of phi bounded, the cap reported as max_iterations
};

namespace revolution_polytope_detail {

constexpr int kMaxPoints = 2 * kRevolutionPolytopeMaxVertices;

// The polytope's vertices in its core frame (false: not a polytope core, or
// too many vertices).
struct Vertices {
  std::array<Eigen::Vector3d, kRevolutionPolytopeMaxVertices> p;
  int n = 0;
};

template <class Core>
bool vertices_of(const Core&, Vertices&) {
  return false;
}
inline bool vertices_of(const PointCore&, Vertices& v) {
  v.n = 1;
  v.p[0].setZero();
  return true;
}
inline bool vertices_of(const SegmentCore& s, Vertices& v) {
  v.n = 2;
  v.p[0] = Eigen::Vector3d(0.0, 0.0, -s.half_length);
  v.p[1] = Eigen::Vector3d(0.0, 0.0, s.half_length);
  return true;
}
inline bool vertices_of(const BoxCore& s, Vertices& v) {
  v.n = 8;
  for (int i = 0; i < 8; ++i)
    v.p[i] = Eigen::Vector3d(i & 1 ? s.half_extents.x() : -s.half_extents.x(),
                             i & 2 ? s.half_extents.y() : -s.half_extents.y(),
                             i & 4 ? s.half_extents.z() : -s.half_extents.z());
  return true;
}
inline bool vertices_of(const PolyhedronCore& s, Vertices& v) {
  if (s.poly == nullptr || s.poly->vertex_count() == 0 ||
      s.poly->vertex_count() > static_cast<std::size_t>(kRevolutionPolytopeMaxVertices))
    return false;
  v.n = static_cast<int>(s.poly->vertex_count());
  for (int i = 0; i < v.n; ++i) v.p[i] = s.poly->vertex(static_cast<hull::Index>(i));
  return true;
}

// The pair: h_D(n) = profile(k . n) + max_j q_j . n, in the frame (e1, e2, k);
// point m = (branch m / n_q, vertex m % n_q) of the 2D sets, sorted by z.
struct Problem {
  tilted_detail::Profile profile;
  Eigen::Vector3d k, e1, e2;
  std::array<Eigen::Vector3d, kRevolutionPolytopeMaxVertices> q;
  std::array<double, kRevolutionPolytopeMaxVertices> qx{}, qy{}, psi{}, qr{};  // q . e1, q . e2, argmin, |q_perp|
  int nq = 0;
  std::array<double, kMaxPoints> z{};             // s_i + q_j . k
  std::array<std::uint16_t, kMaxPoints> order{};  // points by increasing z
  int points = 0;
  double rounding = 0.0;
  bool revolution_is_a = true;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  const tilted_detail::Branch& branch(int m) const { return m < nq ? profile.lo : profile.hi; }
  int vertex(int m) const { return m < nq ? m : m - nq; }
  Eigen::Vector3d direction(double phi, const Eigen::Vector2d& d) const {
    const Eigen::Vector3d n = d.y() * k + d.x() * (std::cos(phi) * e1 + std::sin(phi) * e2);
    return n / n.norm();
  }
  // h_D(n) for any unit n, from the profile and the vertices.
  double h(const Eigen::Vector3d& n) const {
    double best = -std::numeric_limits<double>::infinity();
    for (int j = 0; j < nq; ++j) best = std::max(best, q[j].dot(n));
    return profile.value(k, n) + best;
  }
};

// The minimum over theta in [0, pi] of max_m (A_m sin theta + z_m cos theta):
// its value, direction (sin theta, cos theta) and the chain points (with the
// weight of the second) whose combination is nearest to the origin.
struct ChainMinimum {
  double value = std::numeric_limits<double>::infinity();
  Eigen::Vector2d direction = Eigen::Vector2d(0.0, 1.0);
  int p0 = 0, p1 = 0;
  double weight = 0.0;
};

inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// The right chain (largest A) of the points in z order, Andrew's monotone
// chain, then its candidates: both poles, each edge's normal, each
// vertex's own minimum (-|P|, where the origin is outside) within its arc.
inline ChainMinimum chain_minimum(const Problem& pr, const double* A) {
  std::array<std::uint16_t, kMaxPoints> chain;
  int top = 0;
  const auto point = [&](int m) { return Eigen::Vector2d(A[m], pr.z[m]); };
  for (int i = 0; i < pr.points; ++i) {
    const int m = pr.order[i];
    const Eigen::Vector2d p = point(m);
    while (top >= 2 && cross2(point(chain[top - 1]) - point(chain[top - 2]), p - point(chain[top - 2])) <= 0.0) --top;
    chain[top++] = static_cast<std::uint16_t>(m);
  }
  HEDRA_ASSERT(top >= 1 && top <= pr.points);
  ChainMinimum best;
  const auto consider = [&](double value, const Eigen::Vector2d& d, int p0, int p1, double w) {
    if (value < best.value) best = {value, d, p0, p1, w};
  };
  consider(-pr.z[pr.order[0]], Eigen::Vector2d(0.0, -1.0), pr.order[0], pr.order[0], 0.0);
  consider(pr.z[pr.order[pr.points - 1]], Eigen::Vector2d(0.0, 1.0), pr.order[pr.points - 1], pr.order[pr.points - 1],
           0.0);
  Eigen::Vector2d previous(0.0, -1.0);  // the normal before chain vertex i
  for (int i = 0; i < top; ++i) {
    const Eigen::Vector2d p = point(chain[i]);
    Eigen::Vector2d next(0.0, 1.0);
    if (i + 1 < top) {
      const Eigen::Vector2d e = point(chain[i + 1]) - p;
      const double len = e.norm();
      if (len > 0.0) {
        next = Eigen::Vector2d(e.y(), -e.x()) / len;
        const double w = std::clamp(-p.dot(e) / (len * len), 0.0, 1.0);
        consider(next.dot(p), next, chain[i], chain[i + 1], w);
      } else {
        next = previous;
      }
    }
    const double pn = p.norm();
    if (pn > 0.0) {
      const Eigen::Vector2d w = -p / pn;
      if (w.x() >= 0.0 && cross2(previous, w) >= 0.0 && cross2(w, next) >= 0.0)
        consider(-pn, w, chain[i], chain[i], 0.0);
    }
    previous = next;
  }
  return best;
}

// Phase 1: the pair in the frame of the axis; false when it is not a
// curved core of revolution and a polytope core (of at most
// kRevolutionPolytopeMaxVertices vertices).
template <class Revolution, class Polytope>
bool make_problem(const Revolution& revolution, const Polytope& polytope, const RelativePose& relative,
                  bool revolution_is_a, double scale, Problem& pr) {
  pr.profile = tilted_detail::profile_of(revolution);
  if (!pr.profile.valid || !pr.profile.curved) return false;
  if (!(std::isfinite(scale) && scale > 0.0)) return false;
  Vertices v;
  if (!vertices_of(polytope, v)) return false;
  const Eigen::Matrix3d& R = relative.rotation;
  pr.t = relative.translation;
  pr.revolution_is_a = revolution_is_a;
  // A's profile is f_A(a . n); B's is f_B(b . (-n)) = f_B((-b) . n).
  pr.k = revolution_is_a ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(-R.col(2));
  pr.k.normalize();
  pr.e1 = pr.k.unitOrthogonal();
  pr.e2 = pr.k.cross(pr.e1);
  pr.nq = v.n;
  for (int j = 0; j < v.n; ++j) {
    pr.q[j] = revolution_is_a ? Eigen::Vector3d(-(R * v.p[j] + pr.t)) : Eigen::Vector3d(v.p[j] - pr.t);
    pr.qx[j] = pr.q[j].dot(pr.e1);
    pr.qy[j] = pr.q[j].dot(pr.e2);
    pr.qr[j] = accurate_hypot(pr.qx[j], pr.qy[j]);
    pr.psi[j] = std::atan2(-pr.qy[j], -pr.qx[j]);  // where qx cos(phi) + qy sin(phi) is least
    if (!std::isfinite(pr.qr[j])) return false;
  }
  pr.points = 2 * v.n;
  HEDRA_ASSERT(pr.points >= 2 && pr.points <= kMaxPoints);
  for (int m = 0; m < pr.points; ++m) {
    pr.z[m] = pr.branch(m).slope + pr.q[pr.vertex(m)].dot(pr.k);
    pr.order[m] = static_cast<std::uint16_t>(m);
  }
  std::sort(pr.order.begin(), pr.order.begin() + pr.points, [&](int x, int y) { return pr.z[x] < pr.z[y]; });
  const double eps = std::numeric_limits<double>::epsilon();
  pr.rounding = 64.0 * eps * (2.0 * scale + pr.t.norm());
  return true;
}

// A lower bound of h_D over the azimuths [phi0, phi1] (width below pi):
// each vertex's q . u(phi) at its least over the interval (an end, or
// -|q_perp| where its minimum lies inside).
inline double interval_bound(const Problem& pr, double phi0, double phi1) {
  std::array<double, kMaxPoints> A;
  const double c0 = std::cos(phi0), s0 = std::sin(phi0), c1 = std::cos(phi1), s1 = std::sin(phi1);
  constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
  for (int j = 0; j < pr.nq; ++j) {
    double low = std::min(pr.qx[j] * c0 + pr.qy[j] * s0, pr.qx[j] * c1 + pr.qy[j] * s1);
    const double psi = pr.psi[j];
    if ((psi >= phi0 && psi <= phi1) || (psi - kTwoPi >= phi0 && psi - kTwoPi <= phi1) ||
        (psi + kTwoPi >= phi0 && psi + kTwoPi <= phi1))
      low = -pr.qr[j];
    A[j] = pr.profile.lo.radius + low;
    A[j + pr.nq] = pr.profile.hi.radius + low;
  }
  return chain_minimum(pr, A.data()).value - pr.rounding;
}

// The exact chain at one azimuth.
inline ChainMinimum chain_at(const Problem& pr, double phi) {
  std::array<double, kMaxPoints> A;
  const double c = std::cos(phi), s = std::sin(phi);
  for (int j = 0; j < pr.nq; ++j) {
    const double along = pr.qx[j] * c + pr.qy[j] * s;
    A[j] = pr.profile.lo.radius + along;
    A[j + pr.nq] = pr.profile.hi.radius + along;
  }
  return chain_minimum(pr, A.data());
}

// The best upper bound so far (a support value h_D(n)) and its direction.
struct Search {
  const Problem& pr;
  const EpaSettings& settings;
  double scale;
  double upper = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_n = Eigen::Vector3d::UnitZ();

  Search(const Problem& problem, const EpaSettings& s, double sc) : pr(problem), settings(s), scale(sc) {}

  void offer(const Eigen::Vector3d& n) {
    if (!n.allFinite()) return;
    const double v = pr.h(n);
    if (v < upper) {
      upper = v;
      best_n = n;
    }
  }
  void offer_azimuth(double phi) { offer(pr.direction(phi, chain_at(pr, phi).direction)); }
  double tolerance() const {
    return std::max(settings.relative_tolerance * std::abs(upper), settings.absolute_tolerance * scale);
  }
};

struct Bracket {
  double certified = std::numeric_limits<double>::infinity();  // the smallest bound of the intervals dropped
  int intervals = 0;
  bool capped = false;
};

// Phase 2: depth first over intervals of phi, from kStart intervals of
// [-pi, pi]; an interval is dropped once its bound is within the
// tolerance of the best upper bound, or at the cap (its bound is then what
// is certified for it).
inline Bracket branch_and_bound(Search& search, int max_intervals) {
  struct Interval {
    double phi0, phi1, bound;
  };
  constexpr int kStart = 32, kMaxDepth = 64;
  constexpr double kPi = 3.14159265358979323846;
  std::array<Interval, kStart + 2 * kMaxDepth> stack;
  int top = 0;
  Bracket out;
  const auto make = [&](double phi0, double phi1, double parent) {
    ++out.intervals;
    search.offer_azimuth(0.5 * (phi0 + phi1));
    return Interval{phi0, phi1, std::max(parent, interval_bound(search.pr, phi0, phi1))};
  };
  for (int i = 0; i < kStart; ++i)
    stack[top++] = make(-kPi + 2.0 * kPi * i / kStart, -kPi + 2.0 * kPi * (i + 1) / kStart,
                        -std::numeric_limits<double>::infinity());
  const double eps = std::numeric_limits<double>::epsilon();
  while (top > 0) {
    const Interval iv = stack[--top];
    if (!(iv.bound < search.upper - search.tolerance())) {  // NaN bounds are kept below
      if (!std::isnan(iv.bound)) {
        out.certified = std::min(out.certified, iv.bound);
        continue;
      }
    }
    if (out.intervals + 2 > max_intervals || top + 2 > static_cast<int>(stack.size()) ||
        !(iv.phi1 - iv.phi0 > 8.0 * eps) || std::isnan(iv.bound)) {
      out.capped = out.capped || out.intervals + 2 > max_intervals || std::isnan(iv.bound);
      out.certified =
          std::min(out.certified, std::isnan(iv.bound) ? -std::numeric_limits<double>::infinity() : iv.bound);
      continue;
    }
    const double mid = 0.5 * (iv.phi0 + iv.phi1);
    const Interval lo = make(iv.phi0, mid, iv.bound), hi = make(mid, iv.phi1, iv.bound);
    // The lower bound is popped first.
    if (lo.bound < hi.bound) {
      stack[top++] = hi;
      stack[top++] = lo;
    } else {
      stack[top++] = lo;
      stack[top++] = hi;
    }
  }
  return out;
}

// Phase 3, witnesses: the chain's nearest combination at the answer's
// azimuth, split into the revolution core's points (s_i k + rho_i u) and
// the polytope's vertices.
inline void set_witnesses(const Search& search, EpaResult& r) {
  const Problem& pr = search.pr;
  const Eigen::Vector3d& n = search.best_n;
  const double x = n.dot(pr.e1), y = n.dot(pr.e2);
  const double phi = (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
  const ChainMinimum c = chain_at(pr, phi);
  const Eigen::Vector3d u = std::cos(phi) * pr.e1 + std::sin(phi) * pr.e2;
  const auto revolution_point = [&](int m) {
    const tilted_detail::Branch& b = pr.branch(m);
    return Eigen::Vector3d(b.slope * pr.k + b.radius * u);
  };
  const double w0 = 1.0 - c.weight, w1 = c.weight;
  const Eigen::Vector3d rev = w0 * revolution_point(c.p0) + w1 * revolution_point(c.p1);
  const Eigen::Vector3d q = w0 * pr.q[pr.vertex(c.p0)] + w1 * pr.q[pr.vertex(c.p1)];
  if (pr.revolution_is_a) {
    r.point_a = rev;
    r.point_b = -q;
  } else {
    r.point_a = q + pr.t;
    r.point_b = pr.t - rev;
  }
}

}  // namespace revolution_polytope_detail

// The signed depth (min over unit n of h_D(n), > 0 when the cores overlap)
// of a curved core of revolution (cylinder, cone) and a polytope core (box,
// hull of at most kRevolutionPolytopeMaxVertices vertices, segment,
// point), either order (B placed by `relative` in A's frame), certified
// within max(relative_tolerance depth, absolute_tolerance scale) of
// EpaSettings; false when the pair is not of that kind. `hints`: directions
// whose support values start the upper bound. Conventions of
// epa_penetration.
template <class CA, class CB>
bool revolution_polytope_penetration(const CA& core_a, const CB& core_b, const RelativePose& relative, double scale,
                                     const Eigen::Vector3d* hints, int hint_count, const EpaSettings& settings,
                                     EpaResult& out, const RevolutionPolytopeSettings& options = {}) {
  using namespace revolution_polytope_detail;
  Problem pr;
  if (!make_problem(core_a, core_b, relative, true, scale, pr) &&
      !make_problem(core_b, core_a, relative, false, scale, pr))
    return false;
  Search search(pr, settings, scale);
  for (int i = 0; i < hint_count; ++i) {
    const double len = hints[i].norm();
    if (len > 0.0 && std::isfinite(len)) search.offer(hints[i] / len);
  }
  search.offer(pr.k);
  search.offer(-pr.k);
  const Bracket bracket = branch_and_bound(search, options.max_intervals);
  if (!std::isfinite(search.upper)) return false;
  const double certified = std::isfinite(bracket.certified) ? bracket.certified : search.upper;
  EpaResult r;
  r.depth = search.upper;
  r.normal = search.best_n;
  set_witnesses(search, r);
  r.error_bound = std::max(search.upper - std::min(certified, search.upper), 0.0);
  r.iterations = bracket.intervals;
  r.dimension = 3;
  r.status = bracket.capped ? EpaStatus::max_iterations : EpaStatus::ok;
  if (!bracket.capped && r.error_bound > search.tolerance()) r.status = EpaStatus::stalled;
  out = r;
  return true;
}

}  // namespace hedra::collision
