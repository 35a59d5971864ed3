// Box-box contact manifolds: the general polytope path (manifold.cpp) for the
// commonest pair, written for the box so that nothing is looked up, copied
// or searched that a box knows in closed form.
//   * SAT: the 15 axes from the relative rotation R and translation t alone
//     (the 6 face axes |t_k| - h_k - (|R| h)_k, the 9 edge axes e_i x f_j
//     by Gottschalk's OBB formulas), the same formulas as sat.cpp's box
//     case, so the same separations bit for bit; no support call.
//   * The axis chosen with the face bias and the cache's kept face of B
//     (manifold.cpp's choose_axis, the same rule).
//   * Face contact: the incident face is the other box's face most
//     anti-parallel to the reference normal (the largest |m_j| of the normal
//     in its frame); its 4 corners are clipped by the reference face's 4 side
//     planes (Sutherland-Hodgman, the tolerance semantics of
//     hull::clip_polygon), points within the contact distance kept, reduced
//     to four and named as manifold.cpp names them (vertex, clipped edge,
//     reference corner: the unit box mesh's indices). Edge contact: the
//     closest points of the two support edges, exact.
//   * Cache: the last answer in A's frame with the relative pose it was
//     computed at (ContactCache::box). A pair whose relative pose and inputs
//     are bit for bit the last frame's has the same answer: it is placed in
//     the world at the new poses without recomputing it (a cache hit).
//     Anything else is rebuilt at the new poses.
// Whatever this path does not answer exactly as the general path would
// (rounded cores that touch or overlap, whose depths need the rounded exits;
// sharp cores apart whose nearest candidate is not the SAT separation; a
// deepest vertex clipped away), it hands back: box_box_contact() returns false.
#include "box_box.hpp"

#include <algorithm>
#include <cmath>
#include <hedra/collision/sat.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>

