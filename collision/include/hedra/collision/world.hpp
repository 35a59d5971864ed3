// World: bodies (shape + pose + collision filter), a BVH over their world
// boxes, and the all-pairs query on all cores.
//
// Boxes. A body's box is tight: per world axis k the exact extent of the
// shape along +-e_k (closed forms for spheres, boxes, capsules, cylinders
// and cones, support vertices for hulls, margins added), not the cube of the
// bounding sphere. It is then grown by the body's allowance
//   w_i = kBoxBand r_i + kBoxRounding (|t_i|_inf + rho_i),
// r_i the bounding radius, rho_i a bound on |x| over the shape's local frame
// (r_i, plus the centroid offset of a hull).
//
// Never missed (the proof; docs/batch.md has the long form). pairs() keeps a
// candidate when its query says distance <= D + kTouchingBand s (D =
// max_distance, s = the larger bounding radius of the two; contact: the pair
// was not proved separated beyond D). Queries return a distance no smaller
// than the true one less their rounding rho_q <= c eps (|t_a - t_b| + rho_a
// + rho_b), c of a few hundred at most (GJK's |v| is the norm of a point of
// the computed Minkowski difference). So a kept pair is truly within
// D' = D + kTouchingBand s + rho_q. Two convex sets within D' have points
// p, q with |p - q| <= D', hence on every axis lo_B - hi_A <= q_k - p_k <= D'
// for their exact boxes. The stored boxes hold the exact boxes grown by
// kBoxBand r (their own rounding, a few eps (|t| + rho), is inside the
// kBoxRounding term), and kBoxBand (r_a + r_b) >= 2 kBoxBand s >
// kTouchingBand s, kBoxRounding (|t_a| + |t_b| + rho_a + rho_b) > rho_q
// (kBoxRounding = 1e-12, about 4500 eps). The traversal grows the query
// box by D and by kBoxRounding (|x| + D) for the rounding of that addition,
// and compares exactly. Hence every kept pair's stored boxes, grown by D,
// overlap: it was a candidate. (The query tolerances must stay below
// kBoxBand / 2 of the size: the defaults are 1e-10, the touching band 1e-9.)
//
// BVH: median split on the longest axis of the box centres (ties by body
// index: the tree depends on the boxes only), up to kLeafSize bodies a
// leaf, nodes in depth-first order (a parent before its children), the
// bodies in leaf order (spatially coherent), each node keeping the last leaf
// position below it. pairs() runs in three steps:
//   1. candidates: in parallel_for's fixed chunks of leaf positions, each
//      body's grown box against the tree, pruning subtrees that lie wholly
//      before it in leaf order (each pair is visited once, from its earlier
//      body), keys (a << 32 | b, a < b) per chunk;
//   2. the keys of all chunks sorted (LSD radix sort): the order (a, b);
//   3. the queries, in fixed chunks of the sorted candidates: a pair that
//      GJK's boolean test certifies apart by more than the reach
//      (separated_beyond) is dropped without the full query; the others run
//      it and are kept by the rule above; the chunks' results are
//      concatenated in chunk order.
// Every step's output depends on the boxes only, never on the thread count.
//
// Moving bodies: set_pose / set_poses mark boxes stale; pairs() recomputes
// them and refits the tree (reverse depth-first order: children before
// parents) unless a rebuild pays. The rule (measured, docs/batch.md): rebuild
// when bodies were added, or when the refitted tree's cost (the sum of its
// internal nodes' surface areas) exceeds kRebuildCostRatio times the cost
// right after the last build.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/parallel.hpp>
#include <hedra/collision/pose.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/shapes.hpp>
#include <vector>

