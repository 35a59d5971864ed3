// EPA, the Expanding Polytope Algorithm (van den Bergen, GDC 2001; "Collision
// Detection in Interactive 3D Environments", 2003, 4.3.7): the signed
// penetration depth, normal and witnesses of two overlapping (or touching)
// convex shapes, over GJK's support concept, both in one common frame.
//
// A convex polytope P inside D = A - B around the origin grows from GJK's
// final simplex (reduced if flat, then grown into a tetrahedron; a flat D
// answers depth 0 at once). Each iteration takes the face f of P nearest the
// origin (plane n . x = d) and w = s_D(n): d <= depth <= n . w; it stops when
// the gap is within the tolerance, otherwise removes the faces that see w
// and fans new faces from w to the horizon. The answer is f's plane; an exit
// before convergence (cap, full, stalled) reports the smallest support value
// seen instead (a translation that certainly separates), with the bracket.
// Invariants (checked in debug builds): unit face normals; a closed
// two-manifold triangulation (each edge shared by two faces that know each
// other); an expansion applied only once validated (one simple horizon
// cycle, non-degenerate new faces), otherwise P unchanged and status
// stalled; fixed capacity, no heap (kEpaMaxVertices, kEpaMaxFaces);
// finite outputs and point_a - point_b = depth * normal on every exit.
// Derivations: docs/design.md, "EPA".
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <hedra/collision/detail/gjk.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>

#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

// Inlines every call in the function's body, for the hot loops where GCC
// leaves a small helper out of line: Polytope::expand's area_vector (through
// plane), tilted_revolution.hpp's piece_bound's accurate_hypot. Inlining
// changes no result (-ffp-contract=off: the same operations, the same bits).
// Only in optimised builds without assertions or sanitizers: there the
// recursive inlining reaches every unoptimised helper (Eigen's expression
// layers, the assertions' checks), and GCC 12 at -O1 with ASan took more
// than 6 GB and 15 minutes on query.cpp before it was stopped.
#if defined(__SANITIZE_ADDRESS__)
#  define HEDRA_SANITIZED 1
#elif defined(__has_feature)
#  if __has_feature(address_sanitizer)
#    define HEDRA_SANITIZED 1
#  endif
#endif
#if defined(__GNUC__) && defined(__OPTIMIZE__) && !HEDRA_ASSERTS_ENABLED && !defined(HEDRA_SANITIZED)
#  define HEDRA_FLATTEN __attribute__((flatten))
#else
#  define HEDRA_FLATTEN
#endif

namespace hedra::collision {

enum class EpaStatus {
  ok,              // converged: depth within tolerance, outputs valid
  max_iterations,  // the iteration cap was hit: best answer so far, see error_bound
  polytope_full,   // the fixed-capacity polytope ran out of vertices or faces: best so far
  stalled,         // rounding forbids a valid expansion while the gap is above tolerance: best so far
  degenerate,      // no usable start (empty simplex) or a non-finite support point
};

inline const char* to_string(EpaStatus status) {
  switch (status) {
    case EpaStatus::ok:
      return "ok";
    case EpaStatus::max_iterations:
      return "max_iterations";
    case EpaStatus::polytope_full:
      return "polytope_full";
    case EpaStatus::stalled:
      return "stalled";
    case EpaStatus::degenerate:
      return "degenerate";
  }
  return "unknown";
}

inline constexpr int kEpaMaxVertices = 128;
// A convex polytope with V vertices has at most 2V - 4 triangles.
inline constexpr int kEpaMaxFaces = 2 * kEpaMaxVertices;

struct EpaResult {
  EpaStatus status = EpaStatus::ok;
  // Signed: > 0 the shapes overlap; <= 0 only when the origin is on or a
  // hair outside D (GJK's simplex touched it from outside), then -depth is
  // the separation along `normal`.
  double depth = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  // unit, from A toward B, common frame
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  // witness on A, common frame
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  // point_a - point_b = depth * normal
  // Certified in exact arithmetic: |true signed depth - depth| <= error_bound.
  double error_bound = 0.0;
  int iterations = 0;
  int support_calls = 0;  // evaluations of the Minkowski difference's support
  int dimension = 3;      // affine dimension of D seen: 3, or 0..2 when D is flat (then depth = 0)
};

namespace epa_detail {

struct Vertex {
  Eigen::Vector3d w;  // a - b
  Eigen::Vector3d a;
  Eigen::Vector3d b;
};

template <class A, class B>
Vertex support(const A& a, const B& b, const Eigen::Vector3d& d) {
  Vertex v;
  v.a = a.support(d);
  v.b = b.support(-d);
  v.w = v.a - v.b;
  return v;
}

// w = a - b is finite exactly when a and b are (an infinite or NaN operand
// gives an infinite or NaN difference), and w also catches an overflow.
inline bool finite(const Vertex& v) { return v.w.allFinite(); }

// Parameter in [0, 1] of the point of segment p0 p1 closest to x.
inline double segment_parameter(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& x) {
  const Eigen::Vector3d e = p1 - p0;
  const double ee = e.squaredNorm();
  if (!(ee > 0.0)) return 0.0;
  return std::clamp((x - p0).dot(e) / ee, 0.0, 1.0);
}

// Barycentric coordinates (non-negative, summing to 1) of the point of
// triangle p0 p1 p2 closest to x, in `out`; returns whether x's projection
// on the triangle's plane lies inside the triangle (then `out` are its exact
// coordinates). The interior case uses signed areas against the triangle's
// own normal; outside (or for a degenerate triangle) the nearest of the
// three clamped edge projections.
inline bool triangle_barycentric(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                 const Eigen::Vector3d& x, std::array<double, 3>& out) {
  const Eigen::Vector3d n = area_vector(p0, p1, p2);
  const double nn = n.squaredNorm();
  if (nn > 0.0 && std::isfinite(nn)) {
    const std::array<double, 3> c = {n.dot((p1 - x).cross(p2 - x)), n.dot((p2 - x).cross(p0 - x)),
                                     n.dot((p0 - x).cross(p1 - x))};
    if (c[0] >= 0.0 && c[1] >= 0.0 && c[2] >= 0.0) {
      const double sum = c[0] + c[1] + c[2];
      if (sum > 0.0) {
        out = {c[0] / sum, c[1] / sum, c[2] / sum};
        return true;
      }
    }
  }
  const std::array<const Eigen::Vector3d*, 3> p = {&p0, &p1, &p2};
  out = {1.0, 0.0, 0.0};
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const double t = segment_parameter(*p[i], *p[j], x);
    const double d2 = ((1.0 - t) * *p[i] + t * *p[j] - x).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      out = {0.0, 0.0, 0.0};
      out[i] = 1.0 - t;
      out[j] = t;
    }
  }
  return false;
}

