// SAT's certified depth for overlapping polytopes (see sat_depth.hpp).
//
// Frame: A's core frame, B placed by (R, t). A candidate axis n (unit, A
// toward B) separates by s(n) = min_B n.b - max_A n.a; over the normals of
// the faces of D = B - A the largest s is minus the depth. Error terms,
// each a bound on |computed s - s(true axis)|:
//   * a face axis: rounding, 16 eps (|t| + R_A + R_B);
//   * an edge axis e_A x e_B: the cross product of the rounded edges is off
//     by about 2 eps |e_A||e_B|, so the unit axis by 2 eps / sin(angle), and
//     s by that times |p_B - p_A|: 16 eps |p_B - p_A| / sin + rounding;
//   * an edge pair within kTinySine of parallel is not measured: the face of
//     D it spans is a parallelogram of width |e| sin, and a neighbouring face
//     (measured) lies within that width of the same depth: 2 (|e_A| + |e_B|)
//     sin is added to the bound.
// Witness points: a face axis's incident support vertex projected onto the
// reference face when it lands inside; otherwise a point of the overlap of
// the reference face and the incident feature (the incident face's vertices
// within tol of the support level) seen along the axis. An edge axis: the
// closest points of the two edges. No allocation: fixed buffers of
// kMaxDegree vertices; a larger face leaves the answer to EPA.
#include "sat_depth.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <hedra/hull/assert.hpp>
#include <limits>

#include "segment_box.hpp"

namespace hedra::collision::detail {

namespace {

using Vec = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kTinySine = 1e-13;
constexpr std::size_t kMaxDegree = 64;

// The running answer: the largest separation, its error, the smallest
// certified lower bound of the depth, and the slack of skipped slivers.
struct Tally {
  SatAxis best;
  double best_error = 0.0;
  double lower = std::numeric_limits<double>::infinity();
  double slack = 0.0;
  int measured = 0;
  Vec best_pa = Vec::Zero(), best_ea = Vec::Zero(), best_pb = Vec::Zero(), best_eb = Vec::Zero();

