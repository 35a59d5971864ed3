// Contact manifolds: up to four contact points for a pair of posed shapes,
// the input a simulator's contact solver needs.
//
//   ContactResult contact(a, pose_a, b, pose_b, cache, settings)
//
// Paths (ContactResult::path says which ran):
//   * polytopes (Box, and Polyhedron with a solid hull) against polytopes,
//     in A's core frame. The candidate axes come from one of two searches
//     (ContactSettings::axis_search; by default SAT when E_A x E_B <= 150
//     edge pairs, two boxes among them, else the exact normal):
//       SAT (sat.hpp): A's best face, B's best face, the best edge pair;
//       exact normal: penetration()'s signed distance s* and normal n
//       (GJK, EPA when the cores overlap); the face candidates are, on each
//       side, the face at the support vertex along n most nearly along n,
//       and the edge axis is n itself with s*. SAT's largest separation is
//       s*, so both searches agree up to which face wins within the bias,
//       and the exact normal costs penetration() and two face measurements
//       instead of SAT's E_A x E_B edge pairs.
//     Then
//       face contact: the reference face is the face axis (A's, or B's when
//       B's is better by the bias below); the incident face is the face of
//       the other shape most anti-parallel to it, searched only around the
//       other shape's support vertex (its ring of faces). The incident
//       polygon is clipped by the side planes of the reference face's edges
//       (hull::clip_polygon, no allocation); points whose separation from
//       the reference plane is <= the contact distance (plus the touching
//       band, below) are kept, and
//       reduced to four: the deepest, the one farthest from it, then the
//       largest positive and negative signed triangle areas with those two
//       (the quadrilateral of largest area these choices can reach), each
//       choice the first candidate in the clipped polygon's order within a
//       tie of the best (depths: the touching band; lengths: 1e-6 of the
//       size), so a resting polygon's equally deep corners do not swap with
//       rounding noise; with a cache, the last frame's four while they hold
//       (ContactSettings::hold, below);
//       edge contact: one point, the closest points of the two edges (the
//       exact normal: penetration()'s witnesses, named by the edges at the
//       support vertices most nearly perpendicular to n).
//     Face axes are preferred over edge axes, and A's face over B's (B's
//     when the cache holds B's same face from the last frame): the
//     challenger must beat the incumbent by relative_bias |s| +
//     absolute_bias scale, so a tilt of 1e-6 rad never flips the manifold.
//     The reported depth is therefore at most that bias above the exact
//     penetration depth (ContactResult::error_bound says by how much). It
//     is the overlap along the reported normal, h_A(n) + h_B(-n), and the
//     deepest point is that deep: a face contact whose clipping cut away
//     the incident shape's deepest vertex (no point can be as deep as its
//     axis) follows the exact normal as for cores apart below
//     (contact_depth.hpp).
//   * a capsule against a polytope: the penetration normal (penetration());
//     when it is within face_angle_tolerance of a face normal of the
//     polytope the capsule's segment is clipped by that face's side planes
//     swept along the normal: one or two points (a capsule lying on a face
//     gets two; one standing on it, tilted or not, one: the points on one
//     end's ball are that ball's lowest); otherwise one point. Curved paths keep penetration()'s
//     normal (the points' depths are gaps along it) and add its witnesses
//     when every clipped point is shallower than they are.
//   * a cylinder or cone against a polytope: the penetration normal; when it
//     is near a face normal and a flat cap of the shape lies against that face
//     (cap axis within face_angle_tolerance of the normal) the exact region
//     cap disc x face polygon (projected along the normal) is sampled without approximating the disc by a
//     polygon: candidates are the disc's rim points on the shape's local +-x,
//     +-y and the deepest rim point (when inside the polygon), the polygon's
//     vertices inside the disc, and the exact crossings of the polygon's
//     edges with the rim circle (all on the region's boundary), reduced to
//     four as above. When instead a straight line of the side (cylinder:
//     a generator; cone: apex to rim) lies along the face, that segment is
//     clipped like a capsule's. Otherwise one point.
//   * every other pair (spheres, curved against curved, point/segment/flat
//     hulls): one point from penetration().
// Two boxes take box_box.cpp's path: the polytope path above written for the
// box (SAT from the relative rotation, no support call), the same answers
// (ContactSettings::box_box_path = false runs the general one).
// Margins (rounded shapes): every point's depth is the gap of the rounded
// surfaces on its line along the normal (the reference side its radius out
// of the face; the incident side where the line leaves the incident core
// grown by its radius: r / cos(tilt) off a tilted face). Cores apart
// (rounded or sharp, within the contact distance): SAT only bounds their
// distance, so the manifold follows the exact normal n of the cores (GJK's):
// when n is within face_angle_tolerance of a face normal of A or B (a face
// against the other's face, edge or corner, or an edge or corner of the face
// against a part hanging beyond it: n tilted), a face contact with n as its
// normal: the incident face clipped by the reference face's side planes
// swept along n, each point's depth the gap of the rounded surfaces on its
// line along n (both sides' exits from their grown cores), the deepest
// penetration()'s; otherwise penetration()'s point.
//
// Points. Each ContactPoint holds the midpoint between the two surfaces and
// the depth along the normal: the point on A is point + (depth / 2) normal,
// the point on B is point - (depth / 2) normal (depth < 0: a speculative
// point, the surfaces depth apart). Feature ids are built from half-edge,
// face and vertex indices (stable across frames while the same features
// touch), so a solver can match points and warm-start its impulses.
//
// Frames: all the geometry runs in A's core frame (B placed by the relative
// pose), and results return to world coordinates at the end.
//
// Memory: fixed-size storage on the stack; no allocation per query (the
// shared unit-box topology is built once, on the first box query).
//
// Cache: a ContactCache per pair carries GJK's warm start, the polytopes'
// support vertices (hill-climbing starts) and the last axis (a face, or an
// edge pair), re-measured at the new poses before any search:
//   * separated along it by more than the contact distance: answered from
//     that axis alone (separated; the distance a lower bound, as SAT's);
//   * otherwise certified exact when it is (manifold.cpp: the origin's foot
//     inside the axis's facet of the Minkowski difference, or the ball of
//     the depth inside the pyramid of that facet and a support point; a
//     face's facet is the reference face against the other shape's support
//     vertex, or against its incident face's vertices at the support level
//     when that alone does not certify: a body resting face on face): the
//     axis a cold query would choose, so the manifold is built from it
//     without SAT or GJK/EPA (an edge pair still meets the faces about its
//     axis through the bias). A face with the cores overlapping or touching
//     is certified within the bias (relative_bias |s| + absolute_bias size,
//     choose_axis's: no challenger could beat it); an edge pair, or cores
//     apart, within the touching band;
//   * otherwise the full search runs, and a cached reference face of B that
//     is still B's candidate stays the incumbent (the reference face does
//     not swap while the same faces touch).
//   * a face contact with more than four candidates keeps the last frame's
//     four points (ContactCache::kept) while all are still candidates and
//     their deepest lies within ContactSettings::hold (a fraction of the
//     size; 0 by default) of the deepest candidate: a solver's corrections move a resting polygon's depths by
//     1e-6 to 1e-4 of the size a frame, and the cold choice would swap its
//     points every few frames.
// Warm answers equal cold ones but for that kept face of B (within the
// bias), a cached face kept while another face of the same shape
// separates by less than the bias more (a cold query takes that one), the
// held points (the deepest within the
// hold) and ties (two axes exact to rounding: the same distance).
// tests/collision/frame_coherence_test.cpp checks it on moving pairs.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <hedra/collision/query.hpp>
#include <hedra/collision/sat.hpp>