struct Face {
  std::array<int, 3> v;         // vertex indices, counter-clockwise seen from outside
  std::array<int, 3> adj;       // neighbour across edge i = (v[i], v[i+1])
  std::array<int, 3> adj_edge;  // index of that edge in the neighbour
  Eigen::Vector3d n;            // unit outward normal
  double d;                     // n . x on the face's plane: signed distance from the origin
  int removed_at;               // iteration that removed it (visibility mark); -1 while unmarked
  bool live;
};

struct HorizonEdge {
  int from, to;       // as seen from the removed side (counter-clockwise)
  int kept, edge;     // the kept face across the edge and the edge's index in it
  Eigen::Vector3d n;  // plane of the new face (from, to, w), computed while validating
  double d;
};

// The polytope and the work arrays of one query; lives on the caller's stack.
// Nothing is initialised up front: every slot is written before it is read.
struct Polytope {
  std::array<Vertex, kEpaMaxVertices> vertex;
  std::array<Face, kEpaMaxFaces> face;
  std::array<int, kEpaMaxFaces> free_face;  // removed face slots, reused first
  std::array<int, kEpaMaxFaces> removed;    // faces that see w, in visit order
  std::array<HorizonEdge, kEpaMaxFaces> horizon;
  std::array<int, kEpaMaxFaces> new_face;     // face created for horizon[i]
  std::array<int, kEpaMaxVertices> starting;  // horizon edge leaving a vertex
  // face[f].d for live faces, +infinity for removed ones: the nearest-face
  // scan runs over this contiguous array without testing `live`.
  std::array<double, kEpaMaxFaces> live_d;
  int vertex_count = 0;
  int face_end = 0;  // slots [0, face_end) have been used
  int free_count = 0;

  // (n, d) of the triangle p0 p1 p2; false when its area is zero or not finite.
  static bool plane(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2, Eigen::Vector3d& n,
                    double& d) {
    const Eigen::Vector3d c = area_vector(p0, p1, p2);
    const double len = std::sqrt(dot3(c, c));
    if (!(len > 0.0) || !std::isfinite(len)) return false;
    n = {c.x() / len, c.y() / len, c.z() / len};
    d = (dot3(n, p0) + dot3(n, p1) + dot3(n, p2)) / 3.0;
    HEDRA_ASSERT(is_unit(n));
    return true;
  }

  int allocate_face() {
    if (free_count > 0) return free_face[--free_count];
    if (face_end < kEpaMaxFaces) return face_end++;
    return -1;
  }
  int available_faces() const { return free_count + (kEpaMaxFaces - face_end); }

