// What the contact paths share (manifold.cpp, contact_clip.cpp,
// contact_polytopes.cpp, contact_curved.cpp): candidate points in A's core
// frame, the frames, the clipping of an incident face by a reference face's
// side planes and the reduction to four points (contact_clip.cpp), the
// polytope pair's state (contact_polytopes.cpp), the curved shapes against a
// polytope (contact_curved.cpp). What they build: docs/contacts.md, "How the
// points are chosen". Nothing here allocates: fixed-capacity buffers on the
// caller's stack.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <hedra/collision/detail/sat.hpp>
#include <hedra/collision/manifold.hpp>
#include <new>
#include <type_traits>

#include "query_detail.hpp"

namespace hedra::collision::detail::manifold {

using Vec = Eigen::Vector3d;
using hull::Index;

// Clip buffers: an incident polygon of n vertices clipped by m side planes
// has at most n + m points; faces whose sum exceeds this take the single
// point path instead (no allocation, ever).
constexpr std::size_t kClipCapacity = 256;

// Fixed-capacity storage left uninitialised (types with default member
// initialisers would otherwise be written in full on every query: 8 kB of
// side planes cost a quarter of a box-box query).
template <class T, std::size_t N>
class UninitializedArray {
 public:
  UninitializedArray() {}
  static_assert(std::is_trivially_destructible_v<T>);
  T& operator[](std::size_t i) { return reinterpret_cast<T*>(storage_)[i]; }
  const T& operator[](std::size_t i) const { return reinterpret_cast<const T*>(storage_)[i]; }
  void set(std::size_t i, const T& value) { new (storage_ + i * sizeof(T)) T(value); }

 private:
  alignas(T) unsigned char storage_[sizeof(T) * N];
};

// A candidate contact point in A's core frame: its witnesses on the two
// cores and its separation along the normal (> 0: a gap).
struct Candidate {
  Vec on_a;
  Vec on_b;
  double separation;
  FeatureId id;
};

// Fixed capacity, left uninitialised until pushed (a few kB per query that
// default-initialising would write for nothing).
class CandidateList {
 public:
  CandidateList() {}
  std::size_t size = 0;
  Candidate& operator[](std::size_t i) { return data()[i]; }
  const Candidate& operator[](std::size_t i) const { return data()[i]; }
  void push(const Vec& on_a, const Vec& on_b, double separation, const FeatureId& id) {
    if (size < kClipCapacity) new (&data()[size++]) Candidate{on_a, on_b, separation, id};
  }