namespace hedra::collision::detail {
namespace {

using Vec = Eigen::Vector3d;
using hull::Index;

// The unit box mesh's numbering (sat.hpp's unit_box_mesh()), read once.
struct BoxTopology {
  std::array<std::array<Index, 4>, 6> face_vertex;  // face f's corners in face_edges order
  std::array<std::array<Index, 4>, 6> face_edge;    // the half-edges leaving them
  std::array<std::array<Index, 3>, 8> vertex_face;  // vertex_faces order
  std::array<Index, 24> twin;
  std::array<Index, 24> origin;
  std::array<Index, 64> edge_between;  // [8 v0 + v1]: the half-edge v0 -> v1
  std::array<Vec, 6> normal;           // unit outward normals (axis vectors)
};

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

Vec corner(const Vec& h, Index v) {
  return {(v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(), (v & 4) ? h.z() : -h.z()};
}

// A box's vertex maximising d . x (sign bits, ties to +, as SatPolytope).
Index support(const Vec& d) {
  return static_cast<Index>((d.x() >= 0 ? 1 : 0) | (d.y() >= 0 ? 2 : 0) | (d.z() >= 0 ? 4 : 0));
}

// One box of the pair, placed in A's core frame: x -> rotation x + translation.
struct Side {
  Vec h;
  const Eigen::Matrix3d* rotation;  // null: A itself (identity)
  const Vec* translation;
  Vec point(Index v) const {
    const Vec c = corner(h, v);
    return rotation ? Vec(*rotation * c + *translation) : c;
  }
  Vec direction(const Vec& d) const { return rotation ? Vec(*rotation * d) : d; }
  Vec local_direction(const Vec& d) const { return rotation ? Vec(rotation->transpose() * d) : d; }
};

struct Pair {
  Vec ha, hb;
  double ra, rb;
  RelativePose rel;
  double scale, band, keep, core_contact, tolerance, hold;
  const ContactCache* last;
  Side side_a() const { return {ha, nullptr, nullptr}; }
  Side side_b() const { return {hb, &rel.rotation, &rel.translation}; }
};

struct Axes {
  SatAxis face_a, face_b, edge;
  int edge_pairs = 0;
};

// The 6 face axes (sat.cpp's box_face_query, the same expressions).
void face_axes(const Pair& p, Axes& out) {
  const Eigen::Matrix3d abs_r = p.rel.rotation.cwiseAbs();
  const Vec& t = p.rel.translation;
  const Vec t_in_b = p.rel.rotation.transpose() * t;
  const Vec radius_b = abs_r * p.hb;
  const Vec radius_a = abs_r.transpose() * p.ha;
  for (int k = 0; k < 3; ++k) {
    const double s = std::abs(t[k]) - p.ha[k] - radius_b[k];
    if (s > out.face_a.separation) {
      const bool plus = t[k] >= 0.0;
      out.face_a.kind = SatAxisKind::face_a;
      out.face_a.separation = s;
      out.face_a.feature_a = static_cast<Index>(2 * k + (plus ? 1 : 0));
      out.face_a.normal = (plus ? 1.0 : -1.0) * Vec::Unit(k);
    }
  }
  for (int j = 0; j < 3; ++j) {
    const double s = std::abs(t_in_b[j]) - p.hb[j] - radius_a[j];
    if (s > out.face_b.separation) {
      const bool plus = -t_in_b[j] >= 0.0;
      out.face_b.kind = SatAxisKind::face_b;
      out.face_b.separation = s;
      out.face_b.feature_b = static_cast<Index>(2 * j + (plus ? 1 : 0));
      out.face_b.normal = -(plus ? 1.0 : -1.0) * p.rel.rotation.col(j);
    }
  }
}

// The 9 edge axes (sat.cpp's box_edge_query, the same expressions). An edge
// pair whose numerator |n . t| - r_A - r_B is negative and at most `floor`
// (the best face axis) separates by no more than it (|e_A x e_B| <= 1, and
// rounding is monotone): it can be no chosen axis and no largest separation,
// and its square root and division are skipped.
void edge_axes(const Pair& p, double parallel_tolerance, double floor, Axes& out) {
  const Eigen::Matrix3d& r = p.rel.rotation;
  const Vec& t = p.rel.translation;
  int best_i = -1, best_j = -1;
  bool flip = false;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double len2 = 1.0 - r(i, j) * r(i, j);
      if (!(len2 > parallel_tolerance * parallel_tolerance)) continue;
      const double nt = t[i2] * r(i1, j) - t[i1] * r(i2, j);
      const double radius_a = p.ha[i1] * std::abs(r(i2, j)) + p.ha[i2] * std::abs(r(i1, j));
      const double radius_b = p.hb[j1] * std::abs(r(i, j2)) + p.hb[j2] * std::abs(r(i, j1));
      const double numerator = std::abs(nt) - radius_a - radius_b;
      ++out.edge_pairs;
      if (numerator <= std::min(floor, 0.0)) continue;
      const double s = numerator / std::sqrt(len2);
      if (s > out.edge.separation) {
        out.edge.separation = s;
        best_i = i;
        best_j = j;
        flip = nt < 0.0;
      }
    }
  }
  if (best_i < 0) return;
  const BoxTopology& topo = topology();
  out.edge.kind = SatAxisKind::edge;
  Vec n = Vec::Unit(best_i).cross(r.col(best_j)).normalized();
  if (flip) n = -n;
  out.edge.normal = n;
  const Index va = support(n) & ~(1u << best_i);
  const Index vb = support(-(r.transpose() * n)) & ~(1u << best_j);
  out.edge.feature_a = topo.edge_between[8 * va + (va | (1u << best_i))];
  out.edge.feature_b = topo.edge_between[8 * vb + (vb | (1u << best_j))];
}

// manifold.cpp's choose_axis: faces before edges, A's face the incumbent,
// each challenger beating it by the bias; B's face kept while the cache
// says it was last frame's reference and it still holds.
SatAxis choose_axis(const Axes& c, const ContactCache* cache, const ContactSettings& settings, double scale) {
  const auto bias = [&](double sep) { return settings.relative_bias * std::abs(sep) + settings.absolute_bias * scale; };
  const auto pick = [&](const SatAxis& incumbent, const SatAxis& challenger) {
    const SatAxis* best = &incumbent;
    if (challenger.separation > incumbent.separation + bias(incumbent.separation)) best = &challenger;
    if (c.edge.kind == SatAxisKind::edge && c.edge.separation > best->separation + bias(best->separation))
      best = &c.edge;
    return best;
  };
  const bool keep_b = cache && cache->axis == SatAxisKind::face_b && cache->feature == c.face_b.feature_b;
  if (keep_b && pick(c.face_b, c.face_a) == &c.face_b) return c.face_b;
  return *pick(c.face_a, c.face_b);
}

// ---- face contact -----------------------------------------------------------

struct Candidate {
  Vec on_a, on_b;
  double separation;
  FeatureId id;
};

// A polygon of at most 4 + 4 points (a quadrilateral clipped by 4 planes),
// each point with where it comes from: `origin` 0..3 the incident corner k
// as is, 8 + L a crossing on the segment labelled L; `next` the label of the
// segment leaving it (0..3 incident edge k, from corner k to k + 1; 4 + j
// the side plane j). Labels name the clipped points as manifold.cpp's
// geometric tests do (a crossing on incident edge k is that edge's), without
// the searches.
constexpr int kMaxPolygon = 8;
struct Polygon {
  std::array<Vec, kMaxPolygon> p;
  std::array<int, kMaxPolygon> origin, next;
  int count = 0;
};

// hull::clip_polygon for the unit plane n . x = d, label 4 + j (the same
// classification and crossings): keeps the part with n . x - d <= tol.
// False on a non-finite crossing (the general path then answers).
bool clip(const Polygon& in, const Vec& n, double d, int label, double tol, Polygon& out) {
  out.count = 0;
  const auto side = [&](double s) { return s > tol ? 1 : (s < -tol ? -1 : 0); };
  const auto crossing = [](const Vec& b, double db, const Vec& f, double df) {
    const double t = db / (db - df);
    return Vec(b + t * (f - b));
  };
  const auto emit = [&](const Vec& x, int origin, int next) {
    if (!x.allFinite() || out.count == kMaxPolygon) return false;
    out.p[out.count] = x;
    out.origin[out.count] = origin;
    out.next[out.count++] = next;
    return true;
  };
  if (in.count == 0) return true;
  if (in.count <= 2) {
    const double d0 = n.dot(in.p[0]) - d;
    const int s0 = side(d0);
    if (in.count == 1) return s0 == 1 || emit(in.p[0], in.origin[0], in.next[0]);
    const double d1 = n.dot(in.p[1]) - d;
    const int s1 = side(d1);
    const int on = 8 + in.next[0];
    if (s0 != 1 && !emit(in.p[0], in.origin[0], in.next[0])) return false;
    if (s0 == -1 && s1 == 1 && !emit(crossing(in.p[0], d0, in.p[1], d1), on, in.next[0])) return false;
    if (s0 == 1 && s1 == -1 && !emit(crossing(in.p[1], d1, in.p[0], d0), on, in.next[0])) return false;
    return s1 == 1 || emit(in.p[1], in.origin[1], in.next[1]);
  }
  double d_cur = n.dot(in.p[0]) - d;
  for (int i = 0; i < in.count; ++i) {
    const int j = i + 1 == in.count ? 0 : i + 1;
    const double d_next = n.dot(in.p[j]) - d;
    const int s_cur = side(d_cur), s_next = side(d_next);
    const int on = 8 + in.next[i];
    if (s_cur != 1 && !emit(in.p[i], in.origin[i], s_cur == 0 && s_next == 1 ? label : in.next[i])) return false;
    if (s_cur == -1 && s_next == 1) {
      if (!emit(crossing(in.p[i], d_cur, in.p[j], d_next), on, label)) return false;
    } else if (s_cur == 1 && s_next == -1) {
      if (!emit(crossing(in.p[j], d_next, in.p[i], d_cur), on, in.next[i])) return false;
    }
    d_cur = d_next;
  }
  return true;
}

// The first of `count` values within `tie` of the largest (manifold.cpp's
// first_near_largest).
int first_near_largest(const double* value, int count, double tie) {
  double best = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < count; ++i) best = std::max(best, value[i]);
  for (int i = 0; i < count; ++i)
    if (value[i] >= best - tie) return i;
  return 0;
}

