// Box-box face contacts (the box path's half that clips, see box_box.cpp):
// the incident face's corners clipped by the reference face's side planes
// with hull::clip_polygon's tolerance semantics, each point carrying where it
// came from (an incident corner, or a crossing on incident edge k) so its
// feature id needs no search; the reduction to four; the last frame's points
// held as manifold.cpp holds them; a rounded box's exits along a normal.
// Every step is manifold.cpp's for the general polytope, written for the box.
#include <algorithm>
#include <cmath>
#include <hedra/hull/assert.hpp>
#include <limits>

#include "box_box_detail.hpp"
#include "contact_choice.hpp"

namespace hedra::collision::detail::box_box {

const BoxTopology& topology() {
  static const BoxTopology t = [] {
    const hull::HalfEdgeMesh& m = unit_box_mesh();
    BoxTopology out{};
    out.edge_between.fill(hull::kInvalidIndex);
    HEDRA_ASSERT(m.face_count() == 6 && m.vertex_count() == 8 && m.half_edge_count() == 24);
    for (Index f = 0; f < 6; ++f) {
      int k = 0;
      for (const Index e : m.face_edges(f)) {
        HEDRA_ASSERT(k < 4);
        out.face_edge[f][k] = e;
        out.face_vertex[f][k++] = m.origin(e);
      }
      out.normal[f] = m.plane(f).normal;
      HEDRA_ASSERT(out.normal[f].cwiseAbs().sum() == 1.0);  // exactly an axis vector
      for (int j = 0; j < 4; ++j) {  // the edge's direction x the normal: one axis, any half extents
        const Vec c =
            (corner(Vec::Ones(), out.face_vertex[f][(j + 1) & 3]) - corner(Vec::Ones(), out.face_vertex[f][j]))
                .cross(out.normal[f]);
        const int i = c.x() != 0.0 ? 0 : (c.y() != 0.0 ? 1 : 2);
        HEDRA_ASSERT(c.squaredNorm() == c[i] * c[i]);
        out.side_axis[f][j] = i;
        out.side_sign[f][j] = c[i] > 0.0 ? 1.0 : -1.0;
      }
    }
    for (Index v = 0; v < 8; ++v) {
      int k = 0;
      for (const Index g : m.vertex_faces(v)) {
        HEDRA_ASSERT(k < 3);
        out.vertex_face[v][k++] = g;
      }
    }
    for (Index e = 0; e < 24; ++e) {
      out.twin[e] = m.twin(e);
      out.origin[e] = m.origin(e);
      out.edge_between[8 * m.origin(e) + m.destination(e)] = e;
    }
    return out;
  }();
  return t;
}

namespace {

// hull::clip_polygon for a unit plane n . x = d, label 4 + j (the same
// classification and crossings): keeps the part with n . x - d <= tol.
// False on a non-finite crossing (the general path then answers).
// `dist[i]`: in.p[i]'s signed distance n . x - d.
bool clip(const Polygon& in, const double* dist, int label, double tol, Polygon& out) {
  out.count = 0;
  const auto side = [&](double s) { return s > tol ? 1 : (s < -tol ? -1 : 0); };
  const auto crossing = [](const Vec& b, double db, const Vec& f, double df) {
    const double t = db / (db - df);
    return Vec(b + t * (f - b));
  };
  // Points carried over are finite (run() checks the incident corners):
  // only crossings are checked.
  const auto emit = [&](const Vec& x, int origin, int next, bool crossed = false) {
    if ((crossed && !x.allFinite()) || out.count == kMaxPolygon) return false;
    out.p[out.count] = x;
    out.origin[out.count] = origin;
    out.next[out.count++] = next;
    return true;
  };
  if (in.count == 0) return true;
  if (in.count <= 2) {
    const double d0 = dist[0];
    const int s0 = side(d0);
    if (in.count == 1) return s0 == 1 || emit(in.p[0], in.origin[0], in.next[0]);
    const double d1 = dist[1];
    const int s1 = side(d1);
    const int on = 8 + in.next[0];
    if (s0 != 1 && !emit(in.p[0], in.origin[0], in.next[0])) return false;
    if (s0 == -1 && s1 == 1 && !emit(crossing(in.p[0], d0, in.p[1], d1), on, in.next[0], true)) return false;
    if (s0 == 1 && s1 == -1 && !emit(crossing(in.p[1], d1, in.p[0], d0), on, in.next[0], true)) return false;
    return s1 == 1 || emit(in.p[1], in.origin[1], in.next[1]);
  }
  double d_cur = dist[0];
  for (int i = 0; i < in.count; ++i) {
    const int j = i + 1 == in.count ? 0 : i + 1;
    const double d_next = dist[j];
    const int s_cur = side(d_cur), s_next = side(d_next);
    const int on = 8 + in.next[i];
    if (s_cur != 1 && !emit(in.p[i], in.origin[i], s_cur == 0 && s_next == 1 ? label : in.next[i])) return false;
    if (s_cur == -1 && s_next == 1) {
      if (!emit(crossing(in.p[i], d_cur, in.p[j], d_next), on, label, true)) return false;
    } else if (s_cur == 1 && s_next == -1) {
      if (!emit(crossing(in.p[j], d_next, in.p[i], d_cur), on, in.next[i], true)) return false;
    }
    d_cur = d_next;
  }
  return true;
}

// The first of `count` values within `tie` of the largest, `best`
// (manifold.cpp's first_near_largest; the caller takes the largest as it
// fills the values, in the same order).
int first_near_largest(const double* value, int count, double tie, double best) {
  for (int i = 0; i < count; ++i)
    if (value[i] >= best - tie) return i;
  return 0;
}

}  // namespace

// manifold.cpp's reduce: the deepest, the farthest from it, the largest
// positive and negative triangle areas about n, each the first within ties.
// Points p[i] (on B) with their separations s[i].
int reduce(const Vec* p, const double* s, int count, const Vec& n, double depth_tie, double length_tie,
           std::array<int, kMaxContactPoints>& keep) {
  if (count == 0) return 0;
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  std::array<double, kMaxPolygon> value;
  double best = kNone;
  for (int i = 0; i < count; ++i) best = std::max(best, value[i] = -s[i]);
  const int i0 = first_near_largest(value.data(), count, depth_tie, best);
  keep[0] = i0;
  if (count == 1) return 1;
  const Vec p0 = p[i0];
  best = kNone;
  for (int i = 0; i < count; ++i) best = std::max(best, value[i] = (p[i] - p0).norm());
  const int i1 = first_near_largest(value.data(), count, length_tie, best);
  const double far = (p[i1] - p0).squaredNorm();
  if (!(far > 0.0)) return 1;
  keep[1] = i1;
  const Vec p1 = p[i1];
  std::array<double, kMaxPolygon> area, negated;
  double best_area = kNone, best_negated = kNone;
  for (int i = 0; i < count; ++i) {
    area[i] = (p0 - p[i]).cross(p1 - p[i]).dot(n);
    negated[i] = -area[i];
    best_area = std::max(best_area, area[i]);
    best_negated = std::max(best_negated, negated[i]);
  }
  const double min_area = 1e-9 * far, area_tie = length_tie * std::sqrt(far);
  const int i2 = first_near_largest(area.data(), count, area_tie, best_area);
  const int i3 = first_near_largest(negated.data(), count, area_tie, best_negated);
  int kept = 2;
  if (area[i2] > min_area) keep[kept++] = i2;
  if (negated[i3] > min_area) keep[kept++] = i3;
  return kept;
}

void FaceClipper::incident_face() {
  const BoxTopology& topo = topo_;
  const Vec m = inc_.local_direction(u_);
  const Index v = support(-m);
  double best = std::numeric_limits<double>::infinity();
  for (const Index g : topo.vertex_face[v]) {
    const double dot = topo.normal[g].dot(m);
    if (dot < best) {
      best = dot;
      inc_face_ = g;
    }
  }
}

// On a face of A swept along its normal (the common case: A's face is the
// incumbent axis) the side planes are axis-aligned in A's frame, the frame
// everything is worked in: each plane's distance is one coordinate less a
// half extent, bit for bit n . x - d of the unit axis normal the general path
// builds. Otherwise the side planes are general. (Clipping a face of B in B's
// own frame would change the rounding of its points and so the sign of an
// exact touch: B's faces keep the general path's arithmetic.)
bool FaceClipper::run(double max_separation, Candidate* out, int& out_count, int& clipped) {
  const BoxTopology& topo = topo_;
  axis_aligned_ = along_ == nullptr && ref_is_a_;
  n_ = ref_.direction(topo.normal[ref_face_]);
  u_ = along_ ? *along_ : n_;
  const double slope = along_ ? n_.dot(u_) : 1.0;  // within the face angle tolerance of 1
  const std::array<Index, 4>& rv = topo.face_vertex[ref_face_];
  for (int k = 0; k < 4; ++k) ref_corner_[k] = ref_.point(rv[k]);
  const double offset = n_.dot(ref_corner_[0]);
  incident_face();
  Polygon a, b;
  for (int k = 0; k < 4; ++k) {
    a.p[k] = incident_[k] = inc_.point(topo.face_vertex[inc_face_][k]);
    a.origin[k] = a.next[k] = k;
    if (!incident_[k].allFinite()) return false;  // what clip() carries over is finite
  }
  a.count = 4;
  side_planes();
  const Polygon* src = clip_by_sides(a, b);
  if (!src) return false;
  clipped_ = src;
  clipped = src->count;
  // The points within max_separation: their separations, and where they are
  // in the clipped polygon (all of it, the common case, needs no copy).
  std::array<double, kMaxPolygon> sep;
  std::array<int, kMaxPolygon> from;
  int count = 0;
  // A face of A along its normal: n_ is an axis vector and the slope 1, so
  // the separation is one coordinate less the offset, bit for bit.
  const int normal_axis = static_cast<int>(ref_face_ >> 1);
  const bool positive = axis_aligned_ && n_[normal_axis] > 0.0;
  HEDRA_ASSERT(!axis_aligned_ || std::abs(n_[normal_axis]) == 1.0);
  for (int i = 0; i < src->count; ++i) {
    const double s = axis_aligned_ ? (positive ? src->p[i][normal_axis] : -src->p[i][normal_axis]) - offset
                                   : (n_.dot(src->p[i]) - offset) / slope;
    if (s <= max_separation) {
      from[count] = i;
      sep[count++] = s;
    }
  }
  std::array<Vec, kMaxPolygon> below;
  const Vec* pts = src->p.data();
  if (count != src->count) {
    for (int i = 0; i < count; ++i) below[i] = src->p[from[i]];
    pts = below.data();
  }
  std::array<int, kMaxContactPoints> keep{};
  const int kept = reduce(pts, sep.data(), count, u_, pair_.band, pair_.tolerance, keep);
  std::array<FeatureId, kMaxContactPoints> ids;
  const auto name_kept = [&] {
    for (int i = 0; i < kept; ++i) ids[i] = id_of(from[keep[i]], Vec(pts[keep[i]] - sep[keep[i]] * u_));
  };
  name_kept();
  // With a cache, the last frame's points while they hold (hold_last); when
  // the cold choice is those very points (the same features touch: the
  // common case) nothing else needs a name.
  if (pair_.last && count > kMaxContactPoints && !same_as_last(ids, kept)) {
    const std::array<int, kMaxContactPoints> cold = keep;
    hold_last(pts, sep.data(), from.data(), count, keep, kept);
    if (keep != cold) name_kept();
  }
  out_count = 0;
  for (int i = 0; i < kept; ++i) {
    const double s = sep[keep[i]];
    const Vec& p = pts[keep[i]];
    const Vec on_ref = p - s * u_;
    out[out_count++] = ref_is_a_ ? Candidate{on_ref, p, s, ids[i]} : Candidate{p, on_ref, s, ids[i]};
  }
  return true;
}

// The reference face's side planes: on a face of A swept along its normal,
// +-x_i = h_i from the topology's table (bit for bit the unit axis normal
// and offset the general path builds); otherwise the edge x the sweep.
void FaceClipper::side_planes() {
  const BoxTopology& topo = topo_;
  for (int k = 0; k < 4; ++k) {
    if (axis_aligned_) {
      const int i = topo.side_axis[ref_face_][k];
      const double sign = topo.side_sign[ref_face_][k];
      side_axis_[k] = i;
      side_normal_[k] = sign * Vec::Unit(i);
      side_offset_[k] = sign * ref_corner_[k][i];
      HEDRA_ASSERT(side_offset_[k] == side_normal_[k].dot(ref_corner_[k]));
    } else {
      side_normal_[k] = (ref_corner_[(k + 1) & 3] - ref_corner_[k]).cross(u_).normalized();
      side_offset_[k] = side_normal_[k].dot(ref_corner_[k]);
    }
  }
}

// The incident polygon `a` clipped by the four side planes in turn (`b` the
// scratch); null on a non-finite crossing. A plane no point lies beyond (by
// more than the tolerance) leaves the polygon as it is, provenance
// included: that pass is skipped.
const Polygon* FaceClipper::clip_by_sides(Polygon& a, Polygon& b) const {
  Polygon* src = &a;
  Polygon* dst = &b;
  std::array<double, kMaxPolygon> dist;
  for (int k = 0; k < 4 && src->count > 0; ++k) {
    const double d = side_offset_[k];
    bool beyond = false;
    if (axis_aligned_) {
      const int i = side_axis_[k];
      const double sign = side_normal_[k][i];
      for (int m = 0; m < src->count; ++m) {
        dist[m] = (sign > 0.0 ? src->p[m][i] : -src->p[m][i]) - d;
        beyond = beyond || dist[m] > pair_.tolerance;
      }
    } else {
      for (int m = 0; m < src->count; ++m) {
        dist[m] = side_normal_[k].dot(src->p[m]) - d;
        beyond = beyond || dist[m] > pair_.tolerance;
      }
    }
    if (!beyond) continue;
    if (!clip(*src, dist.data(), 4 + k, pair_.tolerance, *dst)) return nullptr;
    std::swap(src, dst);
  }
  return src;
}

// manifold.cpp's feature ids: an incident corner kept as is, else a
// crossing of an incident edge with a side plane (the nearest side plane),
// else a reference corner. A crossing on incident edge k is named by k
// without measuring its distance to every incident edge.
FeatureId FaceClipper::id_of(int i, const Vec& on_ref) const {
  const BoxTopology& topo = topo_;
  const Vec& p = clipped_->p[i];
  FeatureId id;
  id.reference_on_b = !ref_is_a_;
  id.reference = ref_face_;
  for (int k = 0; k < 4; ++k)
    if (incident_[k].x() == p.x() && incident_[k].y() == p.y() && incident_[k].z() == p.z()) {
      id.kind = FeatureKind::face_vertex;
      id.incident = topo.face_vertex[inc_face_][k];
      return id;
    }
  double best_side = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    const double along = axis_aligned_ ? side_normal_[k][side_axis_[k]] * p[side_axis_[k]] : side_normal_[k].dot(p);
    const double d = std::abs(along - side_offset_[k]);
    if (d < best_side) {
      best_side = d;
      id.clip = topo.face_edge[ref_face_][k];
    }
  }
  const int origin = clipped_->origin[i];
  Index edge = hull::kInvalidIndex;
  if (origin >= 8 && origin < 12) {
    edge = topo.face_edge[inc_face_][origin - 8];
  } else {  // a crossing on a side plane (or a corner moved by rounding): measure
    double best_edge = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) {
      const Vec& a = incident_[k];
      const Vec ab = incident_[(k + 1) & 3] - a;
      const double t = std::clamp(ab.dot(p - a) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
      const double d = (a + t * ab - p).norm();
      if (d < best_edge) {
        best_edge = d;
        edge = topo.face_edge[inc_face_][k];
      }
    }
    if (!(best_edge <= pair_.tolerance)) edge = hull::kInvalidIndex;
  }
  if (edge != hull::kInvalidIndex) {
    id.kind = FeatureKind::face_clip;
    id.incident = std::min(edge, topo.twin[edge]);
    return id;
  }
  // A corner of the reference face: named by its own half-edge (the one
  // leaving the corner nearest the point).
  id.kind = FeatureKind::face_corner;
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    const double d = (ref_corner_[k] - on_ref).squaredNorm();
    if (d < best) {
      best = d;
      id.clip = topo.face_edge[ref_face_][k];
    }
  }
  id.incident = inc_face_;
  return id;
}

