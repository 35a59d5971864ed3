// Penetration of two cores of revolution (segment, cylinder, cone) at any
// tilt, certified, by branch and bound over the directions.
//
// Nearly coaxial cylinders and cones defeat EPA (the depth is almost the
// same over a circle of directions) and the exact reduction of
// revolution.hpp holds only for parallel axes. Each core's support function
// depends on one variable, the cosine to its axis; in disc coordinates P of
// the unit sphere the kinks of both profiles are straight lines, and over a
// square of P cut by those lines a chord bound of each concave branch leaves
// a convex function minimised in closed form: a certified lower bound,
// exact on the kink lines. Upper bounds are support values h_D(n) at the
// pieces' minimisers, the poles and the caller's hints. Depth first over a
// quadtree of [-1, 1]^2 with a fixed stack and a cap on squares (then
// max_iterations with the bracket so far). The poles, where disc coordinates
// cannot resolve directions, get their own cap bounds. Witnesses: points of
// the support sets (point, segment, disc) by alternating projections.
// Derivations: docs/design.md, "Tilted cores of revolution".
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <hedra/collision/detail/epa.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <limits>

namespace hedra::collision {

namespace tilted_detail {

// One branch g(c) = slope c + radius sqrt(1 - c^2), concave on [-1, 1].
// sqrt(1 - c^2) as sqrt((1 - c)(1 + c)): no cancellation near the poles
// (1 - c * c there has an error of a quarter of its value).
inline double sine_of(double c) { return std::sqrt(std::max(0.0, (1.0 - c) * (1.0 + c))); }

struct Branch {
  double slope = 0.0;
  double radius = 0.0;
  double value(double c) const { return slope * c + radius * sine_of(c); }
  // With the sine given (from the direction itself, exact near the poles).
  double value(double c, double sine) const { return slope * c + radius * sine; }
  // The slope of the chord over [c0, c1], without cancellation:
  // (sqrt(1 - c1^2) - sqrt(1 - c0^2)) / (c1 - c0) = -(c0 + c1) / (sum of roots).
  double chord_slope(double c0, double c1) const {
    const double roots = sine_of(c0) + sine_of(c1);
    if (!(roots > 0.0)) return slope;  // c0 = c1 = +-1: a single point
    return slope - radius * (c0 + c1) / roots;
  }
};

// The profile f(c) = max(lo(c), hi(c)); lo is active for c <= kink.
struct Profile {
  bool valid = false;
  bool curved = false;
  Branch lo, hi;
  double kink = 0.0;
  double half_length = 0.0, radius = 0.0;
  int kind = 0;  // 1 segment, 2 cylinder, 3 cone
  // h(n) for the axis k: the sine from |k x n| (a direction 1e-9 rad off the
  // axis has c = 1 exactly in double, and a radius term of 1e-9 r).
  double value(const Eigen::Vector3d& k, const Eigen::Vector3d& n) const {
    const double c = std::clamp(k.dot(n), -1.0, 1.0);
    const double sine = std::min(k.cross(n).norm(), 1.0);
    return std::max(lo.value(c, sine), hi.value(c, sine));
  }
};

template <class Core>
Profile profile_of(const Core&) {
  return {};
}
inline Profile profile_of(const SegmentCore& s) {
  Profile p;
  p.valid = true;
  p.lo = {-s.half_length, 0.0};
  p.hi = {s.half_length, 0.0};
  p.half_length = s.half_length;
  p.kind = 1;
  return p;
}
inline Profile profile_of(const CylinderCore& s) {
  Profile p;
  p.valid = p.curved = true;
  p.lo = {-s.half_length, s.radius};
  p.hi = {s.half_length, s.radius};
  p.half_length = s.half_length;
  p.radius = s.radius;
  p.kind = 2;
  return p;
}
inline Profile profile_of(const ConeCore& s) {
  Profile p;
  p.valid = p.curved = true;
  p.lo = {-s.half_length, s.radius};
  p.hi = {s.half_length, 0.0};
  const double l = std::hypot(s.radius, 2.0 * s.half_length);
  p.kink = l > 0.0 ? s.radius / l : 0.0;
  p.half_length = s.half_length;
  p.radius = s.radius;
  p.kind = 3;
  return p;
}

// A convex polygon of the (X, Y) plane, fixed capacity (a square cut by two
// lines has at most 6 vertices).
struct Polygon {
  std::array<Eigen::Vector2d, 8> p;
  int n = 0;
};

// The part of `in` where side * (normal . P - offset) <= 0.
inline Polygon clip(const Polygon& in, const Eigen::Vector2d& normal, double offset, double side) {
  Polygon out;
  if (in.n == 0) return out;
  // Each vertex's signed distance once; a polygon wholly on one side is
  // kept or dropped whole (what the walk below gives it).
  std::array<double, 8> dist;
  bool any_kept = false, any_cut = false;
  for (int i = 0; i < in.n; ++i) {
    dist[i] = side * (normal.dot(in.p[i]) - offset);
    any_kept = any_kept || dist[i] <= 0.0;
    any_cut = any_cut || !(dist[i] <= 0.0);
  }
  if (!any_kept) return out;
  if (!any_cut) {  // the points in order, no copy of the unused slots
    if (in.n < 3) return out;
    out.n = in.n;
    for (int i = 0; i < in.n; ++i) out.p[i] = in.p[i];
    return out;
  }
  for (int i = 0; i < in.n; ++i) {
    const int j = i + 1 < in.n ? i + 1 : 0;
    const Eigen::Vector2d& p = in.p[i];
    const Eigen::Vector2d& q = in.p[j];
    const double dp = dist[i], dq = dist[j];
    if (dp <= 0.0) out.p[out.n++] = p;
    if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) {
      const double w = dp / (dp - dq);
      out.p[out.n++] = p + w * (q - p);
    }
  }
  if (out.n < 3) out.n = 0;
  return out;
}

// The pair in the disc coordinates described at the top.
struct Problem {
  Profile fa, fb;
  Eigen::Vector3d a, e2, m, b, t;
  double c = 1.0, s = 0.0;      // b . n = c X + s Y
  double t1 = 0.0, t2 = 0.0;    // t . a, t . e2
  double tau = 0.0;             // |t . m|
  double sigma = 1.0;           // sign of t . m
  double rounding = 0.0;        // subtracted from every lower bound
  double pole_allowance = 0.0;  // and this from bounds that reach a pole
  // Per pole (+a, -a, -b, +b: where a . n = +-1 or w = -(b . n) = +-1) and
  // per branch of that pole's profile: h_D(n) >= H cos(phi) + kappa sin(phi)
  // for n at angle phi from the pole (see pole_cap_bound).
  std::array<std::array<double, 2>, 4> cap_h{}, cap_kappa{};

