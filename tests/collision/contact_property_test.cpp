// Property test of contact() over twenty-three seeded pair families (random
// hulls of 8 to 64 vertices, boxes, rounded boxes and hulls with margins of
// 2 % to 10 % of the size, spheres, capsules, cylinders and cones, sharp and
// rounded, against polytopes, 150 random poses each; and cones standing or
// lying on a box's face, tilted by up to 5e-4 rad, 75 each, so that their
// cap and side-line paths run; rounded cylinders the same way, often hanging
// over the face's edge; and rounded boxes and hulls resting tilted on a
// rounded box with their lowest corner just inside or just beyond its edge,
// where the cores' exact normal is tilted off the faces), each pair penetrating
// or brought to touching (B moved along penetration()'s normal by its
// distance). For every pair:
//   * status ok and at least one point;
//   * every point's witnesses lie on the two surfaces (signed distance
//     functions below, exact: closed forms, hull planes inside, the exact
//     qhull reference outside), so its depth is the overlap of the two
//     surfaces along the normal at that point;
//   * the deepest point is never shallower than penetration()'s depth (less
//     its error bound and 1e-9 of the size);
//   * contact()'s distance equals penetration()'s, or, where the face
//     preference chose another axis, lies within the stated bias below it.
// A second pass moves every pair apart to a gap within the contact distance
// (5 % of the size): the same checks on speculative points (negative depth,
// the gap along the normal).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <hedra/collision/manifold.hpp>
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

Pose random_pose(std::mt19937_64& rng, const Vec& t) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized(), t);
}

struct Pair {
  Shape a, b;
  Pose pa, pb;
  std::string family;
};

Shape random_hull(std::mt19937_64& rng, double margin_fraction) {
  std::uniform_int_distribution<int> n(8, 64);
  std::uniform_real_distribution<double> axis(0.4, 1.0);
  const Vec scale(axis(rng), axis(rng), axis(rng));
  return Polyhedron{make_hull(random_points(rng, n(rng), scale)), margin_fraction * scale.norm()};
}

Shape random_box(std::mt19937_64& rng, double margin_fraction) {
  std::uniform_real_distribution<double> axis(0.3, 1.0);
  const Vec h(axis(rng), axis(rng), axis(rng));
  return Box{h, margin_fraction * h.norm()};
}