namespace hedra::collision {

enum class ContactPath {
  none,          // invalid input or a failure before any geometry
  separated,     // SAT (or the cached axis) proved a gap beyond contact_distance
  face_a,        // reference face on A, incident face on B clipped
  face_b,        // reference face on B, incident face on A clipped
  edge,          // edge-edge: one point
  segment,       // a capsule's segment or a straight side line clipped by a face
  cap,           // a cylinder's or cone's cap disc against a face
  single_point,  // one point from penetration()
};

const char* to_string(ContactPath path);

enum class FeatureKind : std::uint8_t {
  none,
  face_vertex,  // an incident vertex kept by the clipping: incident = vertex index
  face_clip,    // an incident edge cut by the side plane of reference half-edge `clip`:
                // incident = the incident half-edge (or its twin, the smaller index)
  face_corner,  // a corner of the reference face (on no incident edge): clip = the
                // reference half-edge leaving that corner, incident = the incident face
  edge,         // edge-edge: reference = A's half-edge, incident = B's half-edge
  segment,      // capsule / side line: incident = 0 or 1 (an end kept), or 2 (cut by the side
                // plane of reference half-edge `clip`)
  cap,          // cap disc: incident = 0..3 rim on +-x +-y, 4 deepest rim, 8 + vertex, 1 << 20 + half-edge crossing
  single,       // penetration()'s point
};

// Identifies a contact point by the features that make it.
struct FeatureId {
  FeatureKind kind = FeatureKind::none;
  bool reference_on_b = false;                    // the reference face belongs to B
  std::uint32_t reference = hull::kInvalidIndex;  // reference face (edge: A's half-edge)
  std::uint32_t clip = hull::kInvalidIndex;       // reference half-edge whose side plane made the point
  std::uint32_t incident = hull::kInvalidIndex;   // see FeatureKind
  bool operator==(const FeatureId& o) const {
    return kind == o.kind && reference_on_b == o.reference_on_b && reference == o.reference && clip == o.clip &&
           incident == o.incident;
  }
  bool operator!=(const FeatureId& o) const { return !(*this == o); }
};

struct ContactPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world: midway between the surfaces
  double depth = 0.0;                               // > 0 penetration, < 0 speculative gap
  FeatureId id;
};

inline constexpr int kMaxContactPoints = 4;

// How a polytope pair's contact axis is found (see the top of the file).
enum class PolytopeAxisSearch {
  automatic,     // sat when the edge counts' product is at most max_sat_edge_pairs
  sat,           // the full separating-axis test
  exact_normal,  // penetration()'s exact normal, faces around its support features
};