  Eigen::Vector3d direction(const Eigen::Vector2d& P) const {
    const double g = std::sqrt(std::max(0.0, 1.0 - P.squaredNorm()));
    Eigen::Vector3d n = P.x() * a + P.y() * e2 + (sigma * g) * m;
    return n / n.norm();
  }
  // h_D(n) for any unit n, from the profiles (not through P).
  double h(const Eigen::Vector3d& n) const { return fa.value(a, n) + fb.value(b, Eigen::Vector3d(-n)) - t.dot(n); }
};

struct Candidate {
  double value = std::numeric_limits<double>::infinity();
  Eigen::Vector2d P = Eigen::Vector2d::Zero();
};

// A lower bound of h_D over every direction within phi_max (< pi/2) of pole
// `which` (see Problem::cap_h), resolved where the disc coordinates are not.
// With p the pole and n = cos(phi) p + sin(phi) u (u a unit vector normal to
// p): the pole's profile is at least each of its branches, slope (+-cos phi)
// + radius sin(phi); the rest of h_D is the support function of a convex
// set K (A - t for B's poles, -B placed for A's), at least n . x for x its
// support point at p, and n . x >= cos(phi) (p . x) - sin(phi) |x - (p . x) p|.
// So h_D(n) >= g(phi) = H cos(phi) + kappa sin(phi), a sinusoid: where both
// ends of [0, phi_max] are positive it is positive, hence concave, between
// them, and its minimum there is at an end. A pole that is a strict kink of
// the profile (a cylinder's cap, kappa > 0) gives the pole's own value
// (to H phi_max^2 / 2); otherwise about the allowance.
inline double pole_cap_bound(const Problem& pr, int which, double phi_max) {
  double bound = -std::numeric_limits<double>::infinity();
  // Caps that wide are coarse squares, which bisection refines anyway (and
  // the argument needs [0, phi_max] shorter than a half period).
  if (!(phi_max < 1.5)) return bound;
  const double c = std::cos(phi_max), sn = std::sin(phi_max);
  for (int k = 0; k < 2; ++k) {
    const double h = pr.cap_h[which][k], kappa = pr.cap_kappa[which][k];
    const double at_end = h * c + kappa * sn;
    if (h > 0.0 && at_end > 0.0) bound = std::max(bound, std::min(h, at_end));
  }
  return bound;
}

// The convex lower bound on one piece: chord_A(X) + chord_B(w) - t1 X - t2 Y
// - tau gamma, w = -(c X + s Y); its exact minimum over piece and disc.
HEDRA_FLATTEN inline Candidate piece_bound(const Problem& pr, const Polygon& poly, const Branch& ga, const Branch& gb) {
  Candidate best;
  if (poly.n == 0) return best;
  const Eigen::Vector2d wb(-pr.c, -pr.s);  // w = wb . P
  double x0 = 1.0, x1 = -1.0, w0 = 1.0, w1 = -1.0;
  for (int i = 0; i < poly.n; ++i) {
    x0 = std::min(x0, poly.p[i].x());
    x1 = std::max(x1, poly.p[i].x());
    w0 = std::min(w0, wb.dot(poly.p[i]));
    w1 = std::max(w1, wb.dot(poly.p[i]));
  }
  x0 = std::clamp(x0, -1.0, 1.0);
  x1 = std::clamp(x1, x0, 1.0);
  w0 = std::clamp(w0, -1.0, 1.0);
  w1 = std::clamp(w1, w0, 1.0);
  const double va = ga.value(x0), ba = ga.chord_slope(x0, x1);
  const double vb = gb.value(w0), bb = gb.chord_slope(w0, w1);
  const auto lambda = [&](const Eigen::Vector2d& P) {
    const double g = std::sqrt(std::max(0.0, 1.0 - P.squaredNorm()));
    return va + ba * (P.x() - x0) + vb + bb * (wb.dot(P) - w0) - pr.t1 * P.x() - pr.t2 * P.y() - pr.tau * g;
  };
  const auto consider = [&](const Eigen::Vector2d& P) {
    const double v = lambda(P);
    if (v < best.value) best = {v, P};
  };
  const Eigen::Vector2d G = Eigen::Vector2d(ba, 0.0) + bb * wb - Eigen::Vector2d(pr.t1, pr.t2);
  // The piece's edges p_i p_{i+1} and their lengths, once for the inside
  // test and the edge minimisers below.
  std::array<Eigen::Vector2d, 8> edge;
  std::array<double, 8> edge_length;
  for (int i = 0; i < poly.n; ++i) {
    edge[i] = poly.p[(i + 1) % poly.n] - poly.p[i];
    edge_length[i] = edge[i].norm();
  }
  // Inside the piece, up to a rounding slack (a point a hair outside only
  // lowers the bound: still certified).
  const auto inside = [&](const Eigen::Vector2d& P) {
    for (int i = 0; i < poly.n; ++i) {
      const Eigen::Vector2d& p = poly.p[i];
      const Eigen::Vector2d& d = edge[i];
      if (d.x() * (P.y() - p.y()) - d.y() * (P.x() - p.x()) < -1e-15 * (edge_length[i] + 1.0)) return false;
    }
    return true;
  };
  const double gn = G.norm();
  if (pr.tau > 0.0) {
    const Eigen::Vector2d P = -G / accurate_hypot(gn, pr.tau);
    if (inside(P)) consider(P);
  }
  if (gn > 0.0) {  // the lowest point of the arc
    const Eigen::Vector2d P = -G / gn;
    if (inside(P)) consider(P);
  }
  for (int i = 0; i < poly.n; ++i) {
    const Eigen::Vector2d& p = poly.p[i];
    const Eigen::Vector2d& d0 = edge[i];
    const double len = edge_length[i];
    if (!(len > 0.0)) {
      if (p.squaredNorm() <= 1.0) consider(p);
      continue;
    }
    const Eigen::Vector2d d = d0 / len;
    // P = F0 + sigma d, F0 the foot of the origin on the edge's line.
    const double sp = p.dot(d);
    const Eigen::Vector2d F0 = p - sp * d;
    const double rho2 = 1.0 - F0.squaredNorm();
    if (!(rho2 >= 0.0)) continue;
    const double rho = std::sqrt(rho2);
    const double lo = std::max(sp, -rho), hi = std::min(sp + len, rho);
    if (!(lo <= hi)) continue;
    consider(F0 + lo * d);
    consider(F0 + hi * d);
    if (pr.tau > 0.0) {
      const double k = G.dot(d);
      const double star = std::clamp(-k * rho / accurate_hypot(k, pr.tau), lo, hi);
      consider(F0 + star * d);
    }
  }
  // Near a pole (X or w within 4e-15 of +-1, 9e-8 rad of an axis) the disc
  // coordinates cannot resolve directions (cos of 1e-8 rad is 1 in
  // double): the bound there is lowered by what that hides, 1e-7 of the
  // radii and of t, so that no square near a pole is dropped on a bound
  // the coordinates cannot support (the minimum there stays uncertified,
  // and the caller falls back to EPA).
  // Unless a cap bound around the pole does better (pole_cap_bound): the
  // piece lies within phi_max of the pole, from 1 -+ its extreme coordinate
  // (exact for X; w carries a few eps of rounding, allowed for).
  const double pole = 1.0 - 4e-15;
  if (x0 <= -pole || x1 >= pole || w0 <= -pole || w1 >= pole) {
    const double eps = std::numeric_limits<double>::epsilon();
    const auto angle = [](double one_minus) {  // acos(1 - one_minus), widened
      return 2.0 * std::asin(std::min(1.0, std::sqrt(std::max(0.0, 0.5 * one_minus)))) * (1.0 + 1e-9) + 1e-300;
    };
    double bound = best.value - pr.pole_allowance;
    if (x1 >= pole) bound = std::max(bound, pole_cap_bound(pr, 0, angle(1.0 - x0)));
    if (x0 <= -pole) bound = std::max(bound, pole_cap_bound(pr, 1, angle(1.0 + x1)));
    if (w1 >= pole) bound = std::max(bound, pole_cap_bound(pr, 2, angle(1.0 - w0 + 8.0 * eps)));
    if (w0 <= -pole) bound = std::max(bound, pole_cap_bound(pr, 3, angle(1.0 + w1 + 8.0 * eps)));
    best.value = bound;
  }
  best.value -= pr.rounding;
  return best;
}

// The support set of a core of revolution (profile p, local axis z) along
// the local unit direction d: a point, a segment (on a kink, within `slack`
// of c), or a disc (a cap, d within `slack` of the axis). World placement
// by (R, t).
struct Feature {
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), p1 = Eigen::Vector3d::Zero();  // segment (p0 = p1: a point)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();                             // disc normal
  double disc = 0.0;                                                           // disc radius (0: none)

