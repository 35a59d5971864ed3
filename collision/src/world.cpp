// World (world.hpp): tight grown boxes, the BVH (median build, refit), and
// the all-pairs query in parallel_for's fixed chunks of bodies.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <hedra/collision/support.hpp>
#include <hedra/collision/world.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>
#include <type_traits>

#include "query_detail.hpp"

namespace hedra::collision {
namespace {

using Vec = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

// Half-extents of a shape symmetric about its origin, per world axis.
Vec symmetric_extent(const Sphere& s, const Eigen::Matrix3d&) { return Vec::Constant(s.radius + s.margin); }
Vec symmetric_extent(const Box& s, const Eigen::Matrix3d& r) {
  return r.cwiseAbs() * s.half_extents + Vec::Constant(s.margin);
}
Vec symmetric_extent(const Capsule& s, const Eigen::Matrix3d& r) {
  return r.col(2).cwiseAbs() * s.half_length + Vec::Constant(s.radius + s.margin);
}
// A disc of radius `radius` perpendicular to the unit axis a reaches
// radius sqrt(1 - a_k^2) along e_k.
Vec disc_extent(const Vec& axis, double radius) {
  Vec e;
  for (int k = 0; k < 3; ++k) e[k] = radius * std::sqrt(std::max(0.0, 1.0 - axis[k] * axis[k]));
  return e;
}
Vec symmetric_extent(const Cylinder& s, const Eigen::Matrix3d& r) {
  return r.col(2).cwiseAbs() * s.half_length + disc_extent(r.col(2), s.radius) + Vec::Constant(s.margin);
}

// The exact (up to rounding) world box of a posed shape.
World::Aabb tight_box(const Shape& shape, const Pose& pose) {
  const Eigen::Matrix3d& r = pose.rotation;
  const Vec& t = pose.translation;
  World::Aabb box;
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Cone>) {
          const Vec axis = r.col(2);
          const Vec apex = axis * s.half_length, base = -axis * s.half_length;
          const Vec rim = disc_extent(axis, s.radius);
          box.lo = apex.cwiseMin(base - rim) - Vec::Constant(s.margin) + t;
          box.hi = apex.cwiseMax(base + rim) + Vec::Constant(s.margin) + t;
        } else if constexpr (std::is_same_v<S, Polyhedron>) {
          // Per axis k: the support vertices along +-(row k of R) in the local frame.
          const ConvexPolyhedron& poly = *s.hull;
          const Vec centre = r * poly.offset() + t;
          for (int k = 0; k < 3; ++k) {
            const Vec d = r.row(k).transpose();
            const hull::Index up = polyhedron_support(poly, d, 0), down = polyhedron_support(poly, -d, 0);
            box.hi[k] = centre[k] + d.dot(poly.vertex(up)) + s.margin;
            box.lo[k] = centre[k] + d.dot(poly.vertex(down)) - s.margin;
          }
        } else {
          const Vec e = symmetric_extent(s, r);
          box.lo = t - e;
          box.hi = t + e;
        }
      },
      shape);
  return box;
}

// A bound on |x| for x in the shape, in its local frame.
double local_extent(const Shape& shape, double radius) {
  if (const auto* p = std::get_if<Polyhedron>(&shape)) return radius + p->hull->offset().norm();
  return radius;
}

bool overlaps(const double* lo, const double* hi, const Vec& qlo, const Vec& qhi) {
  return lo[0] <= qhi[0] && qlo[0] <= hi[0] && lo[1] <= qhi[1] && qlo[1] <= hi[1] && lo[2] <= qhi[2] && qlo[2] <= hi[2];
}

double surface_area(const double* lo, const double* hi) {
  const double x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
  return 2.0 * (x * y + y * z + z * x);
}

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

}  // namespace

// ---- bodies --------------------------------------------------------------

std::uint32_t World::add(const Shape& shape, const Pose& pose, std::uint32_t group, std::uint32_t mask) {
  double radius = 0.0;
  if (!is_valid(shape, radius) || !pose.valid() || shapes_.size() >= kInvalidBody) return kInvalidBody;
  const auto body = static_cast<std::uint32_t>(shapes_.size());
  shapes_.push_back(shape);
  poses_.push_back(pose);
  group_.push_back(group);
  mask_.push_back(mask);
  radius_.push_back(radius);
  local_extent_.push_back(local_extent(shape, radius));
  boxes_.emplace_back();
  stale_.push_back(1);
  any_stale_ = true;
  return body;
}