  // Face f's edge i is shared with exactly one neighbour, which holds it
  // reversed as its edge adj_edge[i] and points back: the closed
  // two-manifold the walks rely on.
  bool linked(int f) const {
    const Face& ff = face[f];
    for (int i = 0; i < 3; ++i) {
      const int g = ff.adj[i], j = ff.adj_edge[i];
      if (g < 0 || g >= face_end || j < 0 || j > 2 || !face[g].live) return false;
      const Face& fg = face[g];
      if (fg.adj[j] != f || fg.adj_edge[j] != i) return false;
      if (fg.v[j] != ff.v[(i + 1) % 3] || fg.v[(j + 1) % 3] != ff.v[i]) return false;
    }
    return true;
  }
  // Capacity and Euler's count: a closed triangulation of a sphere has 2V - 4
  // faces, V its vertices (vertices of removed regions no longer count, so
  // at most 2 vertex_count - 4 live faces).
  bool within_capacity() const {
    const int live = face_end - free_count;
    return vertex_count <= kEpaMaxVertices && face_end <= kEpaMaxFaces && free_count <= face_end && live >= 4 &&
           live <= 2 * vertex_count - 4 && live % 2 == 0;
  }

  static void link(Face& f, int i, int fid, Face& g, int j, int gid) {
    f.adj[i] = gid;
    f.adj_edge[i] = j;
    g.adj[j] = fid;
    g.adj_edge[j] = i;
  }

  // The tetrahedron vertex[0..3]; its signed volume must be positive (the
  // caller orders the vertices so). Returns false on a degenerate face.
  bool init_tetrahedron() {
    static constexpr int kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    // Edge i = (v[i], v[i+1]) of face f is edge kAdjEdge[f][i] of face
    // kAdj[f][i], traversed the other way (worked out from kFaces).
    static constexpr int kAdj[4][3] = {{3, 2, 1}, {0, 2, 3}, {0, 3, 1}, {1, 2, 0}};
    static constexpr int kAdjEdge[4][3] = {{2, 0, 0}, {2, 2, 0}, {1, 1, 1}, {2, 1, 0}};
    face_end = 0;
    free_count = 0;
    for (int f = 0; f < 4; ++f) {
      Face& face_f = face[f];
      face_f.v = {kFaces[f][0], kFaces[f][1], kFaces[f][2]};
      face_f.adj = {kAdj[f][0], kAdj[f][1], kAdj[f][2]};
      face_f.adj_edge = {kAdjEdge[f][0], kAdjEdge[f][1], kAdjEdge[f][2]};
      face_f.live = true;
      face_f.removed_at = -1;
      if (!plane(vertex[face_f.v[0]].w, vertex[face_f.v[1]].w, vertex[face_f.v[2]].w, face_f.n, face_f.d)) return false;
      live_d[f] = face_f.d;
    }
    face_end = 4;
    for (int f = 0; f < 4; ++f) HEDRA_ASSERT(linked(f));
    return true;
  }

  static constexpr int kShortScan = 16;
  // The first slot holding the smallest live_d (-1 when none is finite):
  // the minimum first, then the first slot equal to it. live_d holds no
  // NaN (face planes are finite), so the minimum is order-free and equality
  // with it (+0 == -0 included) marks exactly the slots a strict-less scan
  // could stop at; the first of them is the one it keeps.
  int closest_face() const {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double* d = live_d.data();
    int f = 0;
    double best_d = kInf;
    if (face_end < kShortScan) {  // one pass: fewer instructions on a few faces
      int best = -1;
      for (; f < face_end; ++f)
        if (d[f] < best_d) {
          best_d = d[f];
          best = f;
        }
      return best;
    }
#if defined(__SSE2__)
    __m128d m0 = _mm_set1_pd(kInf), m1 = m0;
    for (; f + 4 <= face_end; f += 4) {
      m0 = _mm_min_pd(m0, _mm_loadu_pd(d + f));
      m1 = _mm_min_pd(m1, _mm_loadu_pd(d + f + 2));
    }
    m0 = _mm_min_pd(m0, m1);
    best_d = std::min(_mm_cvtsd_f64(m0), _mm_cvtsd_f64(_mm_unpackhi_pd(m0, m0)));
#endif
    for (; f < face_end; ++f) best_d = std::min(best_d, d[f]);
    if (!(best_d < kInf)) return -1;
    f = 0;
#if defined(__SSE2__)
    const __m128d target = _mm_set1_pd(best_d);
    for (; f + 4 <= face_end; f += 4) {
      const __m128d lo = _mm_cmpeq_pd(_mm_loadu_pd(d + f), target);
      const __m128d hi = _mm_cmpeq_pd(_mm_loadu_pd(d + f + 2), target);
      if (_mm_movemask_pd(_mm_or_pd(lo, hi)) != 0) break;
    }
#endif
    for (; f < face_end; ++f)
      if (d[f] == best_d) return f;
    HEDRA_ASSERT(false);
    return -1;
  }

  enum class Expansion { done, full, invalid };

