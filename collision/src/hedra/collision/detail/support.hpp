// Support mappings in the local frame: s(d) = argmax_{x in shape} d . x.
//
// Cores (PointCore, SegmentCore, BoxCore, CylinderCore, ConeCore,
// PolyhedronCore) are the shapes without their rounding; each is a "support"
// type: `Eigen::Vector3d support(const Eigen::Vector3d& d) const`, the
// concept GJK is written against. support(shape, d) gives the full shape
// (core + radius, margin included) for callers outside the GJK loop.
//
// Ties: any maximiser is a valid answer. Boxes, segments, cylinders and cones
// break ties towards +axis (sign(0) = +1); a cylinder or cone direction
// parallel to the axis (|d_xy| <= eps |d|) returns the rim point on +x, whose
// support value is off by at most radius * eps * |d|.
//
// Polyhedra: a linear scan below hill_climb_crossover() vertices (four at a
// time, AVX2 or SSE2 where the processor has them, the same first maximiser
// as one at a time), above it hill-climbing over the vertex adjacency of the
// half-edge mesh: from the hint vertex (on large hulls, from the better of
// the hint and the best of a few precomputed extreme vertices), move to the
// neighbour with the largest d . x while it strictly improves. On a convex
// polytope a vertex none of whose neighbours is strictly better is a global
// maximiser (the edge graph of a polytope reaches every vertex along
// non-decreasing d . x from any vertex that is not a maximiser, the simplex
// method's optimality argument), so the answer is exact, plateaus included,
// provided coplanar faces are merged: quickhull merges them, so no face is
// reflex beyond its tolerance. Each step strictly increases d . x, so the
// walk visits a vertex at most once; its cap (the vertex count) can only be
// reached by a broken mesh or a non-finite direction, and then the linear
// scan answers instead. A NaN direction compares false everywhere and
// returns the start vertex: callers reject non-finite directions before
// (GJK does).
//
// The crossover (32 vertices with SSE2 lanes, 64 with AVX2's) is measured:
// docs/design.md, "Support crossover". Where two vertices tie, the scan and
// the climb may answer different ones (both exact), so answers can differ
// in their last bits between processors with and without AVX2.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <hedra/collision/detail/vector_math.hpp>
#include <hedra/collision/shapes.hpp>
#include <limits>

#if defined(__SSE2__)
#  include <emmintrin.h>
#endif
// AVX2 scan: always when the compiler targets AVX2; otherwise, with GCC or
// Clang on x86_64, compiled for AVX2 apart and chosen at run time when the
// processor has it (the default build stays portable to any x86_64).
#if defined(__AVX2__)
#  define HEDRA_AVX2_SCAN 1
#  define HEDRA_AVX2_TARGET
#elif defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#  define HEDRA_AVX2_SCAN 1
#  define HEDRA_AVX2_DISPATCH 1
#  define HEDRA_AVX2_TARGET __attribute__((target("avx2")))
#endif
#if defined(HEDRA_AVX2_SCAN)
#  include <immintrin.h>
#endif