// manifold.cpp's reduce: the deepest, the farthest from it, the largest
// positive and negative triangle areas about n, each the first within ties.
int reduce(const Candidate* c, int count, const Vec& n, double depth_tie, double length_tie,
           std::array<int, kMaxContactPoints>& keep) {
  if (count == 0) return 0;
  std::array<double, kMaxPolygon> value;
  for (int i = 0; i < count; ++i) value[i] = -c[i].separation;
  const int i0 = first_near_largest(value.data(), count, depth_tie);
  keep[0] = i0;
  if (count == 1) return 1;
  const Vec p0 = c[i0].on_b;
  for (int i = 0; i < count; ++i) value[i] = (c[i].on_b - p0).norm();
  const int i1 = first_near_largest(value.data(), count, length_tie);
  const double far = (c[i1].on_b - p0).squaredNorm();
  if (!(far > 0.0)) return 1;
  keep[1] = i1;
  const Vec p1 = c[i1].on_b;
  std::array<double, kMaxPolygon> area, negated;
  for (int i = 0; i < count; ++i) {
    area[i] = (p0 - c[i].on_b).cross(p1 - c[i].on_b).dot(n);
    negated[i] = -area[i];
  }
  const double min_area = 1e-9 * far, area_tie = length_tie * std::sqrt(far);
  const int i2 = first_near_largest(area.data(), count, area_tie);
  const int i3 = first_near_largest(negated.data(), count, area_tie);
  int kept = 2;
  if (area[i2] > min_area) keep[kept++] = i2;
  if (negated[i3] > min_area) keep[kept++] = i3;
  return kept;
}

// The face contact on reference face `ref_face` of `ref` (A when ref_is_a)
// with the incident face of `inc` (manifold.cpp's face_contact along the
// face normal). Candidates (at most four, ids set) go to `out`.
class FaceClipper {
 public:
  // `along` (A's frame, out of the reference, unit; null: the face's normal)
  // is the direction the points are measured along: the side planes are
  // swept along it and each separation is the gap along it.
  FaceClipper(const Pair& pair, const Side& ref, const Side& inc, Index ref_face, bool ref_is_a,
              const Vec* along = nullptr)
      : pair_(pair), ref_(ref), inc_(inc), ref_face_(ref_face), ref_is_a_(ref_is_a), along_(along) {}

  // False when the general path must answer (a non-finite crossing).
  bool run(double max_separation, Candidate* out, int& out_count, int& clipped);

 private:
  void incident_face();
  FeatureId id_of(int i, const Vec& on_ref) const;  // of clipped point i
  int hold_last(const Candidate* c, const int* from, int count, std::array<int, kMaxContactPoints>& keep,
                int kept) const;
  bool same_as_last(const std::array<FeatureId, kMaxContactPoints>& ids, int kept) const;

 public:
  Index incident() const { return inc_face_; }

 private:

