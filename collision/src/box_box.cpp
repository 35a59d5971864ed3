// Box-box contact manifolds: the general polytope path (contact_polytopes.cpp) for the
// commonest pair, written for the box so that nothing is looked up, copied
// or searched that a box knows in closed form.
//   * SAT: the 15 axes from the relative rotation R and translation t alone
//     (the 6 face axes |t_k| - h_k - (|R| h)_k, the 9 edge axes e_i x f_j
//     by Gottschalk's OBB formulas), the same formulas as sat.cpp's box
//     case, so the same separations bit for bit; no support call.
//   * The axis chosen with the face bias and the cache's kept face of B
//     (contact_choice.hpp's choose_axis, shared with the general polytope path).
//   * Face contact: the incident face is the other box's face most
//     anti-parallel to the reference normal (the largest |m_j| of the normal
//     in its frame); its 4 corners are clipped by the reference face's 4 side
//     planes (Sutherland-Hodgman, the tolerance semantics of
//     hull::clip_polygon), points within the contact distance kept, reduced
//     to four and named as contact_clip.cpp names them (vertex, clipped edge,
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
// The face clipping and the rounded exits are in box_face.cpp.
#include "box_box.hpp"

#include <algorithm>
#include <cmath>
#include <hedra/hull/assert.hpp>
#include <limits>

#include "box_box_detail.hpp"
#include "contact_choice.hpp"
#include "contact_depth.hpp"
#include "query_detail.hpp"
#include "segment_box.hpp"

namespace hedra::collision::detail {
namespace box_box {
namespace {

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
    constexpr int kNext[3] = {1, 2, 0}, kAfter[3] = {2, 0, 1};
    const int i1 = kNext[i], i2 = kAfter[i];
    for (int j = 0; j < 3; ++j) {
      const int j1 = kNext[j], j2 = kAfter[j];
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

using detail::choose_axis;  // contact_choice.hpp, shared with the general polytope path
// ---- edge contact ------------------------------------------------------------

using detail::closest_segment_points;  // segment_box.hpp, shared with the general polytope path
// ---- the manifold -------------------------------------------------------------

// The answer in A's frame (world placement last, shared with the cache);
// `in_world`: penetration()'s single point, already in world coordinates.
struct Local {
  ContactPath path = ContactPath::none;
  double distance = 0.0;
  double error_bound = std::numeric_limits<double>::infinity();  // ContactResult's (before rounding)
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

// contact_clip.cpp's emit() for sharp cores: the candidates within the contact
// distance, reduced to four (more than four: a face's four and a witness
// pair), the deepest first.
void emit(Candidate* c, int count, const Vec& normal, const Pair& p, Local& out) {
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    if (!(c[i].separation <= p.keep)) continue;
    if (kept != i) c[kept] = c[i];
    ++kept;
  }
  std::array<int, kMaxContactPoints> keep{};
  if (kept <= kMaxContactPoints) {
    out.count = kept;
    for (int k = 0; k < kept; ++k) keep[k] = k;
    for (int k = 1; k < kept; ++k)
      if (c[keep[k]].separation < c[keep[0]].separation) std::swap(keep[0], keep[k]);
  } else {
    std::array<Vec, kMaxContactPoints + 1> on_b;
    std::array<double, kMaxContactPoints + 1> separation;
    HEDRA_ASSERT(kept <= kMaxContactPoints + 1);
    for (int i = 0; i < kept; ++i) {
      on_b[i] = c[i].on_b;
      separation[i] = c[i].separation;
    }
    out.count = reduce(on_b.data(), separation.data(), kept, normal, p.band, p.tolerance, keep);
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

// contact_polytopes.cpp's build_manifold for a sharp pair on axis `best`.
Built build(const Pair& p, const SatAxis& best, double exact_limit, Local& out, int& clipped) {
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
    closest_segment_points(pa0, pa1 - pa0, pb0, pb1 - pb0, on_a, on_b);
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
  if (count == 0) return Built::general;  // penetration()'s point
  // The deepest vertex clipped away (contact_depth.hpp): the exact normal decides.
  if (deepest_short_of_axis(deepest, best.separation, exact_limit, p.band, p.last ? p.hold : 0.0))
    return Built::exact_normal;
  emit(c.data(), count, best.normal, p, out);
  if (out.count == 0) {  // nothing within the contact distance: the axis
    out.distance = best.separation;
    out.normal = best.normal;
    out.intersecting = false;
  }
  return Built::answered;
}
// Sharp or rounded cores apart (contact_polytopes.cpp's rounded_cores_apart): the
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
      penetration_unchecked(a, pose_a, b, pose_b, cache ? &cache->gjk : nullptr, settings.penetration);
  if (pen.status != Status::ok) return Built::general;
  const double shape_scale = std::max(bounding_radius(a), bounding_radius(b));
  const auto single = [&] {  // penetration_point()
    out = Local{};
    out.in_world = true;
    out.path = ContactPath::single_point;
    out.distance = pen.distance;
    out.error_bound = pen.error_bound;
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
  if (p.ra + p.rb > 0.0) {  // contact_clip.cpp's round_along
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
  face.error_bound = bound_within(face.distance, face.error_bound, pen.distance, pen.error_bound);
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
  out.error_bound = l.error_bound;
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
  l.error_bound = m.error_bound;
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
}  // namespace box_box

using namespace box_box;

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
    HEDRA_ASSERT(std::abs(local.normal.squaredNorm() - 1.0) <= 1e-9);            // a unit normal, A toward B
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
      m.error_bound = local.error_bound;
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
      Built built = build(p, used, limit, local, clipped);
      if (built == Built::exact_normal) {
        clipped = 0;
        built = exact_normal(p, a, pose_a, b, pose_b, cache, settings, local, clipped, used);
        recyclable = false;  // GJK's warm start moves with the cache
      }
      if (built == Built::general) return hand_back();
      // Overlapping: SAT's largest separation is exact; apart (within the
      // contact distance), a lower bound and the points' gap an upper one.
      if (local.count > 0 || largest <= p.band)
        local.error_bound = bound_within(local.distance, local.error_bound, largest, 0.0);
      // penetration()'s point where the cache's kept face of B was chosen
      // against the cold choice: the general path builds the cold one.
      if (local.path == ContactPath::single_point && choose_axis(axes, nullptr, settings, p.scale).kind != chosen.kind)
        return hand_back();
    }
  }
  return finish();
}

}  // namespace hedra::collision::detail