 private:
  static_assert(std::is_trivially_destructible_v<Candidate>);
  Candidate* data() { return reinterpret_cast<Candidate*>(storage_); }
  const Candidate* data() const { return reinterpret_cast<const Candidate*>(storage_); }
  alignas(Candidate) unsigned char storage_[sizeof(Candidate) * kClipCapacity];
};

// What counts as equal in the reduction: depths within `depth` (the
// touching band: equal to rounding), lengths within `length` (the geometric
// tolerance, as for the clipping).
struct Ties {
  double depth;
  double length;
  // Warm queries: the last frame's kept points (null: none) stay kept while
  // all are still candidates and their deepest is within `hold` of the
  // deepest candidate.
  const ContactCache* last = nullptr;
  double hold = 0.0;
};

// The frame of A's core in the world: x_world = R_a (offset_a + x) + t_a.
struct WorldFrame {
  const Pose& pose;
  Vec offset;
  Vec point(const Vec& x) const { return pose.rotation * (offset + x) + pose.translation; }
  Vec direction(const Vec& d) const { return pose.rotation * d; }
  Vec local(const Vec& x) const { return pose.rotation.transpose() * (x - pose.translation) - offset; }
};

// A placement of a polytope's frame in A's core frame: x -> R x + t
// (identity for A itself).
struct Placement {
  Eigen::Matrix3d rotation;
  Vec translation;
  Vec point(const Vec& x) const { return rotation * x + translation; }
  Vec direction(const Vec& d) const { return rotation * d; }
};

// A polytope's SAT view, or false when it has no solid (3D) hull.
inline bool polytope_view(const Box& box, BoxPolytopeStorage& storage, SatPolytope& out) {
  out = sat_polytope(box, storage);
  return true;
}
inline bool polytope_view(const Polyhedron& p, BoxPolytopeStorage&, SatPolytope& out) {
  if (p.hull->dimension() != 3) return false;
  out = sat_polytope(*p.hull);
  return true;
}

inline bool solid(const Box&) { return true; }
inline bool solid(const Polyhedron& p) { return p.hull->dimension() == 3; }

inline double scale_of(const SatPolytope& a, const SatPolytope& b) { return std::max(a.scale, b.scale); }

// Tolerance of the side-plane clipping and of "on a plane / on an edge"
// decisions: a point within it of a side plane counts as on it, so an
// incident vertex that a tilt of 1e-6 rad moves across the side plane of an
// equally wide reference face (stacked equal boxes) stays one vertex with one
// feature id instead of flipping between a vertex and a clipped point. The
// price: kept points may lie that far outside the reference face.
inline double geometric_tolerance(double scale) { return 1e-6 * scale; }

// The largest separation that still yields points: the contact distance
// plus the touching band of penetration() (a fraction of the pair's size).
// Touching surfaces are 0 apart only up to rounding: SAT's separation, a
// clipped point's, or penetration()'s distance of a pair placed exactly
// touching comes out +-1e-16 of the size, and a filter against the bare
// contact distance (0 by default) dropped every point of a resting body.
inline double keep_below(const ContactSettings& settings, double scale) {
  return settings.contact_distance + settings.penetration.touching_band * scale;
}

inline void flip(ContactResult& r) {
  r.normal = -r.normal;
  std::swap(r.point_a, r.point_b);
  for (int k = 0; k < r.count; ++k) r.points[k].id.reference_on_b = !r.points[k].id.reference_on_b;
}

// ---- clipping and reduction (contact_clip.cpp) ------------------------------

// Reduction to at most four points (docs/contacts.md): the indices kept.
int reduce(const CandidateList& c, const Vec& n, const Ties& ties, std::array<std::size_t, kMaxContactPoints>& keep);

// Shifts the cores' candidates by the radii, keeps those separated by at
// most max_separation, reduces to four and writes the world result.
void emit(CandidateList& c, const Vec& normal, double radius_a, double radius_b, double max_separation,
          const Ties& ties, const WorldFrame& world, ContactResult& out);

// The incident face for a reference normal n (A's frame, out of the reference).
Index incident_face(const SatPolytope& inc, const Placement& inc_place, const Vec& n);

// How far the ray p + t d (p on face f of a core, d unit, A's frame) runs
// inside the core grown by radius r.
double exit_distance(const SatPolytope& poly, const Placement& place, Index f, const Vec& p_in, const Vec& d_in,
                     double r);

// Face contact: the incident face clipped by the reference face's side
// planes (swept along `along`, null: the face's normal), reduced to four.
// False when a face is too large for the fixed buffers.
bool face_contact(const SatPolytope& ref, const Placement& ref_place, const SatPolytope& inc,
                  const Placement& inc_place, Index ref_face, bool ref_is_a, const Ties& ties, double max_separation,
                  CandidateList& out, int& clipped, const Vec* along = nullptr);

// Rounded shapes: face candidates moved onto the rounded surfaces along the
// reference face's normal nf (round_candidates) or along a tilted normal
// (round_along).
void round_candidates(CandidateList& c, const Vec& nf, bool ref_is_a, double r_ref, const SatPolytope& inc,
                      const Placement& inc_place, Index inc_face, double r_inc);
void round_along(CandidateList& c, const Vec& along, bool ref_is_a, const SatPolytope& ref, const Placement& ref_place,
                 Index ref_face, double r_ref, const SatPolytope& inc, const Placement& inc_place, Index inc_face,
                 double r_inc);

// The face of `poly` whose normal is closest to n, if within the angle
// tolerance (cosine cos_tol); else kInvalidIndex.
Index face_along(const SatPolytope& poly, const Vec& n, double cos_tol);

// penetration()'s answer as a one-point contact (scale: the larger bounding radius).
ContactResult penetration_point(const PenetrationResult& p, double scale, const ContactSettings& settings);

// penetration()'s witnesses as one more candidate when every candidate is
// shallower than they are by more than `slack`.
void add_witnesses_if_missed(const ContactResult& first, const WorldFrame& world, double slack, CandidateList& c);

// The world result from penetration(): one point.
template <class SA, class SB>
ContactResult single_point(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, ContactCache* cache,
                           const ContactSettings& settings) {
  const PenetrationResult p =
      detail::penetration_unchecked(a, pose_a, b, pose_b, cache ? &cache->gjk : nullptr, settings.penetration);
  return penetration_point(p, std::max(bounding_radius(a), bounding_radius(b)), settings);
}

// ---- polytope pairs (contact_polytopes.cpp) --------------------------------

// A polytope pair as the manifold builder sees it, in A's core frame.
struct PolytopePair {
  SatPolytope pa, pb;
  RelativePose rel;
  double ra = 0.0, rb = 0.0;           // margins
  double scale = 0.0;                  // the pair's size
  double keep = 0.0;                   // largest separation that yields points (rounded surfaces)
  double band = 0.0;                   // penetration()'s touching band at the pair's size
  const ContactCache* last = nullptr;  // the last frame's kept points (warm queries)
  double hold = 0.0;                   // how far they may be shallower (ContactSettings::hold)
  double core_contact = 0.0;           // the same between the cores
  double shape_scale = 0.0;            // max bounding radius, as single_point measures it
  // penetration() on the pair's typed shapes, inputs checked by contact()
  // (set by polytope_contact, which knows the types).
  const void* shape_a = nullptr;
  const void* shape_b = nullptr;
  const Pose* pose_a = nullptr;
  const Pose* pose_b = nullptr;
  PenetrationResult (*penetrate)(const PolytopePair&, ContactCache*, const ContactSettings&) = nullptr;
  PenetrationResult penetration(ContactCache* cache, const ContactSettings& settings) const {
    return penetrate(*this, cache, settings);
  }
  Placement identity{Eigen::Matrix3d::Identity(), Vec::Zero()};
  Placement placed_b;
};

// penetration()'s answer as the pair's one point.
ContactResult single_point(const PolytopePair& pp, ContactCache* cache, const ContactSettings& settings);

// The polytope path on a ready pair (docs/contacts.md): the cached axis
// re-measured, else SAT or the exact normal, then the face or edge contact;
// the cache updated.
ContactResult polytope_manifold(PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
                                const ContactSettings& settings);

// ---- curved shapes against a polytope (contact_curved.cpp) ------------------

// A polytope A (Box, Polyhedron) against a capsule, cylinder or cone B;
// instantiated in contact_curved.cpp for those six pairs.
template <class SA, class SB>
ContactResult curved_contact(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, ContactCache* cache,
                             const ContactSettings& settings);

}  // namespace hedra::collision::detail::manifold