  Eigen::Vector3d project(const Eigen::Vector3d& x) const {
    if (disc > 0.0) {
      Eigen::Vector3d r = x - p0;
      r -= r.dot(axis) * axis;
      const double len = r.norm();
      return len > disc ? Eigen::Vector3d(p0 + (disc / len) * r) : Eigen::Vector3d(p0 + r);
    }
    const Eigen::Vector3d d = p1 - p0;
    const double dd = d.squaredNorm();
    if (!(dd > 0.0)) return p0;
    return p0 + std::clamp((x - p0).dot(d) / dd, 0.0, 1.0) * d;
  }
};

// The closest points of segments [p0, p1] and [q0, q1] (either may be a
// point): the clamped minimiser of |p(s) - q(u)|^2, u re-solved after s is
// clamped and s after u (exact for nearly parallel segments too: any pair
// of the overlap is a closest pair).
inline void closest_on_segments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                                const Eigen::Vector3d& q1, Eigen::Vector3d& p, Eigen::Vector3d& q) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, u = 0.0;
  if (a > 0.0 && e > 0.0) {
    const double b = d1.dot(d2), c = d1.dot(r);
    const double denom = a * e - b * b;
    s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
    u = (b * s + f) / e;
    if (u < 0.0 || u > 1.0) {
      u = std::clamp(u, 0.0, 1.0);
      s = std::clamp((b * u - c) / a, 0.0, 1.0);
    }
  } else if (e > 0.0) {
    u = std::clamp(f / e, 0.0, 1.0);
  } else if (a > 0.0) {
    s = std::clamp(-d1.dot(r) / a, 0.0, 1.0);
  }
  p = p0 + s * d1;
  q = q0 + u * d2;
}