bool World::ignore_pair(std::uint32_t i, std::uint32_t j) {
  if (i >= size() || j >= size() || i == j) return false;
  const std::uint64_t key = pair_key(i, j);
  const auto at = std::lower_bound(ignored_.begin(), ignored_.end(), key);
  if (at == ignored_.end() || *at != key) ignored_.insert(at, key);
  return true;
}

bool World::ignored(std::uint32_t a, std::uint32_t b) const {
  return !ignored_.empty() && std::binary_search(ignored_.begin(), ignored_.end(), pair_key(a, b));
}

bool World::set_pose(std::uint32_t body, const Pose& pose) {
  if (body >= size() || !pose.valid()) return false;
  poses_[body] = pose;
  stale_[body] = 1;
  any_stale_ = true;
  return true;
}

bool World::set_poses(const Pose* poses, std::size_t count) {
  if (count != size() || (count > 0 && poses == nullptr)) return false;
  for (std::size_t i = 0; i < count; ++i)
    if (!poses[i].valid()) return false;
  std::copy(poses, poses + count, poses_.begin());
  std::fill(stale_.begin(), stale_.end(), std::uint8_t{1});
  any_stale_ = count > 0;
  return true;
}

World::Aabb World::box(std::uint32_t body) {
  update_boxes(ParallelSettings{1, nullptr});
  return boxes_[body];
}

// ---- boxes and tree ------------------------------------------------------

void World::update_boxes(const ParallelSettings& parallel) {
  if (!any_stale_) return;
  parallel_for(size(), parallel, [this](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (!stale_[i]) continue;
      Aabb b = tight_box(shapes_[i], poses_[i]);
      const double allowance =
          kBoxBand * radius_[i] + kBoxRounding * (poses_[i].translation.cwiseAbs().maxCoeff() + local_extent_[i]);
      b.lo.array() -= allowance;
      b.hi.array() += allowance;
      boxes_[i] = b;
      stale_[i] = 0;
    }
  });
  any_stale_ = false;
  tree_moved_ = true;
}

void World::build_tree() {
  const auto n = static_cast<std::uint32_t>(size());
  nodes_.clear();
  order_.resize(n);
  centres_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    order_[i] = i;
    centres_[i] = 0.5 * (boxes_[i].lo + boxes_[i].hi);
  }
  if (n > 0) {
    nodes_.reserve(2 * (n / kLeafSize + 1));
    build_node(0, n);
  }
  leaf_boxes_.resize(n);
  for (std::uint32_t k = 0; k < n; ++k) leaf_boxes_[k] = boxes_[order_[k]];
  tree_bodies_ = n;
  built_cost_ = 0.0;
  for (const Node& node : nodes_)
    if (node.count == 0) built_cost_ += surface_area(node.lo, node.hi);
  tree_moved_ = false;
}

// Builds the subtree over order_[begin, end) depth-first; returns its node.
std::uint32_t World::build_node(std::uint32_t begin, std::uint32_t end) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Vec clo = lo, chi = hi;
  for (std::uint32_t k = begin; k < end; ++k) {
    const std::uint32_t body = order_[k];
    lo = lo.cwiseMin(boxes_[body].lo);
    hi = hi.cwiseMax(boxes_[body].hi);
    clo = clo.cwiseMin(centres_[body]);
    chi = chi.cwiseMax(centres_[body]);
  }
  {
    Node& node = nodes_[index];
    for (int k = 0; k < 3; ++k) node.lo[k] = lo[k], node.hi[k] = hi[k];
    node.last = end - 1;
  }
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const std::uint32_t middle = begin + (end - begin) / 2;
  const auto less = [this, axis](std::uint32_t x, std::uint32_t y) {
    const double cx = centres_[x][axis], cy = centres_[y][axis];
    return cx < cy || (cx == cy && x < y);
  };
  std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end, less);
  build_node(begin, middle);
  const std::uint32_t right = build_node(middle, end);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

