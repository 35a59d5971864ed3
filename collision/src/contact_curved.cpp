// Curved shapes (capsules, cylinders, cones) against a polytope: the
// manifold around penetration()'s normal, a capsule's segment or a side line
// clipped by the face along it, a cap disc intersected with the face exactly,
// each point's depth the gap of the rounded surfaces along the normal
// (docs/contacts.md). A box against a capsule apart gets its first point in
// closed form (segment_box.hpp).
#include <algorithm>
#include <cmath>
#include <hedra/hull/assert.hpp>
#include <hedra/hull/mesh_edit.hpp>
#include <limits>

#include "contact_choice.hpp"
#include "contact_common.hpp"
#include "contact_depth.hpp"
#include "segment_box.hpp"

namespace hedra::collision::detail::manifold {

using detail::segment_exit;  // contact_choice.hpp

namespace {

// The side plane of half-edge e of a face of `poly` swept along n (A's frame,
// within the angle tolerance of the face's normal), outward: a point lies
// inside every swept side plane when its projection along n onto the face's
// plane lies inside the face.
Vec swept_side(const SatPolytope& poly, Index e, const Vec& n) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  return (poly.vertex(m.destination(e)) - poly.vertex(m.origin(e))).cross(n);
}

// A point x of B's core against the plane of a face of A along the normal n:
// its foot on the plane along n, and its separation along n.
void push_along(const hull::Plane& plane, const Vec& n, const Vec& x, const FeatureId& id, CandidateList& out) {
  const double s = plane.signed_distance(x) / plane.normal.dot(n);
  out.push(x - s * n, x, s, id);
}

// Segment s0-s1 (A's frame, on B's core) clipped by the side planes of face f
// swept along the normal n.
bool segment_on_face(const SatPolytope& poly, Index f, const Vec& n, const Vec& s0, const Vec& s1, double tol,
                     CandidateList& out) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  std::array<Vec, 4> buf_a{s0, s1}, buf_b;
  Vec* src = buf_a.data();
  Vec* dst = buf_b.data();
  std::size_t count = 2;
  for (const Index e : m.face_edges(f)) {
    const Vec side = swept_side(poly, e, n);
    const hull::ClipResult r =
        hull::clip_polygon(src, count, {side, side.dot(poly.vertex(m.origin(e)))}, dst, buf_b.size(), tol);
    if (r.status != hull::ClipStatus::ok) return false;
    count = r.count;
    std::swap(src, dst);
    if (count == 0) break;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const Vec& p = src[i];
    FeatureId id;
    id.kind = FeatureKind::segment;
    id.reference = f;
    if (p == s0) {
      id.incident = 0;
    } else if (p == s1) {
      id.incident = 1;
    } else {
      double best = std::numeric_limits<double>::infinity();
      for (const Index e : m.face_edges(f)) {
        const double d = std::abs(swept_side(poly, e, n).normalized().dot(p - poly.vertex(m.origin(e))));
        if (d < best) {
          best = d;
          id.clip = e;
        }
      }
      id.incident = 2;
    }
    push_along(poly.plane(f), n, p, id, out);
  }
  return true;
}

// Cap disc (centre c, outward unit normal cn, radius r, local axes ux, uy in
// A's frame) against face f of `poly` along the normal n; see manifold.hpp.
// A point's separation along n is affine over the cap's plane, so its
// extremes over the region (disc x face projected along n) are among the
// candidates: the rim point deepest toward the face's plane, the projected
// face vertices inside the disc, and the edges' crossings of the rim.
void cap_on_face(const SatPolytope& poly, Index f, const Vec& n, const Vec& c, const Vec& cn, double r, const Vec& ux,
                 const Vec& uy, double tol, CandidateList& out) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  const hull::Plane& plane = poly.plane(f);
  const Vec& nf = plane.normal;
  auto inside_face = [&](const Vec& x) {
    for (const Index e : m.face_edges(f)) {
      const Vec side = swept_side(poly, e, n);
      if (side.dot(x - poly.vertex(m.origin(e))) > tol * side.norm()) return false;
    }
    return true;
  };
  auto add = [&](const Vec& x, std::uint32_t which) {
    FeatureId id;
    id.kind = FeatureKind::cap;
    id.reference = f;
    id.incident = which;
    push_along(plane, n, x, id, out);
  };
  const Vec rims[4] = {ux, -ux, uy, -uy};
  for (std::uint32_t k = 0; k < 4; ++k)
    if (inside_face(c + r * rims[k])) add(c + r * rims[k], k);
  // The deepest rim point: towards -nf within the cap plane.
  const Vec w = -(nf - nf.dot(cn) * cn);
  const double wn = w.norm();
  if (wn > 1e-12 && inside_face(c + (r / wn) * w)) add(c + (r / wn) * w, 4);
  // Project the polygon onto the cap plane along n: p -> p - ((p - c).cn / n.cn) n.
  const double ncn = n.dot(cn);  // close to -1 here
  auto project = [&](const Vec& p) { return Vec(p - ((p - c).dot(cn) / ncn) * n); };
  const double r2 = r * r;
  for (const Index e : m.face_edges(f)) {
    const Vec q0 = project(poly.vertex(m.origin(e)));
    const Vec q1 = project(poly.vertex(m.destination(e)));
    if ((q0 - c).squaredNorm() <= r2) add(q0, 8 + m.origin(e));
    // |q0 + s dq - c|^2 = r^2 for s in (0, 1): the edge crossing the rim.
    const Vec dq = q1 - q0, rel = q0 - c;
    const double qa = dq.squaredNorm(), qb = dq.dot(rel), qc = rel.squaredNorm() - r2;
    const double disc = qb * qb - qa * qc;
    if (!(qa > 0.0) || !(disc >= 0.0)) continue;
    const double root = std::sqrt(disc);
    const double roots[2] = {(-qb - root) / qa, (-qb + root) / qa};
    for (int k = 0; k < 2; ++k)
      if (roots[k] > 0.0 && roots[k] < 1.0) add(q0 + roots[k] * dq, (1u << 20) + 2 * e + static_cast<std::uint32_t>(k));
  }
}