inline Feature feature_of(const Profile& p, const Eigen::Vector3d& d, double slack, const Eigen::Matrix3d& R,
                          const Eigen::Vector3d& t) {
  Feature f;
  const double c = std::clamp(d.z(), -1.0, 1.0);
  const double rd = accurate_hypot(d.x(), d.y());
  const Eigen::Vector3d k = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d rim =
      rd > 0.0 ? Eigen::Vector3d(p.radius * d.x() / rd, p.radius * d.y() / rd, 0.0) : Eigen::Vector3d::Zero();
  const double h = p.half_length;
  const Eigen::Vector3d apex = h * k;
  if (p.kind != 3 && rd <= slack && p.radius > 0.0) {  // a cylinder's cap
    f.p0 = f.p1 = (c >= 0.0 ? h : -h) * k;
    f.disc = p.radius;
  } else if (p.kind == 3 && c < 0.0 && rd <= slack) {  // a cone's base
    f.p0 = f.p1 = -h * k;
    f.disc = p.radius;
  } else if (std::abs(c - p.kink) <= slack) {  // on the kink: the segment between the branches' points
    f.p0 = p.kind == 3 ? apex : Eigen::Vector3d(rim + h * k);
    f.p1 = rim - h * k;
  } else if (c > p.kink) {
    f.p0 = f.p1 = p.kind == 3 ? apex : Eigen::Vector3d(rim + h * k);
  } else {
    f.p0 = f.p1 = rim - h * k;
  }
  f.p0 = R * f.p0 + t;
  f.p1 = R * f.p1 + t;
  f.axis = R * k;
  return f;
}

}  // namespace tilted_detail