  const Pair& pair_;
  const Side& ref_;
  const Side& inc_;
  Index ref_face_;
  bool ref_is_a_;
  const Vec* along_;
  Vec n_;  // A's frame, out of the reference face
  Vec u_;  // the sweep: along_ or n_
  Index inc_face_ = 0;
  std::array<Vec, 4> incident_;  // the incident face's corners (A's frame)
  std::array<Vec, 4> ref_corner_;
  std::array<Vec, 4> side_normal_;  // side planes of the reference face's edges
  std::array<double, 4> side_offset_;
  const Polygon* clipped_ = nullptr;
};

void FaceClipper::incident_face() {
  const BoxTopology& topo = topology();
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

bool FaceClipper::run(double max_separation, Candidate* out, int& out_count, int& clipped) {
  const BoxTopology& topo = topology();
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
  }
  a.count = 4;
  for (int k = 0; k < 4; ++k) {
    const Vec side = (ref_corner_[(k + 1) & 3] - ref_corner_[k]).cross(u_).normalized();
    side_normal_[k] = side;
    side_offset_[k] = side.dot(ref_corner_[k]);
  }
  Polygon* src = &a;
  Polygon* dst = &b;
  for (int k = 0; k < 4 && src->count > 0; ++k) {
    if (!clip(*src, side_normal_[k], side_offset_[k], 4 + k, pair_.tolerance, *dst)) return false;
    std::swap(src, dst);
  }
  clipped_ = src;
  clipped = src->count;
  std::array<Candidate, kMaxPolygon> below;
  std::array<int, kMaxPolygon> from;  // the clipped point each candidate is
  int count = 0;
  for (int i = 0; i < src->count; ++i) {
    const double s = (n_.dot(src->p[i]) - offset) / slope;
    if (s <= max_separation) {
      from[count] = i;
      below[count++] = Candidate{src->p[i], src->p[i], s, FeatureId{}};
    }
  }
  std::array<int, kMaxContactPoints> keep{};
  const int kept = reduce(below.data(), count, u_, pair_.band, pair_.tolerance, keep);
  std::array<FeatureId, kMaxContactPoints> ids;
  const auto name_kept = [&] {
    for (int i = 0; i < kept; ++i)
      ids[i] = id_of(from[keep[i]], Vec(below[keep[i]].on_b - below[keep[i]].separation * u_));
  };
  name_kept();
  // With a cache, the last frame's points while they hold (hold_last); when
  // the cold choice is those very points (the same features touch: the
  // common case) nothing else needs a name.
  if (pair_.last && count > kMaxContactPoints && !same_as_last(ids, kept)) {
    const std::array<int, kMaxContactPoints> cold = keep;
    hold_last(below.data(), from.data(), count, keep, kept);
    if (keep != cold) name_kept();
  }
  out_count = 0;
  for (int i = 0; i < kept; ++i) {
    const Vec p = below[keep[i]].on_b;
    const double s = below[keep[i]].separation;
    const Vec on_ref = p - s * u_;
    out[out_count++] = ref_is_a_ ? Candidate{on_ref, p, s, ids[i]} : Candidate{p, on_ref, s, ids[i]};
  }
  return true;
}