// Children before parents: reverse depth-first order. Returns the cost.
double World::refit_tree() {
  for (std::uint32_t k = 0; k < order_.size(); ++k) leaf_boxes_[k] = boxes_[order_[k]];
  double cost = 0.0;
  for (std::size_t i = nodes_.size(); i-- > 0;) {
    Node& node = nodes_[i];
    if (node.count > 0) {
      Vec lo = leaf_boxes_[node.first].lo, hi = leaf_boxes_[node.first].hi;
      for (std::uint32_t k = node.first + 1; k < node.first + node.count; ++k) {
        lo = lo.cwiseMin(leaf_boxes_[k].lo);
        hi = hi.cwiseMax(leaf_boxes_[k].hi);
      }
      for (int k = 0; k < 3; ++k) node.lo[k] = lo[k], node.hi[k] = hi[k];
    } else {
      const Node& left = nodes_[i + 1];
      const Node& right = nodes_[node.first];
      HEDRA_ASSERT(node.first > i + 1);
      for (int k = 0; k < 3; ++k) {
        node.lo[k] = std::min(left.lo[k], right.lo[k]);
        node.hi[k] = std::max(left.hi[k], right.hi[k]);
      }
      cost += surface_area(node.lo, node.hi);
    }
  }
  tree_moved_ = false;
  return cost;
}

void World::update_tree(TreeUpdate mode, const ParallelSettings& parallel) {
  stats_.rebuilt = false;
  update_boxes(parallel);
  const Clock::time_point serial_start = Clock::now();  // the rest runs on the calling thread
  struct SerialTimer {
    WorldStats& stats;
    Clock::time_point start;
    ~SerialTimer() { stats.serial_seconds += std::chrono::duration<double>(Clock::now() - start).count(); }
  } timer{stats_, serial_start};
  if (tree_bodies_ != size() || mode == TreeUpdate::rebuild) {
    build_tree();
    stats_.rebuilt = true;
    stats_.tree_cost_ratio = 1.0;
    return;
  }
  if (!tree_moved_) return;
  const double cost = refit_tree();
  stats_.tree_cost_ratio = built_cost_ > 0.0 ? cost / built_cost_ : 1.0;
  if (mode == TreeUpdate::automatic && stats_.tree_cost_ratio > kRebuildCostRatio) {
    build_tree();
    stats_.rebuilt = true;
  }
}

// ---- the all-pairs query -------------------------------------------------

namespace {

// The query on one candidate; false when the pair is not within reach.
bool query_pair(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb, double band,
                const PairSettings& settings, const ContactSettings& contact_settings, PairResult& out) {
  const double reach = settings.max_distance + band;
  switch (settings.query) {
    case PairQuery::intersect: {
      if (settings.max_distance == 0.0) {
        const IntersectResult r = intersect(a, pa, b, pb, nullptr, settings.gjk);
        out.status = r.status;
        out.intersecting = r.intersecting;
        return r.status != Status::ok || r.intersecting;
      }
      const DistanceResult r = distance(a, pa, b, pb, nullptr, settings.gjk);
      out.status = r.status;
      out.intersecting = r.intersecting;
      return r.status != Status::ok || r.distance <= reach;
    }
    case PairQuery::distance: {
      const DistanceResult r = distance(a, pa, b, pb, nullptr, settings.gjk);
      out.status = r.status;
      out.intersecting = r.intersecting;
      out.distance = r.distance;
      out.normal = r.normal;
      out.point_a = r.point_a;
      out.point_b = r.point_b;
      out.error_bound = r.error_bound;
      return r.status != Status::ok || r.distance <= reach;
    }
    case PairQuery::penetration: {
      const PenetrationResult r = penetration(a, pa, b, pb, nullptr, settings.penetration);
      out.status = r.status;
      out.intersecting = r.intersecting;
      out.distance = r.distance;
      out.normal = r.normal;
      out.point_a = r.point_a;
      out.point_b = r.point_b;
      out.error_bound = r.error_bound;
      return r.status != Status::ok || r.distance <= reach;
    }
    case PairQuery::contact: {
      const ContactResult r = contact(a, pa, b, pb, nullptr, contact_settings);
      out.status = r.status;
      out.intersecting = r.intersecting;
      out.distance = r.distance;
      out.normal = r.normal;
      out.point_a = r.point_a;
      out.point_b = r.point_b;
      out.error_bound = r.error_bound;
      out.count = r.count;
      out.points = r.points;
      return r.status != Status::ok || (r.path != ContactPath::separated && r.distance <= reach);
    }
  }
  return false;
}

}  // namespace