struct ContactSettings {
  // Speculative margin (world length): pairs closer than this return their
  // points with negative depth; 0 reports touching and overlapping pairs only.
  // Touching counts up to penetration.touching_band of the pair's size
  // (1e-9): surfaces placed exactly touching are 0 apart only up to
  // rounding, and their points are kept (depth ~ 0, either sign).
  double contact_distance = 0.0;
  // Bias towards face contacts (see the top of the file): relative to the
  // incumbent separation's magnitude, absolute as a fraction of the pair's size.
  double relative_bias = 0.05;
  double absolute_bias = 1e-4;
  // A normal counts as a face normal (and a cap or side line as lying on a
  // face) within this angle, radians.
  double face_angle_tolerance = 1e-3;
  // SAT: edge pairs closer to parallel than this (sine) are skipped.
  double parallel_tolerance = 0.005;
  // Polytope pairs: SAT or the exact normal. SAT's edge loop visits
  // E_A x E_B edge pairs; above this product the exact normal is cheaper
  // (two boxes: 144 pairs, SAT in closed form).
  PolytopeAxisSearch axis_search = PolytopeAxisSearch::automatic;
  double max_sat_edge_pairs = 150.0;
  // Warm queries (a ContactCache given): a face contact with more than four
  // candidates keeps the last frame's four points while all four are still
  // candidates and their deepest lies within this fraction of the pair's size
  // of the deepest candidate (the deepest point then that much shallower at
  // most); 0 (the default: warm answers equal cold ones) keeps the cold
  // choice (deepest first) every frame. A simulator whose solver does not
  // hold points itself may want about 1e-6 (docs/contacts.md).
  double hold = 0.0;
  // Box pairs take their own path (box_box.cpp: SAT in closed form, the same
  // answers); false runs the general polytope path on them (for comparisons).
  bool box_box_path = true;
  PenetrationSettings penetration;  // for the paths that use penetration()
};

// Box pairs (box_box.cpp): the last answer in A's frame with the relative
// pose and inputs it was computed for. Used only when the new relative pose
// and inputs are bit for bit the same (the answer is then the same: only its
// world placement is redone); anything else rebuilds the manifold.
struct BoxPairMemory {
  bool valid = false;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Zero();  // B in A's frame
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  std::array<double, 12> inputs{};  // half extents, margins and settings it was computed with
  ContactPath path = ContactPath::none;
  double distance = 0.0;
  double error_bound = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // A's frame
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero(), point_b = Eigen::Vector3d::Zero();
  int count = 0;
  std::array<ContactPoint, kMaxContactPoints> points{};  // A's frame
  int edge_pairs = 0, clipped_points = 0;                // its ContactStats
};

struct ContactCache {
  GjkCache gjk;
  SatAxisKind axis = SatAxisKind::none;         // last axis (polytope pairs)
  hull::Index feature = hull::kInvalidIndex;    // its face, or A's half-edge for an edge axis
  hull::Index feature_b = hull::kInvalidIndex;  // B's half-edge for an edge axis
  // The polytopes' last support vertices (hill-climbing starts; an answer
  // does not depend on them beyond ties between equal supports).
  hull::Index support_a = 0, support_b = 0;
  hull::Index far_a = 0, far_b = 0;  // the same on the far sides (the certificate's apex)
  // The last answer's points (ContactSettings::hold).
  int kept_count = 0;
  std::array<FeatureId, kMaxContactPoints> kept{};
  BoxPairMemory box;  // box pairs: the last answer (box_box.cpp)
};

struct ContactStats {
  bool cache_hit = false;  // answered from the cached face axis (separated, or certified exact), or a box
                           // pair's last answer (its relative pose bit for bit the same: ContactCache::box)
  int edge_pairs = 0;      // SAT edge pairs that passed the Gauss-map test
  int clipped_points = 0;  // points after clipping, before the contact-distance filter and reduction
};

struct ContactResult {
  Status status = Status::ok;
  bool intersecting = false;  // distance <= 0
  // Signed distance along `normal`: < 0 the penetration depth of the chosen
  // axis. For a polytope pair separated beyond the contact distance it is
  // the SAT separation, a lower bound on the distance.
  double distance = 0.0;
  // Certified: the exact signed distance of the two shapes lies in
  // [distance - error_bound, distance + error_bound] (rounding included).
  // It covers the face bias (a face kept while another axis overlaps less)
  // and penetration()'s own bound on the paths that use it. +infinity when
  // nothing bounds it: the pair separated beyond the contact distance (path
  // `separated`: the distance only a lower bound), or invalid input.
  double error_bound = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, from A toward B, world
  // The deepest point's witnesses on A and B (world).
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  int count = 0;  // contact points in points[0, count)
  std::array<ContactPoint, kMaxContactPoints> points{};
  ContactPath path = ContactPath::none;
  ContactStats stats;
};

ContactResult contact(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                      ContactCache* cache = nullptr, const ContactSettings& settings = {});

}  // namespace hedra::collision