// manifold.cpp's feature ids: an incident corner kept as is, else a
// crossing of an incident edge with a side plane (the nearest side plane),
// else a reference corner. A crossing on incident edge k is named by k
// without measuring its distance to every incident edge.
FeatureId FaceClipper::id_of(int i, const Vec& on_ref) const {
  const BoxTopology& topo = topology();
  const Vec& p = clipped_->p[i];
  FeatureId id;
  id.reference_on_b = !ref_is_a_;
  id.reference = ref_face_;
  for (int k = 0; k < 4; ++k)
    if (incident_[k] == p) {
      id.kind = FeatureKind::face_vertex;
      id.incident = topo.face_vertex[inc_face_][k];
      return id;
    }
  double best_side = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    const double d = std::abs(side_normal_[k].dot(p) - side_offset_[k]);
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
int FaceClipper::hold_last(const Candidate* c, const int* from, int count, std::array<int, kMaxContactPoints>& keep,
                           int kept) const {
  const ContactCache& last = *pair_.last;
  if (last.kept_count != kept) return kept;
  std::array<int, kMaxContactPoints> held{};
  int found = 0;
  double deepest = std::numeric_limits<double>::infinity(), deepest_held = deepest;
  for (int i = 0; i < count; ++i) {
    deepest = std::min(deepest, c[i].separation);
    const FeatureId id = id_of(from[i], Vec(c[i].on_b - c[i].separation * u_));
    for (int k = 0; k < last.kept_count; ++k)
      if (last.kept[k] == id && found < kMaxContactPoints) {
        held[found++] = i;
        deepest_held = std::min(deepest_held, c[i].separation);
      }
  }
  if (found != kept || !(deepest_held <= deepest + pair_.hold)) return kept;
  int same = 0;
  for (int k = 0; k < kept; ++k) same += std::count(keep.begin(), keep.begin() + kept, held[k]) > 0;
  if (same < kept) keep = held;
  return kept;
}

// ---- edge contact ------------------------------------------------------------

// Closest points of segments p0 + s u and q0 + t v, s, t in [0, 1]
// (Ericson 5.1.9, guarded divisions).
void closest_on_segments(const Vec& p0, const Vec& u, const Vec& q0, const Vec& v, Vec& on_p, Vec& on_q) {
  const Vec r = p0 - q0;
  const double a = u.squaredNorm(), e = v.squaredNorm(), f = v.dot(r);
  double s = 0.0, t = 0.0;
  if (a > 0.0 && e > 0.0) {
    const double c = u.dot(r), b = u.dot(v), denom = a * e - b * b;
    s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
    t = (b * s + f) / e;
    if (t < 0.0) {
      t = 0.0;
      s = std::clamp(-c / a, 0.0, 1.0);
    } else if (t > 1.0) {
      t = 1.0;
      s = std::clamp((b - c) / a, 0.0, 1.0);
    }
  } else if (a > 0.0) {
    s = std::clamp(-u.dot(r) / a, 0.0, 1.0);
  } else if (e > 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  }
  on_p = p0 + s * u;
  on_q = q0 + t * v;
}

// ---- the manifold -------------------------------------------------------------

// The answer in A's frame (world placement last, shared with the cache);
// `in_world`: penetration()'s single point, already in world coordinates.
struct Local {
  ContactPath path = ContactPath::none;
  double distance = 0.0;
  Vec normal = Vec::Zero();
  Vec point_a = Vec::Zero(), point_b = Vec::Zero();
  bool witnesses = false;  // point_a, point_b set
  int count = 0;
  std::array<ContactPoint, kMaxContactPoints> points{};  // A's frame
  bool intersecting = false;
  bool in_world = false;
};

// What build() found: the answer, or that the general path must answer, or
// that the cores are apart and the manifold follows their exact normal.
enum class Built { answered, general, exact_normal };

// manifold.cpp's emit() for sharp cores: the candidates within the contact
// distance, reduced to four (more than four: a face's four and a witness
// pair), the deepest first.
void emit(Candidate* c, int count, const Vec& normal, const Pair& p, Local& out) {
  int kept = 0;
  for (int i = 0; i < count; ++i)
    if (c[i].separation <= p.keep) c[kept++] = c[i];
  std::array<int, kMaxContactPoints> keep{};
  if (kept <= kMaxContactPoints) {
    out.count = kept;
    for (int k = 0; k < kept; ++k) keep[k] = k;
    for (int k = 1; k < kept; ++k)
      if (c[keep[k]].separation < c[keep[0]].separation) std::swap(keep[0], keep[k]);
  } else {
    out.count = reduce(c, kept, normal, p.band, p.tolerance, keep);
  }
  out.normal = normal;
  for (int k = 0; k < out.count; ++k) {
    const Candidate& x = c[keep[k]];
    out.points[k].point = 0.5 * (x.on_a + x.on_b);
    out.points[k].depth = -x.separation;
    out.points[k].id = x.id;
  }
  if (out.count > 0) {
    const Candidate& deepest = c[keep[0]];
    out.distance = deepest.separation;
    out.point_a = deepest.on_a;
    out.point_b = deepest.on_b;
    out.witnesses = true;
  }
  out.intersecting = out.count > 0 && out.distance <= 0.0;
}

// manifold.cpp's build_manifold for a sharp pair on axis `best`.
Built build(const Pair& p, const SatAxis& best, double exact_limit, const ContactSettings& settings, Local& out,
            int& clipped) {
  std::array<Candidate, kMaxContactPoints> c;
  int count = 0;
  const bool apart = best.separation > p.band;
  if (best.kind == SatAxisKind::face_a || best.kind == SatAxisKind::face_b) {
    const bool of_a = best.kind == SatAxisKind::face_a;
    const Side sa = p.side_a(), sb = p.side_b();
    FaceClipper clipper(p, of_a ? sa : sb, of_a ? sb : sa, of_a ? best.feature_a : best.feature_b, of_a);
    if (!clipper.run(p.core_contact, c.data(), count, clipped)) return Built::general;
    out.path = of_a ? ContactPath::face_a : ContactPath::face_b;
  } else {
    const BoxTopology& topo = topology();
    const Index ea = best.feature_a, eb = best.feature_b;
    const Side sa = p.side_a(), sb = p.side_b();
    const Index a_from = topo.origin[ea], a_to = topo.origin[topo.twin[ea]];
    const Index b_from = topo.origin[eb], b_to = topo.origin[topo.twin[eb]];
    const Vec pa0 = sa.point(a_from), pa1 = sa.point(a_to), pb0 = sb.point(b_from), pb1 = sb.point(b_to);
    Vec on_a, on_b;
    closest_on_segments(pa0, pa1 - pa0, pb0, pb1 - pb0, on_a, on_b);
    FeatureId id;
    id.kind = FeatureKind::edge;
    id.reference = ea;
    id.incident = eb;
    c[count++] = Candidate{on_a, on_b, apart ? std::max(best.separation, (on_b - on_a).norm()) : best.separation, id};
    out.path = ContactPath::edge;
  }
  double deepest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < count; ++i) deepest = std::min(deepest, c[i].separation);
  // Sharp cores apart whose nearest candidate is not SAT's separation (SAT
  // bounds their distance from below, the candidate from above): the
  // closest features are no face's interior, the exact normal decides.
  if (apart && count > 0 && deepest > best.separation + p.band) return Built::exact_normal;
  const double bias = settings.relative_bias * std::abs(best.separation) + settings.absolute_bias * p.scale;
  const double held = p.last ? p.hold : 0.0;
  const double limit = std::min(best.separation + bias, exact_limit) + held;
  if (count == 0 || deepest > limit) return Built::general;  // penetration()'s point
  emit(c.data(), count, best.normal, p, out);
  if (out.count == 0) {  // nothing within the contact distance: the axis
    out.distance = best.separation;
    out.normal = best.normal;
    out.intersecting = false;
  }
  return Built::answered;
}