// Pairs whose axes are within kCoaxialTilt rad of parallel (or
// anti-parallel) go to the branch and bound before EPA, with a budget of
// kCoaxialFirstSquares squares (EPA's polytope cannot certify them; the
// bench's nearly coaxial pairs, tilts 1e-10 .. 1e-3, need at most 64).
inline constexpr double kCoaxialTilt = 1e-2;
inline constexpr int kCoaxialFirstSquares = 512;

template <class CA, class CB>
bool nearly_coaxial(const CA& core_a, const CB& core_b, const RelativePose& relative) {
  const tilted_detail::Profile pa = tilted_detail::profile_of(core_a), pb = tilted_detail::profile_of(core_b);
  if (!pa.valid || !pb.valid || !(pa.curved || pb.curved)) return false;
  const Eigen::Vector3d kb = relative.rotation.col(2);
  return std::atan2(Eigen::Vector3d::UnitZ().cross(kb).norm(), std::abs(kb.z())) <= kCoaxialTilt;
}

struct TiltedRevolutionSettings {
  int max_squares = 4096;  // squares bounded, the cap reported as max_iterations
};

namespace tilted_detail {

// Phase 1: the pair in the disc coordinates described at the top of this
// file, with its pole caps (pole_cap_bound); false when the pair is not two
// cores of revolution, one curved, with axes that are not parallel.
template <class CA, class CB>
bool make_problem(const CA& core_a, const CB& core_b, const RelativePose& relative, double scale, Problem& pr) {
  pr.fa = profile_of(core_a);
  pr.fb = profile_of(core_b);
  if (!pr.fa.valid || !pr.fb.valid || !(pr.fa.curved || pr.fb.curved)) return false;
  if (!(std::isfinite(scale) && scale > 0.0)) return false;
  pr.a = Eigen::Vector3d::UnitZ();
  pr.b = relative.rotation.col(2);
  pr.t = relative.translation;
  // m perpendicular to a and b to a few eps: the cross product's rounding
  // (eps / theta of its direction) is taken out against a, which leaves
  // b . m at eps too (b - (a . b) a is small where that rounding is large).
  Eigen::Vector3d m = pr.a.cross(pr.b);
  const double mn = m.norm();
  if (!(mn > 0.0) || !std::isfinite(mn)) return false;
  m /= mn;
  m -= m.dot(pr.a) * pr.a;
  m.normalize();
  pr.m = m;
  pr.e2 = m.cross(pr.a);
  pr.c = pr.a.dot(pr.b);
  pr.s = pr.e2.dot(pr.b);
  pr.t1 = pr.t.dot(pr.a);
  pr.t2 = pr.t.dot(pr.e2);
  const double tm = pr.t.dot(m);
  pr.tau = std::abs(tm);
  pr.sigma = tm >= 0.0 ? 1.0 : -1.0;
  const double eps = std::numeric_limits<double>::epsilon();
  pr.rounding = 64.0 * eps * (2.0 * scale + pr.t.norm());
  pr.pole_allowance = 1e-7 * (pr.fa.radius + pr.fb.radius + pr.fa.half_length + pr.fb.half_length + pr.t.norm());
  // The pole caps: for A's poles p = +-a the rest is -B placed at t, its
  // support point at p being -(R s_B(R^T (-p)) + t); for B's poles p = -+b
  // (w = +-1) it is A - t, with s_A(p) - t.
  const Eigen::Matrix3d& R = relative.rotation;
  const std::array<Eigen::Vector3d, 4> poles = {pr.a, Eigen::Vector3d(-pr.a), Eigen::Vector3d(-pr.b), pr.b};
  for (int which = 0; which < 4; ++which) {
    const Eigen::Vector3d& p = poles[which];
    const bool of_a = which < 2;
    const Eigen::Vector3d x = of_a ? Eigen::Vector3d(-(R * core_b.support(R.transpose() * (-p)) + pr.t))
                                   : Eigen::Vector3d(core_a.support(p) - pr.t);
    const double along = p.dot(x), across = (x - along * p).norm();
    const Profile& f = of_a ? pr.fa : pr.fb;
    const double sign = which % 2 == 0 ? 1.0 : -1.0;  // the profile's coordinate at the pole
    const Branch* branch[2] = {&f.lo, &f.hi};
    for (int k = 0; k < 2; ++k) {
      pr.cap_h[which][k] = sign * branch[k]->slope + along;
      pr.cap_kappa[which][k] = branch[k]->radius - across;
    }
  }
  return true;
}

// The search's state: the best upper bound (a support value h_D(n)), its
// direction, and the tolerance it implies.
struct Search {
  const Problem& pr;
  const EpaSettings& settings;
  double scale;
  Eigen::Vector2d kink_b_normal;  // w = -(b . n) = kink_b_normal . P
  double upper = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_n = Eigen::Vector3d::UnitX();