namespace hedra::collision {

// Below this many vertices the scan answers, from it on the climb
// (docs/design.md, "Support crossover"): 32 with SSE2 lanes, 64 with AVX2's
// (hill_climb_crossover(), below, picks the one this processor runs).
inline constexpr std::size_t kHillClimbCrossover = 32;
inline constexpr std::size_t kHillClimbCrossoverAvx2 = 64;

// The first index of a vertex maximising d . vertex(i), one vertex at a
// time: the reference the vectorised scan below must agree with.
inline hull::Index polyhedron_support_scan_serial(const ConvexPolyhedron& poly, const Eigen::Vector3d& d) {
  const Eigen::Vector3d* v = poly.vertices().data();
  const std::size_t n = poly.vertex_count();
  hull::Index best = 0;
  double best_value = dot3(d, v[0]);
  for (std::size_t i = 1; i < n; ++i) {
    const double value = dot3(d, v[i]);
    if (value > best_value) {
      best_value = value;
      best = static_cast<hull::Index>(i);
    }
  }
  return best;
}

// The first position p in `count` blocks of four points (position 4 b + k:
// block b, lane k) whose value d . x is the largest and strictly above
// `start_value`, with that value; {-1, start_value} when none is. Lane k
// keeps the first such point among positions = k (mod 4), the values in
// dot3's order (the same bits as a serial loop); the lanes then compare by
// value, ties to the smaller position, which is the first overall. NaN
// values never compare greater, as in a serial loop. SSE2 (baseline on
// x86_64) when the compiler offers it, plain lanes otherwise.
struct BlockBest {
  double position;
  double value;
};
// The lanes' reduction: the largest value, ties to the smaller position.
inline BlockBest best_of_lanes(const double (&value)[4], const double (&position)[4]) {
  int best = 0;
  for (int k = 1; k < 4; ++k)
    if (value[k] > value[best] || (value[k] == value[best] && position[k] < position[best])) best = k;
  return {position[best], value[best]};
}

inline BlockBest first_block_max_sse2(const ConvexPolyhedron::VertexBlock* blocks, std::size_t count,
                                      const Eigen::Vector3d& d, double start_value) {
  alignas(16) double value[4], position[4];
#if defined(__SSE2__)
  const __m128d dx = _mm_set1_pd(d.x()), dy = _mm_set1_pd(d.y()), dz = _mm_set1_pd(d.z());
  const __m128d step = _mm_set1_pd(4.0);
  __m128d best_lo = _mm_set1_pd(start_value), best_hi = best_lo;
  __m128d position_lo = _mm_set1_pd(-1.0), position_hi = position_lo;
  __m128d at_lo = _mm_set_pd(1.0, 0.0), at_hi = _mm_set_pd(3.0, 2.0);
  for (const ConvexPolyhedron::VertexBlock* b = blocks; b != blocks + count; ++b) {
    const __m128d v_lo = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, _mm_load_pd(b->x)), _mm_mul_pd(dy, _mm_load_pd(b->y))),
                                    _mm_mul_pd(dz, _mm_load_pd(b->z)));
    const __m128d v_hi =
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, _mm_load_pd(b->x + 2)), _mm_mul_pd(dy, _mm_load_pd(b->y + 2))),
                   _mm_mul_pd(dz, _mm_load_pd(b->z + 2)));
    const __m128d up_lo = _mm_cmpgt_pd(v_lo, best_lo), up_hi = _mm_cmpgt_pd(v_hi, best_hi);
    // maxpd(v, best) is v > best ? v : best (best on ties and NaN).
    best_lo = _mm_max_pd(v_lo, best_lo);
    best_hi = _mm_max_pd(v_hi, best_hi);
    position_lo = _mm_or_pd(_mm_and_pd(up_lo, at_lo), _mm_andnot_pd(up_lo, position_lo));
    position_hi = _mm_or_pd(_mm_and_pd(up_hi, at_hi), _mm_andnot_pd(up_hi, position_hi));
    at_lo = _mm_add_pd(at_lo, step);
    at_hi = _mm_add_pd(at_hi, step);
  }
  _mm_store_pd(value, best_lo);
  _mm_store_pd(value + 2, best_hi);
  _mm_store_pd(position, position_lo);
  _mm_store_pd(position + 2, position_hi);
#else
  for (int k = 0; k < 4; ++k) {
    value[k] = start_value;
    position[k] = -1.0;
  }
  double at = 0.0;
  for (const ConvexPolyhedron::VertexBlock* b = blocks; b != blocks + count; ++b, at += 4.0) {
    for (int k = 0; k < 4; ++k) {
      const double v = (d.x() * b->x[k] + d.y() * b->y[k]) + d.z() * b->z[k];
      if (v > value[k]) {
        value[k] = v;
        position[k] = at + k;
      }
    }
  }
#endif
  return best_of_lanes(value, position);
}