// manifold.cpp's segment_exit: how far the ray p + t d (d unit, p within r
// of the segment a-b) runs inside the capsule of radius r about a-b (the
// ball at a and the cylinder; the ball at b is the next edge's ball at a).
double segment_exit(const Vec& p, const Vec& d, const Vec& a, const Vec& b, double r) {
  double t = -std::numeric_limits<double>::infinity();
  const Vec w = p - a;
  const double bq = d.dot(w), disc = bq * bq - (w.squaredNorm() - r * r);
  if (disc >= 0.0) t = -bq + std::sqrt(disc);
  const Vec ab = b - a;
  const double len = ab.norm();
  if (!(len > 0.0)) return t;
  const Vec u = ab / len;
  const Vec dp = d - d.dot(u) * u, wp = w - w.dot(u) * u;
  const double qa = dp.squaredNorm(), qb = dp.dot(wp), qd = qb * qb - qa * (wp.squaredNorm() - r * r);
  if (qa > 0.0 && qd >= 0.0) {
    const double tc = (-qb + std::sqrt(qd)) / qa;
    const double along = (w + tc * d).dot(u);
    if (along >= 0.0 && along <= len) t = std::max(t, tc);
  }
  return t;
}

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
    t = std::max(t, segment_exit(p, d, corner(h, topo.face_vertex[f][k]), corner(h, topo.face_vertex[f][(k + 1) & 3]), r));
  return t;
}

// Sharp or rounded cores apart (manifold.cpp's rounded_cores_apart): the
// exact normal n of penetration(); the face of A (else of B) within the face
// angle tolerance of n is the reference, its incident face clipped by its
// side planes swept along n, each point's depth the gap of the rounded
// surfaces on its line along n (both cores' exits along it), penetration()'s
// witnesses added when every clipped point is shallower; penetration()'s
// point when that leaves nothing. `used`: the face, for the cache. Built::general when no face lies
// along n (edge against edge or corner: the general path names the edges).
Built exact_normal(const Pair& p, const Box& a, const Pose& pose_a, const Box& b, const Pose& pose_b,
                   ContactCache* cache, const ContactSettings& settings, Local& out, int& clipped, SatAxis& used) {
  const PenetrationResult pen =
      penetration(Shape{a}, pose_a, Shape{b}, pose_b, cache ? &cache->gjk : nullptr, settings.penetration);
  if (pen.status != Status::ok) return Built::general;
  const double shape_scale = std::max(bounding_radius(a), bounding_radius(b));
  const auto single = [&] {  // penetration_point()
    out = Local{};
    out.in_world = true;
    out.path = ContactPath::single_point;
    out.distance = pen.distance;
    out.normal = pen.normal;
    out.point_a = pen.point_a;
    out.point_b = pen.point_b;
    out.witnesses = true;
    out.intersecting = pen.distance <= 0.0;
    if (pen.distance <= settings.contact_distance + settings.penetration.touching_band * shape_scale) {
      out.count = 1;
      out.points[0].point = 0.5 * (pen.point_a + pen.point_b);
      out.points[0].depth = -pen.distance;
      out.points[0].id.kind = FeatureKind::single;
    } else {
      out.path = ContactPath::separated;
    }
  };
  single();
  used = SatAxis{};
  if (out.count == 0) return Built::answered;
  const Vec n = pose_a.rotation.transpose() * pen.normal;  // A's frame, A -> B
  const BoxTopology& topo = topology();
  const double cos_tol = std::cos(settings.face_angle_tolerance);
  const auto face_along = [&](const Vec& d) {
    Index face = hull::kInvalidIndex;
    double best = cos_tol;
    for (const Index f : topo.vertex_face[support(d)]) {
      const double dot = topo.normal[f].dot(d);
      if (dot >= best) {
        best = dot;
        face = f;
      }
    }
    return face;
  };
  const Index fa = face_along(n);
  const Index fb = fa == hull::kInvalidIndex ? face_along(p.rel.rotation.transpose() * -n) : hull::kInvalidIndex;
  if (fa == hull::kInvalidIndex && fb == hull::kInvalidIndex) return Built::general;
  const bool of_a = fa != hull::kInvalidIndex;
  used.kind = of_a ? SatAxisKind::face_a : SatAxisKind::face_b;
  used.feature_a = fa;
  used.feature_b = fb;
  const Vec along = of_a ? n : Vec(-n);
  const Side sa = p.side_a(), sb = p.side_b();
  FaceClipper clipper(p, of_a ? sa : sb, of_a ? sb : sa, of_a ? fa : fb, of_a, &along);
  std::array<Candidate, kMaxContactPoints + 1> c;
  int count = 0, face_clipped = 0;
  if (!clipper.run(p.core_contact, c.data(), count, face_clipped)) return Built::answered;  // the single point
  if (p.ra + p.rb > 0.0) {  // manifold.cpp's round_along
    const double r_ref = of_a ? p.ra : p.rb, r_inc = of_a ? p.rb : p.ra;
    const Side& ref = of_a ? sa : sb;
    const Side& inc = of_a ? sb : sa;
    const Index ref_face = of_a ? fa : fb, inc_face = clipper.incident();
    for (int i = 0; i < count; ++i) {
      Candidate& x = c[i];
      Vec& on_ref = of_a ? x.on_a : x.on_b;
      Vec& on_inc = of_a ? x.on_b : x.on_a;
      const double t_ref = r_ref > 0.0 ? exit_distance(ref, ref_face, on_ref, along, r_ref) : 0.0;
      const double t_inc = r_inc > 0.0 ? exit_distance(inc, inc_face, on_inc, -along, r_inc) : 0.0;
      on_ref += t_ref * along;
      on_inc -= t_inc * along;
      x.separation -= t_ref + t_inc;
    }
  }
  bool hit = false;
  for (int i = 0; i < count; ++i) hit = hit || c[i].separation <= pen.distance + p.band;
  if (!hit) {
    FeatureId id;
    id.kind = FeatureKind::single;
    const Vec wa = pose_a.rotation.transpose() * (pen.point_a - pose_a.translation);
    const Vec wb = pose_a.rotation.transpose() * (pen.point_b - pose_a.translation);
    c[count++] = Candidate{wa, wb, pen.distance, id};
  }
  Local face;
  face.path = of_a ? ContactPath::face_a : ContactPath::face_b;
  emit(c.data(), count, n, p, face);
  if (face.count == 0) return Built::answered;  // the single point
  out = face;
  clipped = face_clipped;
  return Built::answered;
}