  // Adds `w` seen from face `start` (which must see it): removes every face
  // connected to `start` through faces that see w by more than `visible`,
  // and fans new faces from w to the horizon. Validates first; on failure
  // the polytope is unchanged.
  HEDRA_FLATTEN Expansion expand(int start, const Vertex& w, double visible, int stamp) {
    if (vertex_count >= kEpaMaxVertices) return Expansion::full;
    const int wid = vertex_count;
    // 1. The visibility walk, breadth first: `removed` is the queue and, at
    //    the end, the list of faces that see w (each face enters it at most
    //    once: it is marked when it enters).
    int removed_count = 0, horizon_count = 0;
    face[start].removed_at = stamp;
    removed[removed_count++] = start;
    for (int next = 0; next < removed_count; ++next) {
      const int f = removed[next];
      for (int i = 0; i < 3; ++i) {
        const int g = face[f].adj[i];
        Face& fg = face[g];
        if (fg.removed_at == stamp) continue;
        if (dot3(fg.n, w.w) - fg.d > visible) {
          fg.removed_at = stamp;
          removed[removed_count++] = g;
        } else {
          if (horizon_count >= kEpaMaxFaces) return unmark(removed_count, Expansion::full);
          HorizonEdge& e = horizon[horizon_count++];
          e.from = face[f].v[i];
          e.to = face[f].v[(i + 1) % 3];
          e.kept = g;
          e.edge = face[f].adj_edge[i];
        }
      }
    }
    // 2. Validation: one simple cycle (each horizon vertex starts exactly one
    //    edge, and following the edges from the first comes back after all
    //    of them), room for the new faces, no degenerate new face.
    if (horizon_count < 3) return unmark(removed_count, Expansion::invalid);
    for (int i = 0; i < horizon_count; ++i) starting[horizon[i].from] = starting[horizon[i].to] = -1;
    for (int i = 0; i < horizon_count; ++i) {
      if (starting[horizon[i].from] != -1) return unmark(removed_count, Expansion::invalid);
      starting[horizon[i].from] = i;
    }
    int at = 0, steps = 0;
    do {
      at = starting[horizon[at].to];
      ++steps;
    } while (at > 0 && steps <= horizon_count);
    if (at != 0 || steps != horizon_count) return unmark(removed_count, Expansion::invalid);
    if (available_faces() + removed_count < horizon_count) return unmark(removed_count, Expansion::full);
    for (int i = 0; i < horizon_count; ++i) {
      HorizonEdge& e = horizon[i];
      if (!plane(vertex[e.from].w, vertex[e.to].w, w.w, e.n, e.d)) return unmark(removed_count, Expansion::invalid);
    }
    // 3. Commit: free the removed faces, add the vertex, fan the new faces.
    for (int k = 0; k < removed_count; ++k) {
      face[removed[k]].live = false;
      live_d[removed[k]] = std::numeric_limits<double>::infinity();
      free_face[free_count++] = removed[k];
    }
    vertex[wid] = w;
    ++vertex_count;
    for (int i = 0; i < horizon_count; ++i) {
      const HorizonEdge& e = horizon[i];
      const int id = allocate_face();  // cannot fail: room checked above
      Face& nf = face[id];
      nf.v = {e.from, e.to, wid};
      nf.n = e.n;
      nf.d = e.d;
      live_d[id] = e.d;
      nf.live = true;
      nf.removed_at = -1;
      link(nf, 0, id, face[e.kept], e.edge, e.kept);
      new_face[i] = id;
    }
    // Edge 1 (to, w) of each new face meets edge 2 (w, to) of the face that
    // starts at `to`.
    for (int i = 0; i < horizon_count; ++i) {
      const int next = starting[horizon[i].to];
      link(face[new_face[i]], 1, new_face[i], face[new_face[next]], 2, new_face[next]);
    }
    // Only the new faces' links changed (a kept face's link to a removed one
    // now goes to the new face across the same edge).
    for (int i = 0; i < horizon_count; ++i) HEDRA_ASSERT(linked(new_face[i]));
    HEDRA_ASSERT(within_capacity());
    return Expansion::done;
  }

  // Undoes the marks of a rejected expansion.
  Expansion unmark(int removed_count, Expansion why) {
    for (int k = 0; k < removed_count; ++k) face[removed[k]].removed_at = -1;
    return why;
  }
};

// n or -n, whichever does not point away from `preferred`.
inline Eigen::Vector3d orient_normal(const Eigen::Vector3d& n, const Eigen::Vector3d& preferred) {
  return n.dot(preferred) < 0.0 ? Eigen::Vector3d(-n) : n;
}