// Step 1: the candidates of the bodies at leaf positions [begin, end).
void World::find_candidates(std::size_t begin, std::size_t end, double max_distance,
                            std::vector<std::uint64_t>& keys) const {
  keys.clear();
  const double d = max_distance;
  constexpr int kStackSize = 128;  // the tree's depth is about log2(n / kLeafSize)
  std::uint32_t stack[kStackSize];
  for (std::size_t position = begin; position < end; ++position) {
    const auto k = static_cast<std::uint32_t>(position);
    const std::uint32_t i = order_[k];
    const Aabb& box = leaf_boxes_[k];
    const Vec qlo = (box.lo.array() - d - kBoxRounding * (box.lo.array().abs() + d)).matrix();
    const Vec qhi = (box.hi.array() + d + kBoxRounding * (box.hi.array().abs() + d)).matrix();
    int top = 0;
    if (!nodes_.empty() && nodes_[0].last > k) stack[top++] = 0;
    while (top > 0) {
      const std::uint32_t index = stack[--top];
      const Node& node = nodes_[index];
      if (!overlaps(node.lo, node.hi, qlo, qhi)) continue;
      if (node.count > 0) {
        for (std::uint32_t p = std::max(node.first, k + 1); p < node.first + node.count; ++p) {
          if (!overlaps(leaf_boxes_[p].lo.data(), leaf_boxes_[p].hi.data(), qlo, qhi)) continue;
          const std::uint32_t j = order_[p];
          if ((group_[i] & mask_[j]) == 0 || (group_[j] & mask_[i]) == 0 || ignored(i, j)) continue;
          keys.push_back(pair_key(i, j));
        }
        continue;
      }
      HEDRA_ASSERT(top + 2 <= kStackSize);
      // Subtrees wholly at or before position k hold no later body.
      if (nodes_[node.first].last > k) stack[top++] = node.first;
      if (nodes_[index + 1].last > k) stack[top++] = index + 1;
    }
  }
}

// Step 2: every chunk's keys, sorted (LSD radix sort, 11 bits a pass, over
// the bits the keys use).
void World::gather_candidates() {
  std::size_t total = 0;
  const std::size_t chunks = parallel_chunk_count(size());
  for (std::size_t c = 0; c < chunks; ++c) total += chunks_[c].keys.size();
  candidates_.clear();
  candidates_.reserve(total);
  for (std::size_t c = 0; c < chunks; ++c)
    candidates_.insert(candidates_.end(), chunks_[c].keys.begin(), chunks_[c].keys.end());
  sort_scratch_.resize(total);
  int bits = 0;
  while (bits < 32 && (std::uint64_t{1} << bits) < size()) ++bits;
  constexpr int kDigit = 11;
  std::uint64_t* from = candidates_.data();
  std::uint64_t* to = sort_scratch_.data();
  int passes = 0;
  for (int shift : {0, 32}) {
    for (int low = 0; low < bits; low += kDigit, ++passes) {
      std::size_t count[(1 << kDigit) + 1] = {};
      const int at = shift + low;
      for (std::size_t i = 0; i < total; ++i) ++count[((from[i] >> at) & ((1u << kDigit) - 1)) + 1];
      for (int b = 0; b < (1 << kDigit); ++b) count[b + 1] += count[b];
      for (std::size_t i = 0; i < total; ++i) to[count[(from[i] >> at) & ((1u << kDigit) - 1)]++] = from[i];
      std::swap(from, to);
    }
  }
  if (passes % 2 == 1) candidates_.swap(sort_scratch_);
  HEDRA_ASSERT(std::is_sorted(candidates_.begin(), candidates_.end()));
}