  Search(const Problem& problem, const EpaSettings& s, double sc)
      : pr(problem), settings(s), scale(sc), kink_b_normal(-problem.c, -problem.s) {}

  void offer(const Eigen::Vector3d& n) {
    if (!n.allFinite()) return;
    const double v = pr.h(n);
    if (v < upper) {
      upper = v;
      best_n = n;
    }
  }
  double tolerance() const {
    return std::max(settings.relative_tolerance * std::abs(upper), settings.absolute_tolerance * scale);
  }
  // A square's bound: the smallest over its pieces (cut by the two kink
  // lines); each piece's minimiser is offered as an upper bound.
  double square_bound(const Eigen::Vector2d& lo_corner, double size) {
    Polygon sq;
    sq.n = 4;
    sq.p[0] = lo_corner;
    sq.p[1] = lo_corner + Eigen::Vector2d(size, 0.0);
    sq.p[2] = lo_corner + Eigen::Vector2d(size, size);
    sq.p[3] = lo_corner + Eigen::Vector2d(0.0, size);
    double bound = std::numeric_limits<double>::infinity();
    for (int ia = 0; ia < 2; ++ia) {
      const Polygon pa = clip(sq, Eigen::Vector2d::UnitX(), pr.fa.kink, ia == 0 ? 1.0 : -1.0);
      if (pa.n == 0) continue;
      for (int ib = 0; ib < 2; ++ib) {
        const Polygon piece = clip(pa, kink_b_normal, pr.fb.kink, ib == 0 ? 1.0 : -1.0);
        if (piece.n == 0) continue;  // an empty piece bounds nothing (piece_bound's infinity)
        const Candidate cnd = piece_bound(pr, piece, ia == 0 ? pr.fa.lo : pr.fa.hi, ib == 0 ? pr.fb.lo : pr.fb.hi);
        if (cnd.value < bound) bound = cnd.value;
        if (std::isfinite(cnd.value)) offer(pr.direction(cnd.P));
      }
    }
    return bound;
  }
};

// What the branch and bound certified.
struct Bracket {
  double certified = std::numeric_limits<double>::infinity();  // the smallest bound of the squares dropped
  int squares = 0;                                             // squares bounded
  bool capped = false;                                         // max_squares reached
};

// Phase 2: depth first over a quadtree of [-1, 1]^2, children in stack
// order; a square is dropped once its bound is within the tolerance of the
// best upper bound, or at the cap (then its parent's bound is what is
// certified for it).
inline Bracket branch_and_bound(Search& search, int max_squares) {
  struct Square {
    Eigen::Vector2d corner;
    double size;
    double bound;
  };
  constexpr int kMaxDepth = 64;
  std::array<Square, 4 * kMaxDepth + 4> stack;
  int top = 0;
  Bracket out;
  // The four quadrants of [-1, 1]^2, bounded first: every square on the
  // stack then carries a finite bound (its parent's), which is what the cap
  // certifies for the squares it leaves unexplored.
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d corner(i % 2 == 0 ? -1.0 : 0.0, i / 2 == 0 ? -1.0 : 0.0);
    ++out.squares;
    stack[top++] = {corner, 1.0, search.square_bound(corner, 1.0)};
  }
  const double eps = std::numeric_limits<double>::epsilon();
  while (top > 0) {
    const Square sq = stack[--top];
    if (sq.bound >= search.upper - search.tolerance()) {
      out.certified = std::min(out.certified, sq.bound);
      continue;
    }
    if (out.squares >= max_squares) {
      out.capped = true;
      out.certified = std::min(out.certified, sq.bound);
      continue;
    }
    // A child bounded, or a quadrant (bounded already, at size 1).
    double bound = sq.bound;
    if (sq.size < 1.0) {
      ++out.squares;
      bound = search.square_bound(sq.corner, sq.size);
    }
    if (bound == std::numeric_limits<double>::infinity()) continue;         // outside the disc
    if (!(bound >= -std::numeric_limits<double>::max())) bound = sq.bound;  // NaN: keep the parent's
    if (bound >= search.upper - search.tolerance() || top + 4 > static_cast<int>(stack.size()) ||
        !(sq.size > 4.0 * eps)) {
      out.certified = std::min(out.certified, bound);
      continue;
    }
    // The four children carry this square's bound until they are bounded.
    const double half = 0.5 * sq.size;
    std::array<Square, 4> child;
    for (int i = 0; i < 4; ++i)
      child[i] = {sq.corner + Eigen::Vector2d(i % 2 == 0 ? 0.0 : half, i / 2 == 0 ? 0.0 : half), half, bound};
    for (const Square& c : child) stack[top++] = c;
  }
  return out;
}