// True when the kept points' ids are the last frame's, each once (then
// hold_last() would keep them as they are).
bool FaceClipper::same_as_last(const std::array<FeatureId, kMaxContactPoints>& ids, int kept) const {
  const ContactCache& last = *pair_.last;
  if (last.kept_count != kept) return false;
  // The common case first: the same ids in the same order, all distinct.
  bool in_order = true;
  for (int i = 0; i < kept && in_order; ++i) in_order = last.kept[i] == ids[i];
  for (int i = 0; i < kept && in_order; ++i)
    for (int k = i + 1; k < kept && in_order; ++k) in_order = ids[k] != ids[i];
  if (in_order) return true;
  for (int i = 0; i < kept; ++i) {
    int matches = 0;
    for (int k = 0; k < kept; ++k) matches += last.kept[k] == ids[i];
    for (int k = 0; k < kept; ++k) matches -= k != i && ids[k] == ids[i];
    if (matches != 1) return false;
  }
  return true;
}

// manifold.cpp's hold_last: the last frame's four points while all are
// still candidates and their deepest is within the hold of the deepest.
int FaceClipper::hold_last(const Vec* p, const double* sep, const int* from, int count,
                           std::array<int, kMaxContactPoints>& keep, int kept) const {
  const ContactCache& last = *pair_.last;
  if (last.kept_count != kept) return kept;
  std::array<int, kMaxContactPoints> held{};
  int found = 0;
  double deepest = std::numeric_limits<double>::infinity(), deepest_held = deepest;
  for (int i = 0; i < count; ++i) {
    deepest = std::min(deepest, sep[i]);
    const FeatureId id = id_of(from[i], Vec(p[i] - sep[i] * u_));
    for (int k = 0; k < last.kept_count; ++k)
      if (last.kept[k] == id && found < kMaxContactPoints) {
        held[found++] = i;
        deepest_held = std::min(deepest_held, sep[i]);
      }
  }
  if (found != kept || !(deepest_held <= deepest + pair_.hold)) return kept;
  int same = 0;
  for (int k = 0; k < kept; ++k) same += std::count(keep.begin(), keep.begin() + kept, held[k]) > 0;
  if (same < kept) keep = held;
  return kept;
}