#if defined(HEDRA_AVX2_SCAN)
// The same lanes in one 256-bit register each: the same products and sums
// in the same order (no fused multiply-add), so the same first maximiser.
HEDRA_AVX2_TARGET inline BlockBest first_block_max_avx2(const ConvexPolyhedron::VertexBlock* blocks, std::size_t count,
                                                        const Eigen::Vector3d& d, double start_value) {
  alignas(32) double value[4], position[4];
  const __m256d dx = _mm256_set1_pd(d.x()), dy = _mm256_set1_pd(d.y()), dz = _mm256_set1_pd(d.z());
  const __m256d step = _mm256_set1_pd(4.0);
  __m256d best = _mm256_set1_pd(start_value);
  __m256d best_position = _mm256_set1_pd(-1.0);
  __m256d at = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
  for (const ConvexPolyhedron::VertexBlock* b = blocks; b != blocks + count; ++b) {
    const __m256d v =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, _mm256_load_pd(b->x)), _mm256_mul_pd(dy, _mm256_load_pd(b->y))),
                      _mm256_mul_pd(dz, _mm256_load_pd(b->z)));
    const __m256d up = _mm256_cmp_pd(v, best, _CMP_GT_OQ);  // false on NaN, as v > best
    best = _mm256_max_pd(v, best);                          // v > best ? v : best
    best_position = _mm256_blendv_pd(best_position, at, up);
    at = _mm256_add_pd(at, step);
  }
  _mm256_store_pd(value, best);
  _mm256_store_pd(position, best_position);
  return best_of_lanes(value, position);
}
#endif

#if defined(HEDRA_AVX2_DISPATCH)
// Whether this processor runs AVX2, asked once (before this is initialised,
// during other static initialisers, it reads false: the SSE2 scan, the same
// answer).
inline const bool kProcessorHasAvx2 = [] {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") != 0;
}();
#endif

inline std::size_t hill_climb_crossover() {
#if defined(HEDRA_AVX2_DISPATCH)
  return kProcessorHasAvx2 ? kHillClimbCrossoverAvx2 : kHillClimbCrossover;
#elif defined(HEDRA_AVX2_SCAN)
  return kHillClimbCrossoverAvx2;
#else
  return kHillClimbCrossover;
#endif
}

// first_block_max_sse2 or, where the processor has it, first_block_max_avx2:
// the same answer.
inline BlockBest first_block_max(const ConvexPolyhedron::VertexBlock* blocks, std::size_t count,
                                 const Eigen::Vector3d& d, double start_value) {
#if defined(HEDRA_AVX2_DISPATCH)
  if (kProcessorHasAvx2) return first_block_max_avx2(blocks, count, d, start_value);
#elif defined(HEDRA_AVX2_SCAN)
  return first_block_max_avx2(blocks, count, d, start_value);
#endif
  return first_block_max_sse2(blocks, count, d, start_value);
}

// The same index as the serial scan, four vertices at a time over
// vertex_blocks(): the first vertex above vertex 0, else vertex 0 (a NaN
// there answers 0, as nothing compares greater). Padding copies vertex 0:
// never above it.
inline hull::Index polyhedron_support_scan(const ConvexPolyhedron& poly, const Eigen::Vector3d& d) {
  const BlockBest best =
      first_block_max(poly.vertex_blocks().data(), poly.vertex_blocks().size(), d, dot3(d, poly.vertex(0)));
  return best.position < 0.0 ? 0 : static_cast<hull::Index>(best.position);
}

// Where a climb without a hint starts: the first of the hull's start
// vertices with the largest d . x (vertex 0 when it keeps none).
inline hull::Index cold_start(const ConvexPolyhedron& poly, const Eigen::Vector3d& d) {
  if (poly.start_blocks().empty()) return 0;
  const hull::Index first = poly.start_vertex(0);
  const BlockBest best =
      first_block_max(poly.start_blocks().data(), poly.start_blocks().size(), d, dot3(d, poly.vertex(first)));
  return best.position < 0.0 ? first : poly.start_vertex(static_cast<std::size_t>(best.position));
}