// Fills the witnesses of `r` from up to three vertices and their barycentric
// weights, then moves both points by half the residual so that point_a -
// point_b = depth * normal holds to rounding. Returns q = sum lambda_i w_i,
// a point of P (hence of D).
inline Eigen::Vector3d set_witnesses(EpaResult& r, const Vertex* const* v, const double* lambda, int count) {
  Eigen::Vector3d pa = Eigen::Vector3d::Zero(), pb = Eigen::Vector3d::Zero(), q = Eigen::Vector3d::Zero();
  for (int i = 0; i < count; ++i) {
    pa += lambda[i] * v[i]->a;
    pb += lambda[i] * v[i]->b;
    q += lambda[i] * v[i]->w;
  }
  const Eigen::Vector3d residual = (pa - pb) - r.depth * r.normal;
  r.point_a = pa - 0.5 * residual;
  r.point_b = pb + 0.5 * residual;
  return q;
}

// The result for a flat D (dimension 0, 1 or 2, spanned by the first `k`
// points): q, the point of the simplex nearest the origin, is D's point
// nearest the origin (up to flat_tolerance). When |q| stands above rounding
// noise the origin is off D (touching from outside, within GJK's band) and
// the normal follows -q; otherwise it is D's normal (flat), a perpendicular
// (segment) or any unit vector (point), oriented toward `preferred`. The
// signed depth is n . q (<= 0 when the origin is outside).
inline EpaResult flat_result(const std::array<Vertex, 4>& p, int k, const Eigen::Vector3d& preferred, double noise,
                             double flat) {
  EpaResult r;
  r.dimension = k - 1;
  std::array<double, 3> lambda = {1.0, 0.0, 0.0};
  if (k == 2) {
    const double t = segment_parameter(p[0].w, p[1].w, Eigen::Vector3d::Zero());
    lambda = {1.0 - t, t, 0.0};
  } else if (k == 3) {
    triangle_barycentric(p[0].w, p[1].w, p[2].w, Eigen::Vector3d::Zero(), lambda);
  }
  Eigen::Vector3d q = lambda[0] * p[0].w;
  for (int i = 1; i < k; ++i) q += lambda[i] * p[i].w;
  Eigen::Vector3d toward = preferred.allFinite() ? preferred : Eigen::Vector3d::Zero();
  if (q.norm() > noise) toward = -q;
  Eigen::Vector3d n = Eigen::Vector3d::UnitX();
  if (k == 1) {
    if (toward.squaredNorm() > 0.0) n = toward.stableNormalized();
  } else if (k == 2) {
    const Eigen::Vector3d e = (p[1].w - p[0].w).stableNormalized();
    const Eigen::Vector3d perp = toward - toward.dot(e) * e;
    // Why the threshold: a direction (nearly) along the segment leaves only
    // rounding as its perpendicular part.
    n = perp.norm() > 1e-6 * toward.norm() ? Eigen::Vector3d(perp.stableNormalized()) : e.unitOrthogonal();
  } else {
    n = orient_normal(area_vector(p[0].w, p[1].w, p[2].w).stableNormalized(), toward);
  }
  r.normal = n;
  r.depth = n.dot(q);
  const Vertex* v[3] = {&p[0], &p[1], &p[2]};
  set_witnesses(r, v, lambda.data(), k);
  // D is within `flat` of the simplex's affine hull and holds q.
  r.error_bound = std::abs(r.depth - (-q.norm())) + flat;
  return r;
}

// Distance from x to the affine hull of the first k points (k = 1, 2, 3).
inline double affine_distance(const std::array<Vertex, 4>& p, int k, const Eigen::Vector3d& x) {
  if (k == 1) return (x - p[0].w).norm();
  if (k == 2) {
    const Eigen::Vector3d e = p[1].w - p[0].w;
    const double len = e.norm();
    return len > 0.0 ? (x - p[0].w).cross(e).norm() / len : (x - p[0].w).norm();
  }
  const Eigen::Vector3d n = area_vector(p[0].w, p[1].w, p[2].w);
  const double len = n.norm();
  return len > 0.0 ? std::abs(n.dot(x - p[0].w)) / len : affine_distance(p, 2, x);
}