// Distance from a point (B's local frame) to a cylinder's or cone's core,
// from the meridian half-section (radial >= 0, axial): the nearest of its
// edges; `away` is the unit direction from the closest point (local frame).
// For points outside the core (0 and an arbitrary `away` inside).
template <class SB>
double core_distance(const SB& b, const Vec& p, Vec& away) {
  const double h = b.half_length, r = b.radius;
  const double radial = std::hypot(p.x(), p.y());
  const Eigen::Vector2d q(radial, p.z());
  const bool cylinder = std::is_same_v<SB, Cylinder>;
  // Base centre, rim, top rim (cylinder) or apex (cone), top centre.
  const Eigen::Vector2d corners[4] = {{0.0, -h}, {r, -h}, {cylinder ? r : 0.0, h}, {0.0, h}};
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d closest = q;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d e = corners[k + 1] - corners[k];
    const double len2 = e.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((q - corners[k]).dot(e) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d c = corners[k] + t * e;
    const double d = (q - c).norm();
    if (d < best) {
      best = d;
      closest = c;
    }
  }
  const Eigen::Vector2d w = best > 0.0 ? Eigen::Vector2d((q - closest) / best) : Eigen::Vector2d(0.0, 1.0);
  const Vec radial_unit = radial > 0.0 ? Vec(p.x() / radial, p.y() / radial, 0.0) : Vec::UnitX();
  away = w.x() * radial_unit + Vec(0.0, 0.0, w.y());
  return best;
}

// How far the ray x + s d (A's frame; x on B's core, d unit and leaving the
// core there) runs inside B's core grown by r: the root of
// distance(x + s d) = r, between r (the distance grows at most as fast as
// s) and 2 r (at least as fast as s |d . normal| > 1/2 near a face's normal).
// The distance along a line is convex, so Newton's steps from 2 r decrease
// monotonically onto the root: 3 to 4 steps to rounding (at most 16).
template <class SB>
double rounded_exit(const SB& b, const RelativePose& rel, const Vec& x, const Vec& d, double r) {
  const Vec p = rel.rotation.transpose() * (x - rel.translation), dl = rel.rotation.transpose() * d;
  double s = 2.0 * r;
  for (int i = 0; i < 16; ++i) {
    Vec away;
    const double g = core_distance(b, p + s * dl, away) - r;
    const double slope = away.dot(dl);
    if (!(slope > 0.0)) break;
    const double step = g / slope;
    s -= step;
    if (!(std::abs(step) > 4.0 * std::numeric_limits<double>::epsilon() * s)) break;
  }
  return std::clamp(s, r, 2.0 * r);
}