  // An edge axis replaces a face axis only when it separates by more than
  // both errors: an edge axis along a face normal (a box turned about its
  // face normal: e_x x f_z is -e_y) ties with the face by rounding, and
  // the face's witnesses are the ones on the surfaces.
  bool add(const SatAxis& axis, double error) {
    ++measured;
    lower = std::min(lower, -axis.separation - error);
    const bool edge_over_face = axis.kind == SatAxisKind::edge && best.kind != SatAxisKind::edge;
    const double bias = edge_over_face ? error + best_error : 0.0;
    if (!(axis.separation > best.separation + bias)) return false;
    best = axis;
    best_error = error;
    return true;
  }
};

// Two boxes: the 15 axes, each |n.t| - h_A . |n| - h_B . |R^T n|.
void box_axes(const Vec& ha, const Vec& hb, const RelativePose& rel, double rounding, Tally& tally) {
  const Eigen::Matrix3d& r = rel.rotation;
  const Vec& t = rel.translation;
  const auto measure = [&](const Vec& n, double sine, SatAxisKind kind, int i, int j) {
    const double nt = n.dot(t);
    const double s = (std::abs(nt) - ha.dot(n.cwiseAbs()) - hb.dot((r.transpose() * n).cwiseAbs())) / sine;
    SatAxis axis;
    axis.kind = kind;
    axis.separation = s;
    axis.normal = (nt >= 0.0 ? 1.0 : -1.0) * n / sine;
    axis.feature_a = static_cast<hull::Index>(i);  // box axis indices here; features are found later
    axis.feature_b = static_cast<hull::Index>(j);
    tally.add(axis, kind == SatAxisKind::edge ? rounding / sine : rounding);
  };
  for (int k = 0; k < 3; ++k) measure(Vec::Unit(k), 1.0, SatAxisKind::face_a, k, -1);
  for (int k = 0; k < 3; ++k) measure(r.col(k), 1.0, SatAxisKind::face_b, -1, k);
  if (tally.best.separation > 0.0) return;  // apart: the caller asks GJK
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vec n = Vec::Unit(i).cross(r.col(j));
      const double sine = n.norm();
      if (!(sine > kTinySine)) {
        tally.slack = std::max(tally.slack, 4.0 * (ha[i] + hb[j]) * sine);
        continue;
      }
      measure(n, sine, SatAxisKind::edge, i, j);
    }
}

// ---- witness points ---------------------------------------------------------

// A polygon seen along n in the plane frame (e1, e2), with its 3D points.
struct Polygon {
  std::array<Vec, kMaxDegree> p;
  std::array<Vec2, kMaxDegree> xy;
  std::size_t count = 0;
};

double cross2(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

// Inside a convex polygon (either orientation) within tol (2D).
bool inside(const Polygon& poly, const Vec2& q, double tol) {
  if (poly.count < 3) return false;
  double area = 0.0;
  for (std::size_t i = 0; i < poly.count; ++i) area += cross2(poly.xy[i], poly.xy[(i + 1) % poly.count]);
  const double sign = area >= 0.0 ? 1.0 : -1.0;
  for (std::size_t i = 0; i < poly.count; ++i) {
    const Vec2 edge = poly.xy[(i + 1) % poly.count] - poly.xy[i];
    if (sign * cross2(edge, q - poly.xy[i]) < -tol * edge.norm()) return false;
  }
  return true;
}

// The reference face f of `ref` (its frame), the incident polytope mapped
// into it by x -> m x + c: a point on each surface with on_inc - on_ref
// along the face normal, or false.
bool face_witness(const SatPolytope& ref, hull::Index f, const SatPolytope& inc, const Eigen::Matrix3d& m, const Vec& c,
                  double tol, Vec& on_ref, Vec& on_inc) {
  const hull::Plane& plane = ref.plane(f);
  const Vec& n = plane.normal;
  const hull::HalfEdgeMesh& mr = *ref.mesh;
  const hull::HalfEdgeMesh& mi = *inc.mesh;
  const Vec e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  const auto to2 = [&](const Vec& x) { return Vec2(e1.dot(x), e2.dot(x)); };
  Polygon face;
  for (const hull::Index v : mr.face_vertices(f)) {
    if (face.count == kMaxDegree) return false;
    face.p[face.count] = ref.vertex(v);
    face.xy[face.count] = to2(face.p[face.count]);
    ++face.count;
  }
  const hull::Index v = inc.support(-(m.transpose() * n));
  const Vec xv = m * inc.vertex(v) + c;
  const double level = n.dot(xv);
  const auto finish = [&](const Vec& point) {
    on_inc = point;
    on_ref = point - (n.dot(point) - plane.offset) * n;
    return true;
  };
  if (inside(face, to2(xv), tol)) return finish(xv);
  // The incident face: around v, the one facing most against n; its
  // vertices within tol of the support level (a contiguous chain).
  hull::Index g = hull::kInvalidIndex;
  double most = std::numeric_limits<double>::infinity();
  for (const hull::Index h : mi.vertex_faces(v)) {
    const double along = n.dot(m * inc.plane(h).normal);
    if (along < most) most = along, g = h;
  }
  if (g == hull::kInvalidIndex) return false;
  Polygon feature;
  for (const hull::Index w : mi.face_vertices(g)) {
    const Vec x = m * inc.vertex(w) + c;
    if (n.dot(x) > level + tol) continue;
    if (feature.count == kMaxDegree) return false;
    feature.p[feature.count] = x;
    feature.xy[feature.count] = to2(x);
    ++feature.count;
  }
  Vec sum = Vec::Zero();
  int found = 0;
  for (std::size_t i = 0; i < feature.count; ++i)
    if (inside(face, feature.xy[i], tol)) sum += feature.p[i], ++found;
  if (found == 0 && feature.count >= 3) {  // the reference face's corners on the incident face
    const Vec ng = m * inc.plane(g).normal;
    const double denom = ng.dot(n);
    for (std::size_t i = 0; i < face.count && denom < 0.0; ++i)
      if (inside(feature, face.xy[i], tol)) {
        const Vec& p = face.p[i];
        sum += p + ((ng.dot(feature.p[0]) - ng.dot(p)) / denom) * n, ++found;
      }
  }
  if (found == 0 && feature.count >= 2) {  // edge crossings
    const std::size_t closing = feature.count >= 3 ? feature.count : 1;
    for (std::size_t i = 0; i < closing; ++i) {
      const Vec2& p0 = feature.xy[i];
      const Vec2 d = feature.xy[(i + 1) % feature.count] - p0;
      for (std::size_t k = 0; k < face.count; ++k) {
        const Vec2& q0 = face.xy[k];
        const Vec2 e = face.xy[(k + 1) % face.count] - q0;
        const double den = cross2(d, e);
        if (den == 0.0) continue;
        const double u = cross2(q0 - p0, e) / den, w = cross2(q0 - p0, d) / den;
        if (u < 0.0 || u > 1.0 || w < 0.0 || w > 1.0) continue;
        sum += feature.p[i] + u * (feature.p[(i + 1) % feature.count] - feature.p[i]), ++found;
      }
    }
  }
  if (found == 0) return false;
  return finish(sum / found);
}

// The box-box axis's features on the meshes: the face along the normal,
// or the support edges along it.
void box_features(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, Tally& tally) {
  SatAxis& axis = tally.best;
  const Vec& n = axis.normal;
  const Vec nb = -(rel.rotation.transpose() * n);
  if (axis.kind == SatAxisKind::face_a) {
    const int k = static_cast<int>(axis.feature_a);
    axis.feature_a = static_cast<hull::Index>(2 * k + (n[k] > 0.0 ? 1 : 0));
    axis.feature_b = hull::kInvalidIndex;
    return;
  }
  if (axis.kind == SatAxisKind::face_b) {
    const int k = static_cast<int>(axis.feature_b);
    axis.feature_b = static_cast<hull::Index>(2 * k + (nb[k] > 0.0 ? 1 : 0));
    axis.feature_a = hull::kInvalidIndex;
    return;
  }
  const int i = static_cast<int>(axis.feature_a), j = static_cast<int>(axis.feature_b);
  axis.feature_a = axis.feature_b = hull::kInvalidIndex;  // the edges are told by their end points below
  const hull::Index va = a.support(n) & ~(1u << i);
  const hull::Index vb = b.support(nb) & ~(1u << j);
  tally.best_pa = a.vertex(va);
  tally.best_ea = a.vertex(va | (1u << i)) - tally.best_pa;
  tally.best_pb = rel.rotation * b.vertex(vb) + rel.translation;
  tally.best_eb = rel.rotation * (b.vertex(vb | (1u << j)) - b.vertex(vb));
}

bool witnesses(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, const Tally& tally, double tol,
               SatDepth& out) {
  const SatAxis& axis = tally.best;
  if (axis.kind == SatAxisKind::face_a)
    return face_witness(a, axis.feature_a, b, rel.rotation, rel.translation, tol, out.point_a, out.point_b);
  if (axis.kind == SatAxisKind::face_b) {
    const Eigen::Matrix3d rt = rel.rotation.transpose();
    Vec on_b, on_a;
    if (!face_witness(b, axis.feature_b, a, rt, -(rt * rel.translation), tol, on_b, on_a)) return false;
    out.point_a = rel.rotation * on_a + rel.translation;
    out.point_b = rel.rotation * on_b + rel.translation;
    return true;
  }
  closest_segment_points(tally.best_pa, tally.best_ea, tally.best_pb, tally.best_eb, out.point_a, out.point_b);
  // Clamped to an edge's end: the lines' closest points lie off the edges,
  // the pair is not where the depth is attained.
  return (out.point_b - out.point_a - axis.separation * axis.normal).norm() <= tol;
}

}  // namespace

bool sat_depth(const Box& box_a, const Box& box_b, const RelativePose& rel, double scale, const EpaSettings& settings,
               SatDepth& out) {
  const Vec& ha = box_a.half_extents;
  const Vec& hb = box_b.half_extents;
  if (!(ha.minCoeff() > 0.0) || !(hb.minCoeff() > 0.0)) return false;  // flat: no solid
  const double rounding = 16.0 * kEps * (rel.translation.norm() + ha.norm() + hb.norm());
  Tally tally;
  box_axes(ha, hb, rel, rounding, tally);
  if (tally.best.separation > 0.0) return false;  // apart: distance()'s answer, bit for bit (GJK)
  if (tally.best.kind == SatAxisKind::none || !std::isfinite(tally.best.separation)) return false;
  // The boxes' vertices and planes, for the features and the witnesses.
  BoxPolytopeStorage storage_a, storage_b;
  const SatPolytope a = sat_polytope(box_a, storage_a), b = sat_polytope(box_b, storage_b);
  box_features(a, b, rel, tally);
  const double s = tally.best.separation;
  out.distance = s;
  out.normal = tally.best.normal;
  out.axis = tally.best;
  out.axes_tested = tally.measured;
  const double tolerance = std::max(settings.relative_tolerance * std::abs(s), settings.absolute_tolerance * scale);
  HEDRA_ASSERT(std::abs(out.normal.squaredNorm() - 1.0) <= 1e-9);
  const double lower = std::min(tally.lower, -s - tally.slack);
  out.error_bound = std::max(-s + tally.best_error - lower, 0.0);
  return out.error_bound <= tolerance && witnesses(a, b, rel, tally, tolerance, out);
}

}  // namespace hedra::collision::detail