using detail::segment_exit;  // contact_choice.hpp, shared with manifold.cpp

// manifold.cpp's exit_distance for a box: how far the ray p + t d (p on face
// f of the core, A's frame) runs inside the core grown by r: the last exit of
// the slabs of f and the four faces around it, the cylinders of f's edges
// and the balls of its corners. Worked in the box's own frame, where a slab's
// foot lies on its face when its other two coordinates are within the half
// extents (the general path's side-plane test, without the planes).
double exit_distance(const Side& box, Index f, const Vec& p_in, const Vec& d_in, double r) {
  const BoxTopology& topo = topology();
  const Vec p = box.rotation ? Vec(box.rotation->transpose() * (p_in - *box.translation)) : p_in;
  const Vec d = box.local_direction(d_in);
  const Vec& h = box.h;
  double t = r;
  const int opposite = static_cast<int>(f ^ 1u);  // faces 2k, 2k + 1: -axis k, +axis k
  for (int g = 0; g < 6; ++g) {
    if (g == opposite) continue;
    const int k = g >> 1;
    const double sign = (g & 1) ? 1.0 : -1.0;
    const double nd = sign * d[k];
    if (!(nd > 0.0)) continue;
    const double ts = (h[k] - sign * p[k] + r) / nd;
    const Vec foot = p + ts * d - r * sign * Vec::Unit(k);
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    if (!(std::abs(foot[i]) <= h[i] && std::abs(foot[j]) <= h[j])) continue;
    t = std::max(t, ts);
  }
  for (int k = 0; k < 4; ++k)
    t = std::max(t,
                 segment_exit(p, d, corner(h, topo.face_vertex[f][k]), corner(h, topo.face_vertex[f][(k + 1) & 3]), r));
  return t;
}

}  // namespace hedra::collision::detail::box_box