// The candidates of B's cap or straight side line lying on face f of A along
// the normal n (A's frame, A -> B, within the angle tolerance of the face's
// normal nf), see manifold.hpp; ContactPath::none when neither lies along
// the face (or the clipping failed).
template <class SB>
ContactPath curved_candidates(const SatPolytope& pa, Index f, const Vec& n, const SB& b, const RelativePose& rel,
                              const ContactSettings& settings, double tol, CandidateList& candidates) {
  const Vec& nf = pa.plane(f).normal;
  const Vec axis = rel.rotation.col(2);  // B's z in A's frame
  const Vec centre = rel.translation;
  const double h = b.half_length;
  if constexpr (std::is_same_v<SB, Capsule>) {
    if (!segment_on_face(pa, f, n, centre - h * axis, centre + h * axis, tol, candidates)) return ContactPath::none;
    return ContactPath::segment;
  } else {
    // Cylinder: caps at +-h; cone: the base at -h only.
    const double cos_tol = std::cos(settings.face_angle_tolerance);
    const double an = axis.dot(nf);
    const bool cylinder = std::is_same_v<SB, Cylinder>;
    const bool cap_down = an >= cos_tol;             // the cap at -h faces A
    const bool cap_up = cylinder && -an >= cos_tol;  // the cap at +h faces A
    if (cap_down || cap_up) {
      const Vec cn = cap_up ? axis : Vec(-axis);
      cap_on_face(pa, f, n, centre + h * cn, cn, b.radius, rel.rotation.col(0), rel.rotation.col(1), tol, candidates);
      return ContactPath::cap;
    }
    // The side's straight line extreme along -n (radial -n): from the base
    // rim (a cylinder's and a cone's alike) to the top rim (cylinder) or the
    // apex (cone).
    Vec u = -(n - n.dot(axis) * axis);
    const double un = u.norm();
    if (!(un > 0.0)) return ContactPath::none;
    u /= un;
    const Vec s0 = centre - h * axis + b.radius * u;
    const Vec s1 = cylinder ? Vec(centre + h * axis + b.radius * u) : Vec(centre + h * axis);
    const Vec g = s1 - s0;
    if (!(std::abs(g.dot(nf)) <= std::sin(settings.face_angle_tolerance) * g.norm())) return ContactPath::none;
    if (!segment_on_face(pa, f, n, s0, s1, tol, candidates)) return ContactPath::none;
    return ContactPath::segment;
  }
}

// penetration()'s point for the pair; for a box against a capsule whose
// segment misses the box's core by more than the touching band, the same
// point in closed form (segment_box.hpp: the closest points of the segment
// and the box, exact where GJK iterates to its tolerance), the capsule's
// radius and the box's margin taken off along their normal.
template <class SA, class SB>
ContactResult curved_first_point(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, ContactCache* cache,
                                 const ContactSettings& settings) {
  if constexpr (std::is_same_v<SA, Box> && std::is_same_v<SB, Capsule>) {
    const RelativePose rel = relative_pose(pose_a, core_offset(a), pose_b, core_offset(b));
    const Vec axis = rel.rotation.col(2);
    const double scale = std::max(bounding_radius(a), bounding_radius(b));
    detail::SegmentBoxClosest c;
    if (detail::segment_box_closest(rel.translation - b.half_length * axis, rel.translation + b.half_length * axis,
                                    a.half_extents, settings.penetration.touching_band * scale, c)) {
      const WorldFrame world{pose_a, core_offset(a)};
      const Vec n = (c.on_segment - c.on_box) / c.distance;
      HEDRA_ASSERT(std::abs(n.squaredNorm() - 1.0) <= 1e-12);
      PenetrationResult p;
      p.distance = c.distance - core_radius(a) - core_radius(b);
      p.intersecting = p.distance <= 0.0;
      p.normal = world.direction(n);
      p.point_a = world.point(c.on_box + core_radius(a) * n);
      p.point_b = world.point(c.on_segment - core_radius(b) * n);
      return penetration_point(p, scale, settings);
    }
  }
  return single_point(a, pose_a, b, pose_b, cache, settings);
}

}  // namespace