// Reduces a simplex flatter than `flat` to the sub-simplex nearest the
// origin (ties: the largest), until every vertex stands at least `flat` off
// the affine hull of the others.
inline int reduce_simplex(std::array<Vertex, 4>& p, int k, double flat) {
  for (int round = 0; round < 4 && k > 1; ++round) {
    if (k == 4) {
      const Eigen::Vector3d e1 = p[1].w - p[0].w, e2 = p[2].w - p[0].w, e3 = p[3].w - p[0].w;
      const double det = e1.dot(e2.cross(e3));
      bool good = std::isfinite(det) &&
                  std::abs(det) > 64.0 * std::numeric_limits<double>::epsilon() * e1.norm() * e2.norm() * e3.norm();
      static constexpr int kOpposite[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
      for (int m = 0; m < 4 && good; ++m) {
        const Eigen::Vector3d c = area_vector(p[kOpposite[m][0]].w, p[kOpposite[m][1]].w, p[kOpposite[m][2]].w);
        good = std::abs(det) > flat * c.norm();  // height of vertex m = |det| / |c|
      }
      if (good) return 4;
      int best = 0;
      double best_d2 = std::numeric_limits<double>::infinity(), best_area = -1.0;
      for (int m = 0; m < 4; ++m) {
        const Vertex& q0 = p[kOpposite[m][0]];
        const Vertex& q1 = p[kOpposite[m][1]];
        const Vertex& q2 = p[kOpposite[m][2]];
        std::array<double, 3> l;
        triangle_barycentric(q0.w, q1.w, q2.w, Eigen::Vector3d::Zero(), l);
        const double d2 = (l[0] * q0.w + l[1] * q1.w + l[2] * q2.w).squaredNorm();
        const double area = area_vector(q0.w, q1.w, q2.w).norm();
        if (d2 < best_d2 - flat * flat || (d2 <= best_d2 + flat * flat && area > best_area)) {
          best = m;
          best_d2 = std::min(best_d2, d2);
          best_area = area;
        }
      }
      const std::array<Vertex, 4> old = p;
      for (int i = 0; i < 3; ++i) p[i] = old[kOpposite[best][i]];
      k = 3;
    } else if (k == 3) {
      const Eigen::Vector3d c = area_vector(p[0].w, p[1].w, p[2].w);
      const double longest = std::max({(p[1].w - p[0].w).norm(), (p[2].w - p[1].w).norm(), (p[0].w - p[2].w).norm()});
      if (std::isfinite(c.norm()) && c.norm() > flat * longest &&
          c.norm() > 64.0 * std::numeric_limits<double>::epsilon() * longest * longest)
        return 3;
      int best = 0;
      double best_d2 = std::numeric_limits<double>::infinity(), best_len = -1.0;
      for (int m = 0; m < 3; ++m) {
        const Vertex& q0 = p[m];
        const Vertex& q1 = p[(m + 1) % 3];
        const double t = segment_parameter(q0.w, q1.w, Eigen::Vector3d::Zero());
        const double d2 = ((1.0 - t) * q0.w + t * q1.w).squaredNorm();
        const double len = (q1.w - q0.w).norm();
        if (d2 < best_d2 - flat * flat || (d2 <= best_d2 + flat * flat && len > best_len)) {
          best = m;
          best_d2 = std::min(best_d2, d2);
          best_len = len;
        }
      }
      const std::array<Vertex, 4> old = p;
      p[0] = old[best];
      p[1] = old[(best + 1) % 3];
      k = 2;
    } else {  // k == 2
      if ((p[1].w - p[0].w).norm() > flat) return 2;
      if (p[1].w.squaredNorm() < p[0].w.squaredNorm()) p[0] = p[1];
      k = 1;
    }
  }
  return k;
}

// The tolerances of one query, from the settings and the pair's size.
struct Tolerances {
  double size;      // the pair's scale (0 when not finite and positive)
  double flat;      // extents below it count as zero
  double absolute;  // the absolute convergence tolerance
  double visible;   // how far above a face w must be to remove it
  double noise;     // rounding of a point of D
};

inline Tolerances tolerances_of(const EpaSettings& settings, double scale) {
  Tolerances t;
  t.size = std::isfinite(scale) && scale > 0.0 ? scale : 0.0;
  t.flat = settings.flat_tolerance * t.size;
  t.absolute = settings.absolute_tolerance * t.size;
  t.visible = 1e-3 * t.absolute;
  t.noise = 64.0 * std::numeric_limits<double>::epsilon() * t.size;
  return t;
}

// Phase 1: GJK's simplex reduced (reduce_simplex), then grown along its
// degenerate directions into a tetrahedron of positive volume in `poly`:
// the first candidate that stands comfortably off the affine hull (1e-3 of
// the size) is taken, otherwise the farthest of all if it beats `flat`.
// Returns false when `r` is already the answer (degenerate input, or a flat
// D whose answer flat_result gives).
template <class A, class B>
bool start_polytope(const A& a, const B& b, const GjkSimplex& simplex, const Eigen::Vector3d& preferred,
                    const Tolerances& tol, Polytope& poly, EpaResult& r) {
  std::array<Vertex, 4> p;
  int k = std::clamp(simplex.size, 0, 4);
  for (int i = 0; i < k; ++i) p[i] = {simplex.w[i], simplex.a[i], simplex.b[i]};
  for (int i = 0; i < k; ++i)
    if (!finite(p[i])) k = 0;
  if (k == 0) {
    // Why: GJK failed before the loop (non-finite input); nothing to expand.
    r.status = EpaStatus::degenerate;
    return false;
  }
  k = reduce_simplex(p, k, tol.flat);
  while (k < 4) {
    // The degenerate directions: any axis for a point, perpendiculars for
    // a segment, +-normal for a triangle.
    std::array<Eigen::Vector3d, 8> dirs;
    int count = 0;
    if (k == 1) {
      for (int axis = 0; axis < 3; ++axis) {
        dirs[count++] = Eigen::Vector3d::Unit(axis);
        dirs[count++] = -Eigen::Vector3d::Unit(axis);
      }
    } else if (k == 2) {
      const Eigen::Vector3d e = (p[1].w - p[0].w).stableNormalized();
      const Eigen::Vector3d u = e.unitOrthogonal(), v = e.cross(u);
      for (const Eigen::Vector3d& d :
           {u, v, Eigen::Vector3d((u + v).stableNormalized()), Eigen::Vector3d((u - v).stableNormalized())}) {
        dirs[count++] = d;
        dirs[count++] = -d;
      }
    } else {
      const Eigen::Vector3d n = area_vector(p[0].w, p[1].w, p[2].w).stableNormalized();
      dirs[count++] = n;
      dirs[count++] = -n;
    }
    Vertex best = p[0];
    double best_height = -1.0;
    for (int i = 0; i < count; ++i) {
      const Vertex s = support(a, b, dirs[i]);
      ++r.support_calls;
      if (!finite(s)) {
        r.status = EpaStatus::degenerate;
        return false;
      }
      const double height = affine_distance(p, k, s.w);
      if (height > best_height) {
        best_height = height;
        best = s;
      }
      if (best_height > 1e-3 * tol.size) break;
    }
    if (!(best_height > tol.flat)) {
      r = flat_result(p, k, preferred, tol.noise, tol.flat);
      return false;
    }
    p[k++] = best;
  }
  const double det = (p[1].w - p[0].w).dot((p[2].w - p[0].w).cross(p[3].w - p[0].w));
  if (det < 0.0) std::swap(p[1], p[2]);
  for (int i = 0; i < 4; ++i) poly.vertex[i] = p[i];
  poly.vertex_count = 4;
  if (!poly.init_tetrahedron()) {
    // Unreachable after reduce_simplex (every face has area), kept as a
    // guard: report the flat answer rather than divide by zero.
    r = flat_result(p, 3, preferred, tol.noise, tol.flat);
    return false;
  }
  return true;
}

// The smallest support value seen, its direction and support point: an
// upper bound on the depth, and a valid separating translation.
struct BestSupport {
  double upper = std::numeric_limits<double>::infinity();
  Eigen::Vector3d n = Eigen::Vector3d::UnitX();
  Vertex s;
};

// Phase 2: the expansion, until the nearest face's plane is supporting
// within the tolerance or a cap, a full polytope or rounding stops it (the
// status in `r`). Returns the nearest face at the end.
template <class A, class B>
int expand_polytope(const A& a, const B& b, const EpaSettings& settings, const Tolerances& tol, Polytope& poly,
                    BestSupport& best_support, EpaResult& r) {
  for (;;) {
    const int best = poly.closest_face();
    const Face& f = poly.face[best];
    if (r.iterations >= settings.max_iterations) {
      r.status = EpaStatus::max_iterations;
      return best;
    }
    ++r.iterations;
    const Vertex s = support(a, b, f.n);
    ++r.support_calls;
    if (!finite(s)) {
      // Why: a support mapping returned NaN/inf (corrupt shape or pose).
      r.status = EpaStatus::degenerate;
      return best;
    }
    const double h = dot3(f.n, s.w);
    if (h < best_support.upper) {
      best_support.upper = h;
      best_support.n = f.n;
      best_support.s = s;
    }
    if (h - f.d <= std::max(settings.relative_tolerance * std::max(f.d, 0.0), tol.absolute)) return best;
    bool duplicate = false;
    for (int i = 0; i < poly.vertex_count; ++i) {
      const Eigen::Vector3d& v = poly.vertex[i].w;
      if (v.x() == s.w.x() && v.y() == s.w.y() && v.z() == s.w.z()) {
        duplicate = true;
        break;
      }
    }
    if (duplicate) {
      // Why: a vertex of P beyond one of P's supporting planes by more than
      // the tolerance means rounding made P non-convex; adding it again
      // would make a zero-area face.
      r.status = EpaStatus::stalled;
      return best;
    }
    const auto expansion = poly.expand(best, s, tol.visible, r.iterations);
    if (expansion == Polytope::Expansion::full) {
      r.status = EpaStatus::polytope_full;
      return best;
    }
    if (expansion == Polytope::Expansion::invalid) {
      r.status = EpaStatus::stalled;
      return best;
    }
  }
}

// Phase 3a: the face whose plane answers. The projection d n of the origin
// normally lies in the nearest face; when it falls just outside (in a
// coplanar neighbour of a triangulated face of D), a face within the
// tolerance band whose own projection is interior gives the same plane with
// exact witnesses and a tight bound. `lambda`: the barycentric coordinates
// of the chosen face's projection.
template <class A, class B>
const Face* answering_face(const A& a, const B& b, const EpaSettings& settings, const Tolerances& tol,
                           const Polytope& poly, int best, std::array<double, 3>& lambda, EpaResult& r) {
  const Face* chosen = &poly.face[best];
  if (triangle_barycentric(poly.vertex[chosen->v[0]].w, poly.vertex[chosen->v[1]].w, poly.vertex[chosen->v[2]].w,
                           chosen->d * chosen->n, lambda))
    return chosen;
  const double band = chosen->d + std::max(settings.relative_tolerance * std::abs(chosen->d), tol.absolute);
  for (int g = 0; g < poly.face_end; ++g) {
    const Face& fg = poly.face[g];
    std::array<double, 3> lg;
    if (!fg.live || g == best || fg.d > band) continue;
    if (triangle_barycentric(poly.vertex[fg.v[0]].w, poly.vertex[fg.v[1]].w, poly.vertex[fg.v[2]].w, fg.d * fg.n, lg)) {
      // Its plane must also be supporting within the tolerance (on a
      // curved D a face of the band may not have been tested yet): one
      // support call decides.
      const Vertex sg = support(a, b, fg.n);
      ++r.support_calls;
      if (!finite(sg) || fg.n.dot(sg.w) - fg.d > band - chosen->d) continue;
      lambda = lg;
      return &fg;
    }
  }
  return chosen;
}

// Phase 3b: the answer from face f and its bounds on the true signed depth
// D* (exact arithmetic): D* <= upper (a support value); if the nearest
// plane has d >= 0 every face does, the origin is inside P and D* >= d;
// otherwise q, a point of P (so of D), is |q| from the origin and D* >= -|q|.
template <class Poly>
void face_answer(const Poly& poly, const Face& f, double nearest_d, const std::array<double, 3>& lambda,
                 const BestSupport& best_support, EpaResult& r) {
  r.depth = f.d;
  r.normal = f.n;
  const Vertex* v[3] = {&poly.vertex[f.v[0]], &poly.vertex[f.v[1]], &poly.vertex[f.v[2]]};
  const Eigen::Vector3d q = set_witnesses(r, v, lambda.data(), 3);
  const double lower = nearest_d >= 0.0 ? nearest_d : -q.norm();
  const double upper = best_support.upper;
  if (!std::isfinite(upper)) {
    // No support value yet (max_iterations = 0): the face answer, no bound.
    r.error_bound = std::numeric_limits<double>::max();
  } else if (r.status == EpaStatus::ok) {
    r.error_bound = std::max({upper - f.d, f.d - lower, 0.0});
  } else if (r.status != EpaStatus::degenerate) {
    // Not converged (cap, full, stalled): the face plane d is only a lower
    // bound, and moving B by d n would leave the shapes overlapping. The
    // best support direction is a valid separating translation, and where
    // the depth is nearly the same over many directions (a deep ball, a
    // centre on a cylinder's axis: EPA's slow cases) it is by far the
    // better estimate: report it. Witnesses: the support points, moved
    // apart along the supporting planes by half their lateral offset each.
    r.depth = upper;
    r.normal = best_support.n;
    const Eigen::Vector3d lateral = best_support.s.w - upper * best_support.n;
    r.point_a = best_support.s.a - 0.5 * lateral;
    r.point_b = best_support.s.b + 0.5 * lateral;
    r.error_bound = std::max(upper - lower, 0.0);
  } else {
    r.error_bound = std::numeric_limits<double>::max();
  }
}

}  // namespace epa_detail