// Steepest-ascent hill-climbing from `start`, or from the best of the hull's
// start vertices (ConvexPolyhedron::start_blocks()) when that is out of range
// or, on a hull that keeps them, better than `start` (vertex 0 when out of
// range on a hull that keeps none). Exact as argued at the top of this file:
// the start changes the walk's length, not where it may stop.
inline hull::Index polyhedron_support_climb(const ConvexPolyhedron& poly, const Eigen::Vector3d& d, hull::Index start) {
  const std::size_t n = poly.vertex_count();
  const Eigen::Vector3d* v = poly.vertices().data();
  hull::Index current = start < n ? start : cold_start(poly, d);
  double current_value = dot3(d, v[current]);
  if (start < n && !poly.start_blocks().empty()) {
    const hull::Index other = cold_start(poly, d);
    const double other_value = dot3(d, v[other]);
    if (other_value > current_value) {
      current = other;
      current_value = other_value;
    }
  }
  // The row of `current` to look at, as two ranges in the row's order: all
  // of it at the first step; after a step from u, without the run of u and
  // u's neighbours around u (ConvexPolyhedron::entry_rows). Those were all
  // compared at u's step and none beat `current` there, so none is
  // strictly above current_value: the walk, ties included, is the same as
  // over the whole row.
  const hull::Index* const rows = poly.neighbors();
  const hull::Index* first = poly.neighbors_begin(current);
  const hull::Index* first_end = poly.neighbors_end(current);
  const hull::Index* second = first_end;
  const hull::Index* second_end = first_end;
  for (std::size_t step = 0; step < n; ++step) {
    const hull::Index* best = nullptr;
    double best_value = current_value;
    for (const hull::Index* it = first; it != first_end; ++it) {
      const double value = dot3(d, v[*it]);
      if (value > best_value) {
        best_value = value;
        best = it;
      }
    }
    for (const hull::Index* it = second; it != second_end; ++it) {
      const double value = dot3(d, v[*it]);
      if (value > best_value) {
        best_value = value;
        best = it;
      }
    }
    if (best == nullptr) return current;
    current = *best;
    current_value = best_value;
    const ConvexPolyhedron::EntryRows& entry = poly.entry_rows(static_cast<std::size_t>(best - rows));
    first = rows + entry.first_begin;
    first_end = rows + entry.first_end;
    second = rows + entry.second_begin;
    second_end = poly.neighbors_end(current);
  }
  // Unreachable on a valid hull with a finite direction (see above).
  return polyhedron_support_scan(poly, d);
}

inline hull::Index polyhedron_support(const ConvexPolyhedron& poly, const Eigen::Vector3d& d, hull::Index hint) {
  if (poly.vertex_count() < hill_climb_crossover() || poly.dimension() < 2) return polyhedron_support_scan(poly, d);
  return polyhedron_support_climb(poly, d, hint);
}

// sign with sign(0) = +1: ties go to the + side.
inline double support_sign(double x) { return x >= 0.0 ? 1.0 : -1.0; }

// hypot(x, y) without the library call where the arguments are in the
// normal range: sqrt(a^2 + b^2) (a >= b) with Borges' one-step correction of
// the squares' rounding ("An Improved Algorithm for hypot(a, b)", 2019,
// the variant without fused multiply-add), which is what glibc 2.35 and
// later compute there, so the same bits as std::hypot on those systems and
// within one ulp of the exact value anywhere. Outside that range (b below
// a * 2^-54, squares that could overflow or underflow, inf, NaN) it is
// std::hypot. Needs -ffp-contract=off (set for the project): a contracted
// product would be a different rounding.
inline double accurate_hypot(double x, double y) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double a = ax < ay ? ay : ax, b = ax < ay ? ax : ay;
  if (!(a <= 0x1p+511 && b >= 0x1p-459 && b > a * 0x1p-54)) return std::hypot(x, y);
  const double h = std::sqrt(a * a + b * b);
  double t1, t2;  // the squares' rounding error, split so each part is exact enough
  if (h <= 2.0 * b) {
    const double delta = h - b;
    t1 = a * (2.0 * delta - a);
    t2 = (delta - 2.0 * (a - b)) * delta;
  } else {
    const double delta = h - a;
    t1 = 2.0 * delta * (a - 2.0 * b);
    t2 = (4.0 * delta - b) * b + delta * delta;
  }
  return h - (t1 + t2) / (2.0 * h);
}

// Unit vector of (d.x, d.y, 0) scaled by r, or (r, 0, 0) when d is (nearly)
// parallel to z; the threshold is relative to |d|, so the support value is
// off by at most r * eps * |d|.
inline Eigen::Vector3d support_disc(const Eigen::Vector3d& d, double r) {
  const double dxy = accurate_hypot(d.x(), d.y());
  if (!(dxy > std::numeric_limits<double>::epsilon() * d.norm())) return {r, 0.0, 0.0};
  return {r * d.x() / dxy, r * d.y() / dxy, 0.0};
}