// Step 3: the queries of the sorted candidates [begin, end).
void World::query_candidates(std::size_t begin, std::size_t end, const PairSettings& settings,
                             std::vector<PairResult>& results) const {
  results.clear();
  ContactSettings contact_settings = settings.contact;
  contact_settings.contact_distance = settings.max_distance;
  for (std::size_t c = begin; c < end; ++c) {
    PairResult result;
    result.a = static_cast<std::uint32_t>(candidates_[c] >> 32);
    result.b = static_cast<std::uint32_t>(candidates_[c]);
    if (settings.broadphase_only) {
      results.push_back(result);
      continue;
    }
    const std::uint32_t i = result.a, j = result.b;
    const double band = kTouchingBand * std::max(radius_[i], radius_[j]);
    // A pair certified apart beyond the reach is not kept by any query: the
    // cheap boolean GJK settles it (the intersect query at 0 is that test).
    const bool boolean_only = settings.query == PairQuery::intersect && settings.max_distance == 0.0;
    if (!boolean_only) {
      // Shapes and poses were validated when they entered the world; the
      // pair's extent is settled by the radii unless both are tiny.
      const double gap = settings.max_distance + band;
      const bool apart =
          std::max(radius_[i], radius_[j]) >= min_pair_extent
              ? detail::separated_beyond_unchecked(shapes_[i], poses_[i], shapes_[j], poses_[j], gap, settings.gjk)
              : separated_beyond(shapes_[i], poses_[i], shapes_[j], poses_[j], gap, settings.gjk);
      if (apart) continue;
    }
    if (query_pair(shapes_[i], poses_[i], shapes_[j], poses_[j], band, settings, contact_settings, result))
      results.push_back(result);
  }
}

void World::pairs(const PairSettings& settings, std::vector<PairResult>& out) {
  out.clear();
  stats_.candidates = stats_.pairs = 0;
  stats_.serial_seconds = 0.0;
  const Clock::time_point start = Clock::now();
  update_tree(settings.tree_update, settings.parallel);
  const Clock::time_point updated = Clock::now();
  stats_.update_seconds = std::chrono::duration<double>(updated - start).count();
  if (!(settings.max_distance >= 0.0) || !std::isfinite(settings.max_distance)) return;
  const std::size_t n = size();
  if (chunks_.size() < kMaxParallelChunks) chunks_.resize(kMaxParallelChunks);
  parallel_for_chunks(n, settings.parallel, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    find_candidates(begin, end, settings.max_distance, chunks_[chunk].keys);
  });
  const Clock::time_point gather_start = Clock::now();
  gather_candidates();
  stats_.serial_seconds += std::chrono::duration<double>(Clock::now() - gather_start).count();
  stats_.broadphase_seconds = std::chrono::duration<double>(Clock::now() - updated).count();
  const std::size_t m = candidates_.size();
  stats_.candidates = m;
  parallel_for_chunks(m, settings.parallel, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    query_candidates(begin, end, settings, chunks_[chunk].results);
  });
  const Clock::time_point merge_start = Clock::now();
  const std::size_t chunks = parallel_chunk_count(m);
  std::size_t total = 0;
  for (std::size_t c = 0; c < chunks; ++c) total += chunks_[c].results.size();
  out.reserve(total);
  for (std::size_t c = 0; c < chunks; ++c) out.insert(out.end(), chunks_[c].results.begin(), chunks_[c].results.end());
  stats_.pairs = out.size();
  stats_.serial_seconds += std::chrono::duration<double>(Clock::now() - merge_start).count();
  stats_.query_seconds = std::chrono::duration<double>(Clock::now() - updated).count();
  std::size_t memory = (candidates_.capacity() + sort_scratch_.capacity()) * sizeof(std::uint64_t);
  for (const ChunkScratch& c : chunks_)
    memory += c.results.capacity() * sizeof(PairResult) + c.keys.capacity() * sizeof(std::uint64_t);
  memory += shapes_.capacity() * sizeof(Shape) + poses_.capacity() * sizeof(Pose) +
            (group_.capacity() + mask_.capacity() + order_.capacity()) * sizeof(std::uint32_t) +
            (radius_.capacity() + local_extent_.capacity()) * sizeof(double) +
            (boxes_.capacity() + leaf_boxes_.capacity()) * sizeof(Aabb) + nodes_.capacity() * sizeof(Node) +
            centres_.capacity() * sizeof(Vec) + stale_.capacity() + ignored_.capacity() * sizeof(std::uint64_t);
  stats_.memory_bytes = memory;
}

}  // namespace hedra::collision