void remember(ContactCache* cache, const SatAxis& axis) {
  if (!cache) return;
  cache->axis = axis.kind;
  cache->feature = axis.kind == SatAxisKind::face_b ? axis.feature_b : axis.feature_a;
  cache->feature_b = axis.kind == SatAxisKind::edge ? axis.feature_b : hull::kInvalidIndex;
}

// The answer in the world: x_world = R_a x + t_a.
void place(const Local& l, const Pose& pose_a, ContactResult& out) {
  out.status = Status::ok;
  out.path = l.path;
  out.distance = l.distance;
  out.intersecting = l.intersecting;
  out.count = l.count;
  if (l.in_world) {
    out.normal = l.normal;
    for (int k = 0; k < l.count; ++k) out.points[k] = l.points[k];
    out.point_a = l.point_a;
    out.point_b = l.point_b;
    return;
  }
  out.normal = pose_a.rotation * l.normal;
  for (int k = 0; k < l.count; ++k) {
    out.points[k] = l.points[k];
    out.points[k].point = pose_a.rotation * l.points[k].point + pose_a.translation;
  }
  if (l.witnesses) {
    out.point_a = pose_a.rotation * l.point_a + pose_a.translation;
    out.point_b = pose_a.rotation * l.point_b + pose_a.translation;
  }
}

std::array<double, 12> inputs_of(const Box& a, const Box& b, const ContactSettings& s) {
  return {a.half_extents.x(), a.half_extents.y(), a.half_extents.z(), b.half_extents.x(),
          b.half_extents.y(), b.half_extents.z(), a.margin,           b.margin,
          s.contact_distance, s.relative_bias,    s.absolute_bias,    s.penetration.touching_band};
}

// The inputs a box pair's answer depends on besides the shapes and
// inputs_of (checked apart: they are rarely anything but their defaults).
bool default_details(const ContactSettings& s) {
  return s.hold == 0.0 && s.parallel_tolerance == ContactSettings{}.parallel_tolerance;
}

bool recycle(const ContactCache& cache, const RelativePose& rel, const std::array<double, 12>& inputs,
             const ContactSettings& settings, const Pose& pose_a, ContactResult& out) {
  const BoxPairMemory& m = cache.box;
  if (!m.valid || m.rotation != rel.rotation || m.translation != rel.translation || m.inputs != inputs ||
      !default_details(settings))
    return false;
  Local l;
  l.path = m.path;
  l.distance = m.distance;
  l.normal = m.normal;
  l.point_a = m.point_a;
  l.point_b = m.point_b;
  l.witnesses = m.count > 0;
  l.count = m.count;
  l.points = m.points;
  l.intersecting = m.count > 0 ? m.distance <= 0.0 : false;
  place(l, pose_a, out);
  out.stats.cache_hit = true;
  out.stats.edge_pairs = m.edge_pairs;
  out.stats.clipped_points = m.clipped_points;
  return true;
}

}  // namespace

