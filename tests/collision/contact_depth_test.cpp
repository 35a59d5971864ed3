// The reported depth of contact() against the overlap along its own normal,
// over a generator of hard penetrating pairs (one body deep inside another,
// random polytopes, thin plates, pairs far from the origin, rounded boxes and
// hulls, capsules, cylinders and cones against polytopes; fixed seeds):
//   overlap(n) = h_A(n) + h_B(-n)   (world supports with margins, n A -> B)
// For every pair: the reported distance is -overlap(n) and the deepest point
// is as deep, both to rounding (1e-9 of the size); and the exact reference
// (tools/reference, qhull) lies within the reported error bound:
// |distance - exact| <= error_bound (plus the reference's own bound).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exact_reference.hpp>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/manifold.hpp>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using testing::make_hull;
using testing::random_points;
using testing::random_unit;
using Vec = Eigen::Vector3d;

struct Pair {
  Shape a, b;
  Pose pa, pb;
  std::string family;
};

Pose random_pose(std::mt19937_64& rng, const Vec& t) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized(), t);
}

Shape hull_of(std::mt19937_64& rng, const Vec& scale, double margin) {
  std::uniform_int_distribution<int> n(8, 40);
  return Polyhedron{make_hull(random_points(rng, n(rng), scale)), margin};
}

Vec random_scale(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

// The overlap of the two shapes along n (A -> B, world): h_A(n) + h_B(-n).
double overlap_along(const Pair& p, const Vec& n) {
  const Vec sa = p.pa.rotation * support(p.a, p.pa.rotation.transpose() * n) + p.pa.translation;
  const Vec sb = p.pb.rotation * support(p.b, p.pb.rotation.transpose() * -n) + p.pb.translation;
  return n.dot(sa) - n.dot(sb);
}

double size_of(const Pair& p) { return bounding_radius(p.a) + bounding_radius(p.b); }

// Hard penetrating pairs, `per_family` of each family.
std::vector<Pair> hard_pairs(int per_family, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), margin(0.02, 0.1), small(0.1, 0.3);
  std::vector<Pair> pairs;
  for (int i = 0; i < per_family; ++i) {
    // Deep: a small body well inside a large one, near its boundary or not.
    const Shape big = i % 2 ? Shape{Box{random_scale(rng, 0.8, 1.2)}} : hull_of(rng, random_scale(rng, 0.8, 1.2), 0.0);
    const Shape little =
        i % 3 ? hull_of(rng, random_scale(rng, 0.1, 0.3), 0.0) : Shape{Box{random_scale(rng, 0.1, 0.3)}};
    pairs.push_back(
        {big, little, random_pose(rng, Vec::Zero()), random_pose(rng, 0.5 * Vec(u(rng), u(rng), u(rng))), "deep"});
    // Polytopes overlapping by a fraction of their size.
    pairs.push_back({hull_of(rng, random_scale(rng, 0.4, 1.0), 0.0), hull_of(rng, random_scale(rng, 0.4, 1.0), 0.0),
                     random_pose(rng, Vec::Zero()), random_pose(rng, 0.8 * random_unit(rng)), "polytopes"});
    pairs.push_back({Box{random_scale(rng, 0.3, 1.0)}, hull_of(rng, random_scale(rng, 0.4, 1.0), 0.0),
                     random_pose(rng, Vec::Zero()), random_pose(rng, 0.8 * random_unit(rng)), "box_hull"});
    pairs.push_back({Box{random_scale(rng, 0.3, 1.0)}, Box{random_scale(rng, 0.3, 1.0)}, random_pose(rng, Vec::Zero()),
                     random_pose(rng, 0.9 * random_unit(rng)), "boxes"});
    // Thin plates crossing or stacked.
    Vec ha = random_scale(rng, 0.3, 1.0), hb = random_scale(rng, 0.3, 1.0);
    ha.z() = 0.005;
    hb.z() = 0.005;
    pairs.push_back(
        {Box{ha}, Box{hb}, random_pose(rng, Vec::Zero()), random_pose(rng, 0.3 * random_unit(rng)), "thin"});
    // Far from the origin.
    const Vec far = 1e5 * random_unit(rng);
    pairs.push_back({hull_of(rng, random_scale(rng, 0.4, 1.0), 0.0), Box{random_scale(rng, 0.3, 1.0)},
                     random_pose(rng, far), random_pose(rng, far + 0.8 * random_unit(rng)), "far"});
    // Rounded polytopes.
    pairs.push_back({Box{random_scale(rng, 0.3, 1.0), margin(rng)},
                     hull_of(rng, random_scale(rng, 0.4, 1.0), margin(rng)), random_pose(rng, Vec::Zero()),
                     random_pose(rng, 0.9 * random_unit(rng)), "rounded"});
    // Curved shapes against polytopes.
    const Shape poly = i % 2 ? Shape{Box{random_scale(rng, 0.3, 1.0)}} : hull_of(rng, random_scale(rng, 0.4, 1.0), 0.0);
    const double r = small(rng), h = 2.0 * small(rng);
    const Shape curved = i % 3 == 0   ? Shape{Capsule{r, h, 0.0}}
                         : i % 3 == 1 ? Shape{Cylinder{r, h, 0.0}}
                                      : Shape{Cone{r, h, 0.0}};
    pairs.push_back({poly, curved, random_pose(rng, Vec::Zero()), random_pose(rng, 0.7 * random_unit(rng)), "curved"});
  }
  return pairs;
}