// The families: (shape of A, shape of B) makers, margins as fractions.
std::vector<Pair> make_pairs(int per_family) {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> margin(0.02, 0.10);
  std::uniform_real_distribution<double> reach(0.2, 0.9);
  using Maker = Shape (*)(std::mt19937_64&, double);
  struct Family {
    const char* name;
    Maker a, b;
    bool rounded;
  };
  const Maker capsule = [](std::mt19937_64& r, double) -> Shape {
    std::uniform_real_distribution<double> u(0.2, 0.8);
    const double half_length = u(r);  // drawn first, as before the field order changed
    return Capsule{0.5 * u(r), half_length, 0.0};
  };
  const Maker cylinder = [](std::mt19937_64& r, double) -> Shape {
    std::uniform_real_distribution<double> u(0.2, 0.8);
    return Cylinder{u(r), u(r), 0.0};
  };
  const Maker rounded_capsule = [](std::mt19937_64& r, double m) -> Shape {
    std::uniform_real_distribution<double> u(0.2, 0.8);
    const double half_length = u(r);
    return Capsule{0.5 * u(r), half_length, m};
  };
  const Maker rounded_cylinder = [](std::mt19937_64& r, double m) -> Shape {
    std::uniform_real_distribution<double> u(0.2, 0.8);
    return Cylinder{u(r), u(r), m};
  };
  const Maker sphere = [](std::mt19937_64& r, double m) -> Shape {
    std::uniform_real_distribution<double> u(0.2, 0.8);
    return Sphere{u(r), m};
  };
  const Maker cone = [](std::mt19937_64& r, double) -> Shape {
    std::uniform_real_distribution<double> u(0.2, 0.8);
    return Cone{u(r), u(r), 0.0};
  };
  const Maker rounded_cone = [](std::mt19937_64& r, double m) -> Shape {
    std::uniform_real_distribution<double> u(0.2, 0.8);
    return Cone{u(r), u(r), m};
  };
  const Family families[] = {
      {"hulls", random_hull, random_hull, false},
      {"boxes", random_box, random_box, false},
      {"rounded_hulls", random_hull, random_hull, true},
      {"rounded_boxes", random_box, random_box, true},
      {"box_hull", random_box, random_hull, false},
      {"hull_capsule", random_hull, capsule, false},
      {"box_capsule", random_box, capsule, false},
      {"box_cylinder", random_box, cylinder, false},
      {"rounded_box_hull", random_box, random_hull, true},
      {"rounded_hull_capsule", random_hull, rounded_capsule, true},
      {"rounded_box_cylinder", random_box, rounded_cylinder, true},
      {"hull_cylinder", random_hull, cylinder, false},
      {"box_sphere", random_box, sphere, false},
      {"rounded_hull_sphere", random_hull, sphere, true},
      {"box_cone", random_box, cone, false},
      {"hull_cone", random_hull, cone, false},
      {"rounded_box_cone", random_box, rounded_cone, true},
  };
  std::vector<Pair> pairs;
  for (const Family& f : families)
    for (int i = 0; i < per_family; ++i) {
      const double ma = f.rounded ? margin(rng) : 0.0, mb = f.rounded ? margin(rng) : 0.0;
      Pair p{f.a(rng, ma), f.b(rng, mb), random_pose(rng, Vec::Zero()), Pose::identity(), f.name};
      const double r = bounding_radius(p.a) + bounding_radius(p.b);
      p.pb = random_pose(rng, reach(rng) * r * random_unit(rng));
      pairs.push_back(p);
    }
  // Cones on a box's top face (random poses almost never hold a cap or a
  // side line along a face): standing on the base or lying on a side line,
  // tilted by up to 5e-4 rad (within face_angle_tolerance), 1e-3 to 5e-2 deep.
  std::uniform_real_distribution<double> tilt(0.0, 5e-4), depth(1e-3, 5e-2), offset(-0.5, 0.5);
  for (int i = 0; i < per_family; ++i) {
    const Shape box = random_box(rng, 0.0);
    const Vec half = std::get<Box>(box).half_extents;
    const Cone c = std::get<Cone>(cone(rng, 0.0));
    const bool lying = i % 2 == 1;
    const double h = c.half_length, r = c.radius;
    // Lying: the slant side on -y (outward normal (0, -2h, r)) turned to face down.
    const Eigen::Quaterniond down = lying ? Eigen::Quaterniond::FromTwoVectors(Vec(0.0, -2.0 * h, r), -Vec::UnitZ())
                                          : Eigen::Quaterniond::Identity();
    const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(tilt(rng), random_unit(rng))) * down;
    const Vec lowest =
        q * (lying ? Vec(0.0, -r, -h) : Vec(0.0, 0.0, -h));  // a point of the side line, or the base centre
    const Vec t(offset(rng) * half.x(), offset(rng) * half.y(), half.z() - depth(rng) - lowest.z());
    pairs.push_back(
        {box, c, Pose::identity(), Pose::from_quaternion(q, t), lying ? "cone_lying_on_box" : "cone_on_box"});
  }
  // Rounded cylinders (margins 0.02 to 0.1) standing or lying on a box's top
  // face the same way, placed anywhere over it up to 1.5 times its half
  // extents (often hanging over an edge), 1e-3 to 5e-2 deep.
  std::uniform_real_distribution<double> anywhere(-1.5, 1.5);
  for (int i = 0; i < per_family; ++i) {
    const Shape box = random_box(rng, 0.0);
    const Vec half = std::get<Box>(box).half_extents;
    const Cylinder c = std::get<Cylinder>(rounded_cylinder(rng, margin(rng)));
    const bool lying = i % 2 == 1;
    const Eigen::Quaterniond down =
        lying ? Eigen::Quaterniond::FromTwoVectors(Vec::UnitX(), -Vec::UnitZ()) : Eigen::Quaterniond::Identity();
    const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(tilt(rng), random_unit(rng))) * down;
    // The lowest point of the side line at x = r, or the base centre.
    const Vec lowest = q * (lying ? Vec(c.radius, 0.0, 0.0) : Vec(0.0, 0.0, -c.half_length)) - Vec(0, 0, c.margin);
    const Vec t(anywhere(rng) * half.x(), anywhere(rng) * half.y(), half.z() - depth(rng) - lowest.z());
    pairs.push_back({box, c, Pose::identity(), Pose::from_quaternion(q, t),
                     lying ? "rounded_cylinder_lying_on_box" : "rounded_cylinder_on_box"});
  }
  // Rounded boxes and hulls resting on a rounded box's top face, tilted by
  // 1e-4 to 1e-3 rad (a hull on one of its faces), their lowest core
  // corner placed within the gap times the tilt of the face's +x edge, on
  // either side: the cores apart, their closest features a face and a
  // corner (the exact normal the face's) or an edge and a corner hanging
  // beyond it (the exact normal tilted off both faces), 1e-3 to 2e-2 deep.
  std::uniform_real_distribution<double> rest_tilt(1e-4, 1e-3), share(-0.5, 0.5), rest_depth(1e-3, 2e-2);
  for (int i = 0; i < per_family; ++i) {
    const Shape ground = random_box(rng, margin(rng));
    const Box& g = std::get<Box>(ground);
    const bool hull = i % 2 == 1;
    const Shape body = hull ? random_hull(rng, margin(rng)) : random_box(rng, margin(rng));
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    if (hull) {  // a random face of the hull down
      const ConvexPolyhedron& h = *std::get<Polyhedron>(body).hull;
      const hull::Index f = std::uniform_int_distribution<hull::Index>(0, h.mesh().face_count() - 1)(rng);
      q = Eigen::Quaterniond::FromTwoVectors(h.mesh().plane(f).normal, -Vec::UnitZ());
    }
    const Vec level = random_unit(rng).cross(Vec::UnitZ()).normalized();
    const double theta = rest_tilt(rng);
    q = Eigen::Quaterniond(Eigen::AngleAxisd(theta, level)) * q;
    const double mb = hull ? std::get<Polyhedron>(body).margin : std::get<Box>(body).margin;
    const Vec down = q.inverse() * -Vec::UnitZ();
    const Vec lowest = q * (support(body, down) - mb * down);
    const double gap = g.margin + mb - rest_depth(rng);
    const Vec corner(g.half_extents.x() + share(rng) * gap * theta, offset(rng) * g.half_extents.y(),
                     g.half_extents.z() + gap);
    pairs.push_back({ground, body, Pose::identity(), Pose::from_quaternion(q, corner - lowest),
                     hull ? "rounded_hull_over_an_edge" : "rounded_box_over_an_edge"});
  }
  return pairs;
}