// ---- cores: the support types GJK runs on ----------------------------------

struct PointCore {
  Eigen::Vector3d support(const Eigen::Vector3d&) const { return Eigen::Vector3d::Zero(); }
  double bounding_radius() const { return 0.0; }
};

struct SegmentCore {  // (0,0,-h) .. (0,0,+h)
  double half_length = 0.0;
  Eigen::Vector3d support(const Eigen::Vector3d& d) const { return {0.0, 0.0, support_sign(d.z()) * half_length}; }
  double bounding_radius() const { return half_length; }
};

struct BoxCore {
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
  Eigen::Vector3d support(const Eigen::Vector3d& d) const {
    return {support_sign(d.x()) * half_extents.x(), support_sign(d.y()) * half_extents.y(),
            support_sign(d.z()) * half_extents.z()};
  }
  double bounding_radius() const { return half_extents.norm(); }
};

struct CylinderCore {
  double radius = 0.0;
  double half_length = 0.0;
  Eigen::Vector3d support(const Eigen::Vector3d& d) const {
    Eigen::Vector3d s = support_disc(d, radius);
    s.z() = support_sign(d.z()) * half_length;
    return s;
  }
  double bounding_radius() const { return std::hypot(radius, half_length); }
};

struct ConeCore {  // apex (0,0,+h), base disc of radius r at z = -h
  double radius = 0.0;
  double half_length = 0.0;
  Eigen::Vector3d support(const Eigen::Vector3d& d) const {
    // The maximiser is the apex or a point of the base rim: compare the two.
    Eigen::Vector3d rim = support_disc(d, radius);
    rim.z() = -half_length;
    const double apex_value = d.z() * half_length;
    if (apex_value >= d.dot(rim)) return {0.0, 0.0, half_length};
    return rim;
  }
  double bounding_radius() const { return std::hypot(radius, half_length); }
};

// A polyhedron around its centroid (vertex(i), without offset()). `hint` is
// per-query state: the last answer, the start of the next climb. The wrapper
// lives on the caller's stack; the shared hull is never written.
struct PolyhedronCore {
  const ConvexPolyhedron* poly = nullptr;
  mutable hull::Index hint = 0;
  Eigen::Vector3d support(const Eigen::Vector3d& d) const {
    hint = polyhedron_support(*poly, d, hint);
    return poly->vertex(hint);
  }
  double bounding_radius() const { return poly->bounding_radius(); }
};

// ---- full shapes in their local frame (core + radius + margin) -----------

inline Eigen::Vector3d support(const Sphere& s, const Eigen::Vector3d& d) {
  return (s.radius + s.margin) * safe_unit(d);
}
inline Eigen::Vector3d support(const Box& s, const Eigen::Vector3d& d) {
  return BoxCore{s.half_extents}.support(d) + s.margin * safe_unit(d);
}
inline Eigen::Vector3d support(const Capsule& s, const Eigen::Vector3d& d) {
  return SegmentCore{s.half_length}.support(d) + (s.radius + s.margin) * safe_unit(d);
}
inline Eigen::Vector3d support(const Cylinder& s, const Eigen::Vector3d& d) {
  return CylinderCore{s.radius, s.half_length}.support(d) + s.margin * safe_unit(d);
}
inline Eigen::Vector3d support(const Cone& s, const Eigen::Vector3d& d) {
  return ConeCore{s.radius, s.half_length}.support(d) + s.margin * safe_unit(d);
}
inline Eigen::Vector3d support(const Polyhedron& s, const Eigen::Vector3d& d) {
  const hull::Index i = polyhedron_support(*s.hull, d, 0);
  return s.hull->offset() + s.hull->vertex(i) + s.margin * safe_unit(d);
}
inline Eigen::Vector3d support(const Shape& s, const Eigen::Vector3d& d) {
  return std::visit([&d](const auto& shape) { return support(shape, d); }, s);
}

}  // namespace hedra::collision