struct Tally {
  int pairs = 0, short_distance = 0, short_deepest = 0;
  double worst_distance = 0.0, worst_deepest = 0.0;  // / size
};

void print(const std::map<std::string, Tally>& tally) {
  for (const auto& [family, t] : tally)
    std::printf("%-10s pairs %4d  distance short %3d (worst %.3g of the size)  deepest short %3d (worst %.3g)\n",
                family.c_str(), t.pairs, t.short_distance, t.worst_distance, t.short_deepest, t.worst_deepest);
}

// Each pair's shortfall of the reported distance and of the deepest point
// against the overlap along the reported normal, tallied by family and by
// path; `warm`: each pair asked twice with one cache (the second answer, from
// the recycled axis or the box pair's memory, is the one checked).
void check_depths(const std::vector<Pair>& pairs, const ContactSettings& settings, bool warm) {
  std::map<std::string, Tally> tally, by_path;
  for (const Pair& p : pairs) {
    ContactCache cache;
    ContactResult c = contact(p.a, p.pa, p.b, p.pb, warm ? &cache : nullptr, settings);
    if (warm) c = contact(p.a, p.pa, p.b, p.pb, &cache, settings);
    if (c.status != Status::ok || !c.intersecting || c.count == 0) continue;
    const double size = size_of(p), tol = 1e-9 * size;
    const double overlap = overlap_along(p, c.normal);
    double deepest = -INFINITY;
    for (int k = 0; k < c.count; ++k) deepest = std::max(deepest, c.points[k].depth);
    const double short_distance = overlap + c.distance, short_deepest = overlap - deepest;
    for (Tally* t : {&tally[p.family], &by_path[to_string(c.path)]}) {
      ++t->pairs;
      t->short_distance += short_distance > tol;
      t->short_deepest += short_deepest > tol;
      t->worst_distance = std::max(t->worst_distance, short_distance / size);
      t->worst_deepest = std::max(t->worst_deepest, short_deepest / size);
    }
    EXPECT_LE(std::abs(short_distance), tol) << p.family << " path " << to_string(c.path);
    EXPECT_LE(short_deepest, tol) << p.family << " path " << to_string(c.path);
  }
  print(tally);
  print(by_path);
}