// Phase 3: the answer snapped onto a kink line (or both) when that costs
// less than a quarter of the tolerance: the minimum usually lies on one,
// where the support sets are segments and the witnesses can be exact.
inline void snap_to_kinks(Search& search) {
  const Problem& pr = search.pr;
  const Eigen::Vector2d P(pr.a.dot(search.best_n), pr.e2.dot(search.best_n));
  const Eigen::Vector2d nb = search.kink_b_normal / search.kink_b_normal.norm();
  const double kb = pr.fb.kink / search.kink_b_normal.norm();
  const Eigen::Vector2d on_a(pr.fa.kink, P.y());
  const Eigen::Vector2d on_b = P - (nb.dot(P) - kb) * nb;
  Eigen::Vector2d on_both = on_a;
  const double det = nb.y();  // X = ka and nb . P = kb
  if (std::abs(det) > 0.0) on_both = Eigen::Vector2d(pr.fa.kink, (kb - nb.x() * pr.fa.kink) / det);
  const double allowed = search.upper + 0.25 * search.tolerance();
  double best_value = std::numeric_limits<double>::infinity();
  Eigen::Vector3d snapped = search.best_n;
  for (const Eigen::Vector2d& Q : {on_both, on_a, on_b}) {
    if (!(Q.squaredNorm() <= 1.0)) continue;
    const Eigen::Vector3d n = pr.direction(Q);
    const double v = pr.h(n);
    if (v <= allowed && v < best_value) {
      best_value = v;
      snapped = n;
      break;  // the first acceptable in that order: the most constrained
    }
  }
  if (best_value <= allowed) {
    search.upper = best_value;
    search.best_n = snapped;
  }
}