struct Worst {
  double surface = 0.0, below_exact = 0.0, distance_gap = 0.0;
  int pairs = 0, touching = 0, failures = 0, biased = 0;
  int cap = 0, segment = 0;  // cones' caps and side lines on a face
  int cylinder_cap = 0, cylinder_segment = 0;
  int resting = 0, resting_face = 0;  // rounded bodies over an edge; on a face path
};

void check_pair(const Pair& p, const std::string& kind, Worst& worst, const ContactSettings& settings = {}) {
  const double size = bounding_radius(p.a) + bounding_radius(p.b);
  const double tol = 1e-9 * size;
  const PenetrationResult pen = penetration(p.a, p.pa, p.b, p.pb);
  ASSERT_EQ(pen.status, Status::ok) << p.family << " " << kind;
  const ContactResult c = contact(p.a, p.pa, p.b, p.pb, nullptr, settings);
  ++worst.pairs;
  if (std::holds_alternative<Cylinder>(p.b)) {
    worst.cylinder_cap += c.path == ContactPath::cap;
    worst.cylinder_segment += c.path == ContactPath::segment;
  }
  if (std::holds_alternative<Cone>(p.b)) {
    worst.cap += c.path == ContactPath::cap;
    worst.segment += c.path == ContactPath::segment;
  }
  if (p.family.find("_over_an_edge") != std::string::npos) {
    ++worst.resting;
    worst.resting_face += c.path == ContactPath::face_a || c.path == ContactPath::face_b;
  }
  SCOPED_TRACE(p.family + " " + kind + " pen " + std::to_string(pen.distance) + " path " + to_string(c.path));
  EXPECT_EQ(c.status, Status::ok);
  EXPECT_GE(c.count, 1);
  if (c.count < 1) {
    ++worst.failures;
    return;
  }
  double deepest = -INFINITY;
  for (int k = 0; k < c.count; ++k) {
    const ContactPoint& q = c.points[k];
    const Vec on_a = q.point + 0.5 * q.depth * c.normal, on_b = q.point - 0.5 * q.depth * c.normal;
    const double ea = std::abs(testing::surface_distance(p.a, p.pa, on_a)),
                 eb = std::abs(testing::surface_distance(p.b, p.pb, on_b));
    worst.surface = std::max({worst.surface, ea / size, eb / size});
    EXPECT_LE(ea, tol) << "point " << k << " off A's surface";
    EXPECT_LE(eb, tol) << "point " << k << " off B's surface";
    deepest = std::max(deepest, q.depth);
  }
  const double below = -pen.distance - deepest;
  worst.below_exact = std::max(worst.below_exact, below / size);
  EXPECT_LE(below, pen.error_bound + tol) << "deepest point shallower than the exact depth";
  // The face preference: contact's distance may sit below penetration()'s by the bias.
  const double bias = settings.relative_bias * std::abs(pen.distance) + settings.absolute_bias * size;
  const double gap = pen.distance - c.distance;
  worst.distance_gap = std::max(worst.distance_gap, std::abs(gap) / size);
  if (std::abs(gap) > pen.error_bound + tol) ++worst.biased;
  EXPECT_GE(gap, -(pen.error_bound + tol)) << "contact distance " << c.distance;
  EXPECT_LE(gap, bias + pen.error_bound + tol) << "contact distance " << c.distance;
}