namespace hedra::collision {

enum class PairQuery { intersect, distance, penetration, contact };

struct PairResult {
  std::uint32_t a = 0, b = 0;  // body indices, a < b
  Status status = Status::ok;
  bool intersecting = false;
  double distance = 0.0;  // intersect: 0; distance: >= 0; penetration/contact: signed
  Eigen::Vector3d normal = Eigen::Vector3d::Zero(), point_a = Eigen::Vector3d::Zero(),
                  point_b = Eigen::Vector3d::Zero();
  double error_bound = 0.0;
  int count = 0;                                         // contact only: points in points[0, count)
  std::array<ContactPoint, kMaxContactPoints> points{};  // contact only
};

// How pairs() brings the tree up to date after poses moved.
enum class TreeUpdate {
  automatic,  // refit, or rebuild by the rule above
  refit,      // always refit (rebuild only when bodies were added)
  rebuild,    // always rebuild
};

struct PairSettings {
  double max_distance = 0.0;  // report every pair whose distance is <= max_distance (>= 0)
  PairQuery query = PairQuery::penetration;
  ParallelSettings parallel;
  ContactSettings contact;  // for query == contact (its contact_distance is set to max_distance)
  PenetrationSettings penetration;
  GjkSettings gjk;
  TreeUpdate tree_update = TreeUpdate::automatic;
  // The broadphase alone: every pair whose grown boxes (grown by max_distance) overlap and that passes the
  // filter, with a and b only (no query runs; every other field at its default).
  bool broadphase_only = false;
};

// What the last pairs() did (for benchmarks and tuning).
struct WorldStats {
  std::size_t candidates = 0;       // pairs whose grown boxes overlap and that pass the filter
  std::size_t pairs = 0;            // pairs reported
  bool rebuilt = false;             // the tree was rebuilt (else refitted or unchanged)
  double tree_cost_ratio = 1.0;     // the tree's cost over its cost at the last build
  double update_seconds = 0.0;      // boxes + refit or rebuild
  double query_seconds = 0.0;       // traversal + queries + merge
  double broadphase_seconds = 0.0;  // of which traversal and sort (steps 1 and 2)
  double serial_seconds = 0.0;      // on the calling thread alone: refit or build, sort, merge
  std::size_t memory_bytes = 0;     // the world's own arrays (capacity), shapes' hulls excluded
};

// Bodies (shape + pose + collision filter), a BVH over their tight world boxes, and the all-pairs query.
class World {
 public:
  static constexpr std::uint32_t kInvalidBody = 0xFFFFFFFFu;
  static constexpr double kTouchingBand = 1e-9;  // kept beyond max_distance: this fraction of the pair's size
  static constexpr double kBoxBand = 1e-8;       // boxes grown by this fraction of the body's size
  static constexpr double kBoxRounding = 1e-12;  // and this fraction of its coordinates' magnitude
  static constexpr std::size_t kLeafSize = 4;
  static constexpr double kRebuildCostRatio = 1.5;

  // The body's index (0, 1, 2, ... in order of adding; never renumbered), or kInvalidBody (and nothing added)
  // when !validate(shape).ok() or !pose.valid().
  std::uint32_t add(const Shape& shape, const Pose& pose, std::uint32_t group = 1, std::uint32_t mask = 0xFFFFFFFFu);
  std::size_t size() const { return shapes_.size(); }
  const Shape& shape(std::uint32_t body) const { return shapes_[body]; }
  const Pose& pose(std::uint32_t body) const { return poses_[body]; }
  bool ignore_pair(std::uint32_t i, std::uint32_t j);   // false if an index is out of range or i == j
  bool set_pose(std::uint32_t body, const Pose& pose);  // false if out of range or !pose.valid()
  bool set_poses(const Pose* poses,
                 std::size_t count);  // count == size(); false (nothing changed) otherwise or if any is invalid
  // Every pair (a < b) that passes the filter (group_a & mask_b and group_b & mask_a non-zero, not ignored)
  // and whose distance is <= max_distance, sorted by (a, b); the same result for any thread count.
  // Clears and fills `out` (it may allocate as it grows; reuse it across frames).
  // A max_distance that is negative or not finite gives no pair.
  void pairs(const PairSettings& settings, std::vector<PairResult>& out);

  // The grown world box of a body as pairs() sees it (up to date after pairs()).
  struct Aabb {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  };
  Aabb box(std::uint32_t body);
  const WorldStats& stats() const { return stats_; }

 private:
  struct Node {
    double lo[3], hi[3];
    std::uint32_t first = 0;  // leaf: first position in order_; internal: the right child (left = this + 1)
    std::uint32_t count = 0;  // leaf: bodies (>= 1); internal: 0
    std::uint32_t last = 0;   // the last leaf position in the subtree
  };
  struct ChunkScratch {
    std::vector<PairResult> results;
    std::vector<std::uint64_t> keys;
  };

  void update_boxes(const ParallelSettings& parallel);
  void update_tree(TreeUpdate mode, const ParallelSettings& parallel);
  void build_tree();
  std::uint32_t build_node(std::uint32_t begin, std::uint32_t end);
  double refit_tree();
  bool ignored(std::uint32_t a, std::uint32_t b) const;
  void find_candidates(std::size_t begin, std::size_t end, double max_distance, std::vector<std::uint64_t>& keys) const;
  void gather_candidates();
  void query_candidates(std::size_t begin, std::size_t end, const PairSettings& settings,
                        std::vector<PairResult>& results) const;

  std::vector<Shape> shapes_;
  std::vector<Pose> poses_;
  std::vector<std::uint32_t> group_, mask_;
  std::vector<double> radius_, local_extent_;
  std::vector<Aabb> boxes_;
  std::vector<std::uint8_t> stale_;  // box to recompute
  bool any_stale_ = false;
  std::vector<std::uint64_t> ignored_;  // sorted keys (a << 32 | b), a < b
  // The tree.
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;      // body indices in leaf order
  std::vector<Aabb> leaf_boxes_;          // boxes_[order_[k]] at position k
  std::vector<Eigen::Vector3d> centres_;  // build scratch
  std::size_t tree_bodies_ = 0;
  double built_cost_ = 0.0;
  bool tree_moved_ = false;  // boxes changed since the tree was last fitted
  std::vector<ChunkScratch> chunks_;
  std::vector<std::uint64_t> candidates_, sort_scratch_;  // sorted candidate keys; radix sort buffer
  WorldStats stats_;
};

}  // namespace hedra::collision