// The general polytope path (boxes too): a face contact whose reference face's
// side planes clipped away the incident shape's deepest vertex reported its
// kept points, up to the face bias shallower than the axis's overlap.
TEST(ContactDepth, ClippingDropsDeepestIncidentVertex) {
  ContactSettings general;
  general.box_box_path = false;
  check_depths(hard_pairs(160, 20261128), general, false);
}

// The same root cause on box_box.cpp's path (its own clipping).
TEST(ContactDepth, BoxPathClippingDropsDeepestIncidentVertex) {
  check_depths(hard_pairs(160, 20261129), ContactSettings{}, false);
}

// The same through the cache: the recycled axis and the box pair's memory
// rebuild the manifold at the new poses with the same check.
TEST(ContactDepth, CachedAxisClippingDropsDeepestIncidentVertex) {
  check_depths(hard_pairs(160, 20261130), ContactSettings{}, true);
}

// The certified bound: the exact reference's signed distance lies within
// error_bound of the reported distance on every pair (penetrating, and moved
// apart to a gap within the contact distance), cold and warm; the bound's
// median and largest over the size per family. A pair separated beyond the
// contact distance (some generated pairs are) may answer with a lower bound
// and an infinite error bound.
void check_bounds(const std::vector<Pair>& pairs, bool warm) {
  std::map<std::string, std::vector<double>> bounds;
  int checked = 0;
  for (const Pair& pair : pairs) {
    for (const bool apart : {false, true}) {
      Pair p = pair;
      const double size = size_of(p);
      ContactSettings settings;
      if (apart) {
        const PenetrationResult pen = penetration(p.a, p.pa, p.b, p.pb);
        if (pen.status != Status::ok) continue;
        p.pb.translation += (0.02 * size - pen.distance) * pen.normal;  // 2 % of the size apart
        settings.contact_distance = 0.05 * size;
      }
      ContactCache cache;
      ContactResult c = contact(p.a, p.pa, p.b, p.pb, warm ? &cache : nullptr, settings);
      if (warm) c = contact(p.a, p.pa, p.b, p.pb, &cache, settings);
      if (c.status != Status::ok) continue;
      const reference::ExactResult exact = reference::exact_signed_distance(p.a, p.pa, p.b, p.pb);
      if (!exact.ok) continue;
      ++checked;
      // Only a pair separated beyond the contact distance may come without a
      // finite bound (its distance a lower bound).
      if (c.path == ContactPath::separated && !std::isfinite(c.error_bound)) {
        EXPECT_LE(c.distance, exact.distance + exact.error_bound + 1e-12 * size) << p.family;
        continue;
      }
      EXPECT_TRUE(std::isfinite(c.error_bound))
          << p.family << (apart ? " apart" : " penetrating") << " path " << to_string(c.path) << " distance "
          << c.distance << " exact " << exact.distance << " size " << size;
      EXPECT_LE(std::abs(c.distance - exact.distance), c.error_bound + exact.error_bound)
          << p.family << (apart ? " apart" : " penetrating") << " path " << to_string(c.path) << " distance "
          << c.distance << " exact " << exact.distance;
      bounds[p.family + (apart ? "/apart" : "")].push_back(c.error_bound / size);
    }
  }
  EXPECT_GT(checked, static_cast<int>(pairs.size()));
  for (auto& [family, b] : bounds) {
    std::sort(b.begin(), b.end());
    std::printf("%-16s pairs %4zu  error_bound / size: median %.3g, max %.3g\n", family.c_str(), b.size(),
                b[b.size() / 2], b.back());
  }
}

TEST(ContactDepth, ErrorBoundHoldsAgainstTheExactReference) { check_bounds(hard_pairs(40, 20261131), false); }

TEST(ContactDepth, WarmErrorBoundHoldsAgainstTheExactReference) { check_bounds(hard_pairs(40, 20261132), true); }

}  // namespace
}  // namespace hedra::collision