TEST(ContactProperty, PenetratingAndTouchingPairsGetExactPoints) {
  Worst worst;
  for (const Pair& p : make_pairs(150)) {
    const PenetrationResult pen = penetration(p.a, p.pa, p.b, p.pb);
    if (pen.status != Status::ok || !(pen.distance < 0.0)) continue;
    check_pair(p, "penetrating", worst);
    // Touching: B moved out along the normal by the depth.
    Pair t = p;
    t.pb.translation += -pen.distance * pen.normal;
    const PenetrationResult touch = penetration(t.a, t.pa, t.b, t.pb);
    const double size = bounding_radius(p.a) + bounding_radius(p.b);
    if (touch.status != Status::ok || !(std::abs(touch.distance) <= 1e-9 * size)) continue;
    ++worst.touching;
    check_pair(t, "touching", worst);
  }
  std::printf(
      "pairs %d (touching %d), without points %d, another axis by the bias %d; worst / size: off surface %.3g, "
      "below exact %.3g, distance gap %.3g\n",
      worst.pairs, worst.touching, worst.failures, worst.biased, worst.surface, worst.below_exact, worst.distance_gap);
  EXPECT_GT(worst.pairs, 1500);
  EXPECT_GT(worst.touching, 600);
  std::printf("cone pairs on the cap path %d, on the side-line path %d\n", worst.cap, worst.segment);
  EXPECT_GT(worst.cap, 100);
  EXPECT_GT(worst.segment, 100);
  std::printf("cylinder pairs on the cap path %d, on the side-line path %d\n", worst.cylinder_cap,
              worst.cylinder_segment);
  EXPECT_GT(worst.cylinder_cap, 100);
  EXPECT_GT(worst.cylinder_segment, 100);
  std::printf("rounded bodies resting over an edge %d, on a face path %d\n", worst.resting, worst.resting_face);
  EXPECT_GT(worst.resting, 250);
  EXPECT_GT(worst.resting_face, 0.95 * worst.resting);
}

// Within the contact distance: each pair moved apart along penetration()'s
// normal to a gap of 0 to contact_distance (5 % of the size), so that every
// point is speculative (negative depth: the gap along the normal there) and
// the same checks hold.
TEST(ContactProperty, PairsWithinTheContactDistanceGetExactSpeculativePoints) {
  Worst worst;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  for (const Pair& p : make_pairs(150)) {
    const PenetrationResult pen = penetration(p.a, p.pa, p.b, p.pb);
    if (pen.status != Status::ok || !(pen.distance < 0.0)) continue;
    const double size = bounding_radius(p.a) + bounding_radius(p.b);
    ContactSettings settings;
    settings.contact_distance = 0.05 * size;
    Pair t = p;
    t.pb.translation += (-pen.distance + fraction(rng) * settings.contact_distance) * pen.normal;
    const PenetrationResult apart = penetration(t.a, t.pa, t.b, t.pb);
    if (apart.status != Status::ok || !(apart.distance < settings.contact_distance)) continue;
    check_pair(t, "within the contact distance", worst, settings);
  }
  std::printf(
      "pairs %d, without points %d, another axis by the bias %d; worst / size: off surface %.3g, below exact %.3g, "
      "distance gap %.3g\n",
      worst.pairs, worst.failures, worst.biased, worst.surface, worst.below_exact, worst.distance_gap);
  EXPECT_GT(worst.pairs, 1500);
}

}  // namespace
}  // namespace hedra::collision