// Penetration depth of A and B (support types in one common frame) whose
// overlap (or touching) GJK has established: `simplex` is GJK's final simplex
// (its hull contains or touches the origin), `scale` the shapes' size,
// `preferred` a direction from A toward B used only to orient the normal of
// a flat D (e.g. B's centre minus A's).
template <class A, class B>
EpaResult epa_penetration(const A& a, const B& b, const GjkSimplex& simplex, double scale,
                          const Eigen::Vector3d& preferred, const EpaSettings& settings = {}) {
  EpaResult r;
  const epa_detail::Tolerances tol = epa_detail::tolerances_of(settings, scale);
  epa_detail::Polytope poly;
  if (!epa_detail::start_polytope(a, b, simplex, preferred, tol, poly, r)) return r;
  epa_detail::BestSupport best_support;
  best_support.s = poly.vertex[0];
  const int best = epa_detail::expand_polytope(a, b, settings, tol, poly, best_support, r);
  std::array<double, 3> lambda;
  const epa_detail::Face* f = epa_detail::answering_face(a, b, settings, tol, poly, best, lambda, r);
  epa_detail::face_answer(poly, *f, poly.face[best].d, lambda, best_support, r);
  HEDRA_ASSERT(r.status == EpaStatus::degenerate || (is_unit(r.normal) && std::isfinite(r.depth)));
  return r;
}

}  // namespace hedra::collision