// Phase 4, witnesses: p_a in A's support set along n, p_b in B's along -n,
// with p_a - p_b as close to depth * n as alternating projections get
// (exact for points and for segments that overlap; the caller splits the
// rest). A direction within `slack` of a kink (in c) or of an axis sees
// the whole segment or disc: its support value differs by at most
// 2 scale slack, a quarter of the tolerance.
inline void set_witnesses(const Search& search, const RelativePose& relative, EpaResult& r) {
  const Problem& pr = search.pr;
  const double slack = 0.125 * search.tolerance() / search.scale;
  const Eigen::Vector3d& best_n = search.best_n;
  const Feature fa = feature_of(pr.fa, best_n, slack, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  const Feature fb = feature_of(pr.fb, -(relative.rotation.transpose() * best_n), slack, relative.rotation, pr.t);
  const Eigen::Vector3d x = search.upper * best_n;
  Eigen::Vector3d pa, pb;
  if (fa.disc == 0.0 && fb.disc == 0.0) {
    closest_on_segments(fa.p0, fa.p1, fb.p0 + x, fb.p1 + x, pa, pb);
    pb -= x;
  } else {
    pa = fa.project(fb.p0 + x);
    pb = fb.project(pa - x);
    for (int i = 0; i < 16; ++i) {
      pa = fa.project(pb + x);
      pb = fb.project(pa - x);
    }
  }
  r.point_a = pa;
  r.point_b = pb;
}

}  // namespace tilted_detail

// The signed depth (min over unit n of h_D(n), > 0 when the cores overlap)
// of two cores of revolution (segment, cylinder or cone; B placed by
// `relative` in A's frame) whose axes are not parallel, certified within
// max(relative_tolerance depth, absolute_tolerance scale) of EpaSettings;
// false when the pair is not of that kind. `hints`: directions whose support
// values start the upper bound. Conventions of epa_penetration.
template <class CA, class CB>
bool tilted_revolution_penetration(const CA& core_a, const CB& core_b, const RelativePose& relative, double scale,
                                   const Eigen::Vector3d* hints, int hint_count, const EpaSettings& settings,
                                   EpaResult& out, const TiltedRevolutionSettings& tilted = {}) {
  using namespace tilted_detail;
  Problem pr;
  if (!make_problem(core_a, core_b, relative, scale, pr)) return false;
  Search search(pr, settings, scale);
  // The upper bound starts from the caller's directions and the poles
  // themselves (the cap bounds certify minima there).
  for (int i = 0; i < hint_count; ++i) {
    const double len = hints[i].norm();
    if (len > 0.0 && std::isfinite(len)) search.offer(hints[i] / len);
  }
  for (const Eigen::Vector3d& p : {pr.a, Eigen::Vector3d(-pr.a), pr.b, Eigen::Vector3d(-pr.b)}) search.offer(p);
  const Bracket bracket = branch_and_bound(search, tilted.max_squares);
  if (!std::isfinite(search.upper) || std::isnan(bracket.certified)) return false;
  snap_to_kinks(search);
  const double certified = std::isfinite(bracket.certified) ? bracket.certified : search.upper;
  EpaResult r;
  r.depth = search.upper;
  r.normal = search.best_n;
  set_witnesses(search, relative, r);
  r.error_bound = std::max(search.upper - std::min(certified, search.upper), 0.0);
  r.iterations = bracket.squares;
  r.dimension = 3;
  r.status = bracket.capped ? EpaStatus::max_iterations : EpaStatus::ok;
  if (!bracket.capped && r.error_bound > search.tolerance()) r.status = EpaStatus::stalled;
  out = r;
  return true;
}

}  // namespace hedra::collision
