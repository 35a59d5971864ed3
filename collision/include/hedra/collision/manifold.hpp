// Contact manifolds: up to four contact points for a pair of posed shapes,
// the input a simulator's contact solver needs.
//
//   ContactResult contact(a, pose_a, b, pose_b, cache, settings)
//
// The contract (which path a pair takes, how the points are chosen and
// reduced, the rounded shapes' depths, what the cache keeps and when a warm
// answer may differ from a cold one) is described once, in docs/contacts.md,
// "How the points are chosen"; the pair table is collision/src/pair_table.hpp.
// What every answer promises (asserted in builds with HEDRA_ASSERT on):
//   * count <= kMaxContactPoints (4); with points (count > 0):
//   * normal: unit, world frame, from A toward B;
//   * point_b - point_a = distance * normal (the deepest point's witnesses);
//   * each point's depth is the gap of the two surfaces along the normal at
//     that point (> 0 overlap, < 0 a speculative gap);
//   * points[0] is the point of point_a and point_b (depth = -distance), the
//     deepest up to the reduction's ties and ContactSettings::hold;
//   * error_bound: the exact signed distance lies within it of `distance`
//     (infinite when nothing bounds it: separated beyond the contact
//     distance, invalid input);
//   * everything in world coordinates; no allocation per query; the
//     ContactCache is the caller's, one per pair.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <hedra/collision/query.hpp>
#include <hedra/hull/half_edge_mesh.hpp>
#include <limits>

namespace hedra::collision {

// Which path answered (ContactResult::path).
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

// One contact point: on A at point + (depth / 2) normal, on B at
// point - (depth / 2) normal.
struct ContactPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world: midway between the surfaces
  double depth = 0.0;                               // world length along the normal: > 0 overlap, < 0 a gap
  FeatureId id;                                     // stable across frames while the same features touch
};

inline constexpr int kMaxContactPoints = 4;

// The kind of a polytope pair's contact axis (ContactCache::axis): a face of
// A, a face of B, or an edge of each.
enum class SatAxisKind { none, face_a, face_b, edge };

// How a polytope pair's contact axis is found (docs/contacts.md).
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
  // Bias towards face contacts (docs/contacts.md): a challenger axis must
  // separate by more than relative_bias |s| + absolute_bias size beyond the
  // incumbent's s (relative: a fraction of |s|; absolute: of the pair's size).
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

// Per-pair state a caller keeps between frames (one per pair and thread);
// every cached item is re-measured at the new poses before it is used.
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

// Results are in world coordinates.
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

// Up to four contact points of a and b at their poses (world). Inputs are
// checked here, once (invalid_input: a shape failing validate(), a pose not
// Pose::valid(), a pair out of range, a non-finite contact distance).
// `cache` (optional): the pair's warm start, updated by the call.
ContactResult contact(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                      ContactCache* cache = nullptr, const ContactSettings& settings = {});

}  // namespace hedra::collision