bool box_box_contact(const Box& a, const Pose& pose_a, const Box& b, const Pose& pose_b, ContactCache* cache,
                     const ContactSettings& settings, ContactResult& out) {
  const auto hand_back = [&] {
    if (cache) cache->box.valid = false;
    return false;
  };
  // The exact-normal search asked for (or SAT's edge-pair budget below a
  // box pair's 144): the general path's other search.
  if (!settings.box_box_path || settings.axis_search == PolytopeAxisSearch::exact_normal ||
      (settings.axis_search == PolytopeAxisSearch::automatic && !(144.0 <= settings.max_sat_edge_pairs)))
    return hand_back();
  Pair p;
  p.ha = a.half_extents;
  p.hb = b.half_extents;
  p.ra = a.margin;
  p.rb = b.margin;
  p.rel = relative_pose(pose_a, Vec::Zero(), pose_b, Vec::Zero());
  const std::array<double, 12> inputs = inputs_of(a, b, settings);
  if (cache && recycle(*cache, p.rel, inputs, settings, pose_a, out)) return true;
  p.scale = std::max(p.ha.norm(), p.hb.norm()) + std::max(p.ra, p.rb);
  p.band = settings.penetration.touching_band * p.scale;
  p.keep = settings.contact_distance + p.band;
  p.core_contact = p.keep + p.ra + p.rb;
  p.tolerance = 1e-6 * p.scale;
  p.hold = settings.hold * p.scale;
  p.last = cache;

  Axes axes;
  face_axes(p, axes);
  Local local;
  SatAxis used;
  int clipped = 0;
  bool recyclable = true;
  const auto finish = [&] {
    HEDRA_ASSERT(local.count >= 0 && local.count <= kMaxContactPoints);
    HEDRA_ASSERT(std::abs(local.normal.squaredNorm() - 1.0) <= 1e-9);  // a unit normal, A toward B
    HEDRA_ASSERT(local.count == 0 || local.points[0].depth == -local.distance);  // the deepest first
    place(local, pose_a, out);
    out.stats.edge_pairs = axes.edge_pairs;
    out.stats.clipped_points = clipped;
    if (cache) {
      remember(cache, used);
      cache->support_a = cache->support_b = 0;
      cache->kept_count = local.count;
      for (int k = 0; k < local.count; ++k) cache->kept[k] = local.points[k].id;
      BoxPairMemory& m = cache->box;
      m.valid = recyclable;
      m.rotation = p.rel.rotation;
      m.translation = p.rel.translation;
      m.inputs = inputs;
      m.path = local.path;
      m.distance = local.distance;
      m.normal = local.normal;
      m.point_a = local.point_a;
      m.point_b = local.point_b;
      m.count = local.count;
      m.points = local.points;
      m.edge_pairs = axes.edge_pairs;
      m.clipped_points = clipped;
    }
    return true;
  };
  const auto separated = [&](const SatAxis& axis) {
    local.path = ContactPath::separated;
    local.distance = axis.separation - p.ra - p.rb;
    local.normal = axis.normal;
    used = axis;
  };
  if (axes.face_a.separation > p.core_contact || axes.face_b.separation > p.core_contact) {
    separated(axes.face_b.separation > axes.face_a.separation ? axes.face_b : axes.face_a);
  } else {
    edge_axes(p, settings.parallel_tolerance, std::max(axes.face_a.separation, axes.face_b.separation), axes);
    if (axes.edge.kind == SatAxisKind::edge && axes.edge.separation > p.core_contact) {
      separated(axes.edge);
    } else {
      used = choose_axis(axes, cache, settings, p.scale);
      if (p.ra + p.rb > 0.0) {
        // Rounded cores touching or overlapping: their depths need the
        // incident side's exits along the face normal (the general path's).
        if (!(used.separation > p.band)) return hand_back();
        // Apart: the exact normal of the cores (contact_by_sat's rounded branch).
        if (exact_normal(p, a, pose_a, b, pose_b, cache, settings, local, clipped, used) == Built::general)
          return hand_back();
        recyclable = false;
        return finish();
      }
      const double largest = std::max({axes.face_a.separation, axes.face_b.separation, axes.edge.separation});
      const double limit = largest <= p.band ? largest + p.band : std::numeric_limits<double>::infinity();
      const SatAxis chosen = used;
      Built built = build(p, used, limit, settings, local, clipped);
      if (built == Built::exact_normal) {
        clipped = 0;
        built = exact_normal(p, a, pose_a, b, pose_b, cache, settings, local, clipped, used);
        recyclable = false;  // GJK's warm start moves with the cache
      }
      if (built == Built::general) return hand_back();
      // penetration()'s point where the cache's kept face of B was chosen
      // against the cold choice: the general path builds the cold one.
      if (local.path == ContactPath::single_point && choose_axis(axes, nullptr, settings, p.scale).kind != chosen.kind)
        return hand_back();
    }
  }
  return finish();
}

}  // namespace hedra::collision::detail