// A polytope A against a capsule, cylinder or cone B. The manifold is built
// around penetration()'s normal n: the face of A within the angle
// tolerance of n is the reference, and B's cap or side line is clipped by
// that face's side planes swept along n (not along the face's normal: where
// the closest or deepest features are the face's edge and a part of B
// hanging over it, n is tilted and that part lies beyond the face's side
// plane but inside the swept one), so each point's separation is its gap
// along n and the deepest point is penetration()'s (its witnesses added
// where n's own error still cuts them away).
template <class SA, class SB>
ContactResult curved_contact(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, ContactCache* cache,
                             const ContactSettings& settings) {
  ContactResult first = curved_first_point(a, pose_a, b, pose_b, cache, settings);
  if (first.count == 0 || first.status != Status::ok) return first;
  BoxPolytopeStorage storage;
  SatPolytope pa;
  if (!polytope_view(a, storage, pa)) return first;
  const RelativePose rel = relative_pose(pose_a, core_offset(a), pose_b, core_offset(b));
  const double ra = core_radius(a), rb = core_radius(b);
  const WorldFrame world{pose_a, core_offset(a)};
  const Vec n = pose_a.rotation.transpose() * first.normal;  // A's frame, A -> B
  const Index f = face_along(pa, n, std::cos(settings.face_angle_tolerance));
  if (f == hull::kInvalidIndex) return first;
  const double scale = std::max(pa.scale, bounding_radius(b));
  const double tol = geometric_tolerance(scale);
  CandidateList candidates;
  ContactResult out;
  out.stats = first.stats;
  out.path = curved_candidates(pa, f, n, b, rel, settings, tol, candidates);
  if (out.path == ContactPath::none) return first;
  out.stats.clipped_points = static_cast<int>(candidates.size);
  // Rounded surfaces: A's side where the line along n leaves A's core grown
  // by ra (ra / cos of the tilt off the face, less near its edges). A
  // capsule is round about its segment: each point's exit along -n from the
  // segment (r / sin of the tilt on the side, less near an end), not the
  // radius. A capsule standing on the face, tilted so little that the line
  // through its upper end passes through the lower end's ball (2 half_length
  // sin(tilt) < r), has both lines leave it through that ball: one ball
  // against a face touches at one point, so of the points on one end's ball
  // only the deepest (penetration()'s, the ball's lowest) stays; a capsule
  // lying on the face keeps its two ends (on different balls, or the side).
  // Cylinders and cones: where the line along -n leaves the core grown by rb
  // (rb / cos of its angle to the core's normal there, less near a rim).
  const Placement identity{Eigen::Matrix3d::Identity(), Vec::Zero()};
  const Vec axis = rel.rotation.col(2);
  const Vec s0 = rel.translation - b.half_length * axis, s1 = rel.translation + b.half_length * axis;
  // The end ball a capsule's witness lies on (beyond that end along the
  // axis), or -1 (the side; cylinders and cones).
  const auto end_ball = [&](const Vec& on_b) {
    if constexpr (std::is_same_v<SB, Capsule>) {
      const Vec d = s1 - s0;
      if ((on_b - s0).dot(-d) > tol * d.norm()) return 0;
      if ((on_b - s1).dot(d) > tol * d.norm()) return 1;
    }
    return -1;
  };
  std::array<int, kClipCapacity> balls;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < candidates.size; ++i) {
    Candidate x = candidates[i];
    const double ta = ra > 0.0 ? exit_distance(pa, identity, f, x.on_a, n, ra) : 0.0;
    double tb = 0.0;
    if constexpr (std::is_same_v<SB, Capsule>)
      tb = std::max(segment_exit(x.on_b, -n, s0, s1, rb), segment_exit(x.on_b, -n, s1, s0, rb));
    else if (rb > 0.0)
      tb = rounded_exit(b, rel, x.on_b, -n, rb);
    x.on_a += ta * n;
    x.on_b -= tb * n;
    x.separation -= ta + tb;
    // The same point, or the same end ball: the deeper stays.
    const int ball = end_ball(x.on_b);
    std::size_t same = kept;
    for (std::size_t k = 0; k < kept && same == kept; ++k)
      if ((candidates[k].on_b - x.on_b).norm() <= tol || (ball >= 0 && balls[k] == ball)) same = k;
    if (same < kept) {
      if (x.separation < candidates[same].separation) candidates[same] = x;
      continue;
    }
    balls[kept] = ball;
    candidates[kept++] = x;
  }
  candidates.size = kept;
  add_witnesses_if_missed(first, world, settings.penetration.touching_band * scale, candidates);
  const Ties ties{settings.penetration.touching_band * scale, tol};
  emit(candidates, n, 0.0, 0.0, keep_below(settings, scale + std::max(ra, rb)), ties, world, out);
  if (out.count == 0) return first;
  out.error_bound = detail::bound_within(out.distance, out.error_bound, first.distance, first.error_bound);
  return out;
}

// The six pairs contact_typed routes here (pair_table.hpp: polytope_curved).
template ContactResult curved_contact<Box, Capsule>(const Box&, const Pose&, const Capsule&, const Pose&, ContactCache*,
                                                    const ContactSettings&);
template ContactResult curved_contact<Box, Cylinder>(const Box&, const Pose&, const Cylinder&, const Pose&,
                                                     ContactCache*, const ContactSettings&);
template ContactResult curved_contact<Box, Cone>(const Box&, const Pose&, const Cone&, const Pose&, ContactCache*,
                                                 const ContactSettings&);
template ContactResult curved_contact<Polyhedron, Capsule>(const Polyhedron&, const Pose&, const Capsule&, const Pose&,
                                                           ContactCache*, const ContactSettings&);
template ContactResult curved_contact<Polyhedron, Cylinder>(const Polyhedron&, const Pose&, const Cylinder&,
                                                            const Pose&, ContactCache*, const ContactSettings&);
template ContactResult curved_contact<Polyhedron, Cone>(const Polyhedron&, const Pose&, const Cone&, const Pose&,
                                                        ContactCache*, const ContactSettings&);

}  // namespace hedra::collision::detail::manifold
