// Halfspace queries (halfspace.hpp) against exact closed forms and the exact
// reference: the halfspace stands in the reference as a box far larger than
// the shape whose top face is the plane (exact for a shape within its
// footprint), so depths are checked independently of halfspace.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <hedra/collision/halfspace.hpp>
#include <random>

#include "allocation_counter.hpp"
#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using testing::Vec;

// The halfspace {n . x <= margin} (local) as a box of half extents L whose
// top face is its surface, centred below the point `near` (world).
std::pair<Shape, Pose> halfspace_as_box(const Halfspace& h, const Pose& pose, const Vec& near, double L) {
  const Vec n = (pose.rotation * h.normal).normalized();
  const Vec surface_point = pose.apply(h.margin * h.normal);
  const Vec foot = near - n.dot(near - surface_point) * n;
  Pose box_pose;
  box_pose.rotation = Eigen::Quaterniond::FromTwoVectors(Vec::UnitZ(), n).toRotationMatrix();
  box_pose.translation = foot - L * n;
  return {Box{Vec::Constant(L), 0.0}, box_pose};
}

std::vector<Shape> sample_shapes() {
  std::vector<Shape> shapes;
  shapes.push_back(Sphere{0.3, 0.0});
  shapes.push_back(Sphere{0.3, 0.05});
  shapes.push_back(Box{Vec(0.5, 0.2, 0.1), 0.0});
  shapes.push_back(Box{Vec(0.5, 0.2, 0.1), 0.02});
  shapes.push_back(Capsule{0.1, 0.4, 0.0});
  shapes.push_back(Capsule{0.1, 0.4, 0.03});
  shapes.push_back(Cylinder{0.3, 0.2, 0.0});
  shapes.push_back(Cylinder{0.3, 0.2, 0.01});
  shapes.push_back(Cone{0.3, 0.4, 0.0});
  shapes.push_back(Cone{0.3, 0.4, 0.02});
  std::mt19937_64 rng(31);
  shapes.push_back(Polyhedron{testing::make_hull(testing::random_points(rng, 30, Vec(0.4, 0.3, 0.2))), 0.0});
  shapes.push_back(Polyhedron{testing::make_hull(testing::random_points(rng, 12, Vec(0.4, 0.3, 0.2))), 0.01});
  return shapes;
}

TEST(Halfspace, BoxRestingOnThePlaneGivesItsFourBottomCornersAtTheExactDepth) {
  const Halfspace ground;
  const Box box{Vec(0.5, 0.5, 0.5), 0.0};
  const Pose pose = Pose::from_translation(Vec(3.0, -2.0, 0.49));
  const ContactResult r = contact(ground, Pose::identity(), box, pose);
  ASSERT_EQ(r.status, Status::ok);
  ASSERT_EQ(r.count, 4);
  EXPECT_EQ(r.path, ContactPath::face_a);
  EXPECT_NEAR(r.distance, -0.01, 1e-15);
  EXPECT_EQ(r.normal, Vec::UnitZ());
  std::uint32_t corners = 0;
  for (int k = 0; k < r.count; ++k) {
    EXPECT_NEAR(r.points[k].depth, 0.01, 1e-15);
    EXPECT_NEAR(r.points[k].point.z(), -0.005, 1e-15);  // midway between z = 0 and z = -0.01
    EXPECT_EQ(r.points[k].id.kind, FeatureKind::face_vertex);
    corners |= 1u << r.points[k].id.incident;
  }
  EXPECT_EQ(corners, 0b1111u);  // the corners with -z: bits 0 and 1 only
}

TEST(Halfspace, CylinderLyingOnItsSideGivesBothEndsOfTheLowestLine) {
  const Cylinder cylinder{0.2, 0.5, 0.0};
  Pose pose;
  pose.rotation = Eigen::AngleAxisd(M_PI / 2, Vec::UnitX()).toRotationMatrix();  // axis along world y
  pose.translation = Vec(0.0, 0.0, 0.19);
  const ContactResult r = contact(Halfspace{}, Pose::identity(), cylinder, pose);
  ASSERT_EQ(r.count, 2);
  EXPECT_EQ(r.path, ContactPath::segment);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(r.points[k].depth, 0.01, 1e-15);
    EXPECT_NEAR(std::abs(r.points[k].point.y()), 0.5, 1e-15);
  }
  // Standing on a cap: the four rim points on +-x, +-y.
  const ContactResult s = contact(Halfspace{}, Pose::identity(), cylinder, Pose::from_translation(Vec(0, 0, 0.49)));
  ASSERT_EQ(s.count, 4);
  EXPECT_EQ(s.path, ContactPath::cap);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(s.points[k].depth, 0.01, 1e-15);
    EXPECT_LT(s.points[k].id.incident, 4u);  // the deepest rim point merged into the +x one
    EXPECT_EQ(s.points[k].id.clip, 0u);
  }
}

TEST(Halfspace, CapsuleLyingGivesTwoPointsAndStandingOne) {
  const Capsule capsule{0.1, 0.3, 0.0};
  Pose lying;
  lying.rotation = Eigen::AngleAxisd(M_PI / 2, Vec::UnitY()).toRotationMatrix();
  lying.translation = Vec(0, 0, 0.09);
  EXPECT_EQ(contact(Halfspace{}, Pose::identity(), capsule, lying).count, 2);
  const ContactResult standing =
      contact(Halfspace{}, Pose::identity(), capsule, Pose::from_translation(Vec(0, 0, 0.39)));
  ASSERT_EQ(standing.count, 1);
  EXPECT_NEAR(standing.points[0].depth, 0.01, 1e-15);
  EXPECT_EQ(standing.points[0].id.incident, 0u);  // the -z end
}

// Random poses of every shape against tilted halfspaces: the deepest depth
// is the exact reference's, every point's two witnesses lie on the two
// surfaces (so its depth is the gap along the normal there), and the other
// queries agree.
TEST(Halfspace, EveryShapeAgreesWithTheExactReference) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::vector<Shape> shapes = sample_shapes();
  int compared = 0;
  for (int trial = 0; trial < 40; ++trial) {
    for (const Shape& shape : shapes) {
      const Halfspace h{testing::random_unit(rng), trial % 3 == 0 ? 0.05 : 0.0};
      const Pose pose_h = Pose::from_quaternion(Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng)),
                                                Vec(unit(rng), unit(rng), unit(rng)));
      Pose pose_b = Pose::from_quaternion(Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng)),
                                          Vec(unit(rng), unit(rng), unit(rng)) * 5.0);
      // Put B's support 0.1 above to 0.1 below the surface.
      const Vec n = pose_h.rotation * h.normal;
      const double size = bounding_radius(shape);
      const PenetrationResult p0 = penetration(h, pose_h, shape, pose_b);
      ASSERT_EQ(p0.status, Status::ok);
      pose_b.translation -= (p0.distance - 0.1 * unit(rng) * size) * n;

      ContactSettings settings;
      settings.contact_distance = 0.02 * size;
      const ContactResult r = contact(h, pose_h, shape, pose_b, nullptr, settings);
      const PenetrationResult p = penetration(h, pose_h, shape, pose_b);
      ASSERT_EQ(r.status, Status::ok);
      const auto [box, box_pose] = halfspace_as_box(h, pose_h, pose_b.translation, 50.0 * size);
      const reference::ExactResult exact = reference::exact_signed_distance(box, box_pose, shape, pose_b);
      ASSERT_TRUE(exact.ok) << exact.reason;
      const double tol = 1e-9 * size + exact.error_bound;
      EXPECT_NEAR(p.distance, exact.distance, tol) << "trial " << trial;
      EXPECT_NEAR(r.distance, exact.distance, tol);
      EXPECT_LT((r.normal - n).norm(), 1e-15);
      EXPECT_EQ(r.intersecting, r.distance <= 0.0);
      EXPECT_EQ(intersect(h, pose_h, shape, pose_b).intersecting, p.distance <= 0.0);
      const DistanceResult d = distance(h, pose_h, shape, pose_b);
      EXPECT_EQ(d.intersecting, p.distance <= 0.0);
      if (!d.intersecting) {
        EXPECT_DOUBLE_EQ(d.distance, p.distance);
      }
      if (r.distance <= settings.contact_distance) {
        ASSERT_GE(r.count, 1);
        double deepest = -INFINITY;
        for (int k = 0; k < r.count; ++k) deepest = std::max(deepest, r.points[k].depth);
        EXPECT_GE(deepest, -exact.distance - tol);  // never shallower than the exact depth
      } else {
        EXPECT_EQ(r.count, 0);
      }
      for (int k = 0; k < r.count; ++k) {
        const ContactPoint& c = r.points[k];
        EXPECT_GE(c.depth, -settings.contact_distance - 1e-9 * size);
        const Vec on_a = c.point + (c.depth / 2.0) * r.normal, on_b = c.point - (c.depth / 2.0) * r.normal;
        EXPECT_NEAR(n.dot(on_a - pose_h.translation), h.margin, 1e-12);
        EXPECT_NEAR(testing::surface_distance(shape, pose_b, on_b), 0.0, 1e-9 * size) << "point " << k;
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 40 * static_cast<int>(shapes.size()));
}

// A plate thinner than its depth: its top corners are candidates too, and
// the line down from a top corner crosses the plate, so its depth is
// measured to where that line leaves the plate's underside.
TEST(Halfspace, HiddenFeaturesOfAThinPlateGetTheirGapWhereTheLineLeavesTheShape) {
  const Box plate{Vec(0.5, 0.5, 0.0005), 0.0};
  Pose pose;
  // Upside down: the corners with local -z (listed first, so chosen among
  // corners that coincide in the plane) are the top ones. (Tilted, a top
  // corner whose side face leans out over the plane has its own gap: the
  // line down from it leaves the plate at once.)
  pose.rotation = Eigen::Vector3d(1, -1, -1).asDiagonal();  // exactly: sides exactly vertical
  pose.translation = Vec(0, 0, -0.001);
  ContactSettings settings;
  settings.contact_distance = 0.01;
  const ContactResult r = contact(Halfspace{}, Pose::identity(), plate, pose, nullptr, settings);
  ASSERT_EQ(r.count, 4);
  int top = 0;
  for (int k = 0; k < r.count; ++k) {
    const Vec on_b = r.points[k].point - (r.points[k].depth / 2.0) * r.normal;
    EXPECT_NEAR(testing::surface_distance(plate, pose, on_b), 0.0, 1e-12) << k;
    EXPECT_NEAR(r.points[k].depth, 0.0015, 1e-12);  // every corner's line leaves the plate at its bottom
    top += r.points[k].id.incident < 4;
  }
  EXPECT_GT(top, 0);  // a hidden corner was measured
}

TEST(Halfspace, SpeculativePointsComeWithinTheContactDistanceOnly) {
  const Box box{Vec(0.5, 0.5, 0.5), 0.0};
  Pose pose;
  pose.rotation = Eigen::AngleAxisd(0.1, Vec::UnitX()).toRotationMatrix();
  pose.translation = Vec(0, 0, 0.5 * (std::cos(0.1) + std::sin(0.1)) + 0.01);  // lowest edge 0.01 above
  ContactSettings settings;
  EXPECT_EQ(contact(Halfspace{}, Pose::identity(), box, pose, nullptr, settings).count, 0);
  settings.contact_distance = 0.02;
  const ContactResult r = contact(Halfspace{}, Pose::identity(), box, pose, nullptr, settings);
  ASSERT_EQ(r.count, 2);  // the lowest edge's corners; the next ones are 0.1 higher
  EXPECT_NEAR(r.distance, 0.01, 1e-15);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(r.points[k].depth, -0.01, 1e-15);
}

TEST(Halfspace, AHullRestingOnAFaceOfManyVerticesKeepsFourOfLargestArea) {
  std::vector<Vec> points;
  for (int i = 0; i < 12; ++i) {
    const double a = 2.0 * M_PI * i / 12.0;
    points.emplace_back(std::cos(a), std::sin(a), 0.0);
    points.emplace_back(0.5 * std::cos(a), 0.5 * std::sin(a), 1.0);
  }
  const Polyhedron prism{testing::make_hull(points), 0.0};
  const ContactResult r = contact(Halfspace{}, Pose::identity(), prism, Pose::from_translation(Vec(0, 0, -0.001)));
  ASSERT_EQ(r.count, 4);
  // The kept quadrilateral: the first vertex, its opposite, and the two at a
  // quarter turn: area 2.
  Vec p[4];
  for (int k = 0; k < 4; ++k) {
    p[k] = r.points[k].point;
    EXPECT_NEAR(r.points[k].depth, 0.001, 1e-15);
  }
  const double area =
      0.5 * std::abs((p[2] - p[0]).cross(p[1] - p[0]).z()) + 0.5 * std::abs((p[3] - p[0]).cross(p[1] - p[0]).z());
  EXPECT_NEAR(area, 2.0, 1e-12);
  // The same points with a cache, cold and warm.
  ContactCache cache;
  const ContactResult cold =
      contact(Halfspace{}, Pose::identity(), prism, Pose::from_translation(Vec(0, 0, -0.001)), &cache);
  const ContactResult warm =
      contact(Halfspace{}, Pose::identity(), prism, Pose::from_translation(Vec(0, 0, -0.001)), &cache);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(cold.points[k].id, warm.points[k].id);
}

TEST(Halfspace, HoldKeepsTheLastFourWhileTheyAreWithinTheHold) {
  std::vector<Vec> points;
  for (int i = 0; i < 8; ++i) {
    const double a = 2.0 * M_PI * i / 8.0;
    points.emplace_back(std::cos(a), std::sin(a), 0.0);
    points.emplace_back(std::cos(a), std::sin(a), 1.0);
  }
  const Polyhedron prism{testing::make_hull(points), 0.0};
  ContactSettings settings;
  settings.hold = 1e-6;
  ContactCache cache;
  const Pose level = Pose::from_translation(Vec(0, 0, -0.01));
  const ContactResult first = contact(Halfspace{}, Pose::identity(), prism, level, &cache, settings);
  ASSERT_EQ(first.count, 4);
  // Tilted by 1e-7 rad towards another vertex: within the hold, the same four.
  Pose tilted = level;
  tilted.rotation = Eigen::AngleAxisd(1e-7, Vec(-std::sin(M_PI / 8), std::cos(M_PI / 8), 0)).toRotationMatrix();
  const ContactResult held = contact(Halfspace{}, Pose::identity(), prism, tilted, &cache, settings);
  ASSERT_EQ(held.count, 4);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(held.points[k].id, first.points[k].id);
  // Tilted by 1e-3 towards a bottom vertex not held: beyond the hold, the
  // cold choice, which has that vertex (the deepest).
  const auto kept = [&](std::uint32_t v) {
    for (int k = 0; k < 4; ++k)
      if (first.points[k].id.incident == v) return true;
    return false;
  };
  hull::Index other = 0;
  while (kept(other) || prism.hull->vertex(other).z() + prism.hull->offset().z() > 0.5) ++other;
  const Vec v = prism.hull->vertex(other) + prism.hull->offset();
  tilted.rotation = Eigen::AngleAxisd(1e-3, Vec(-v.y(), v.x(), 0).normalized()).toRotationMatrix();
  const ContactResult moved = contact(Halfspace{}, Pose::identity(), prism, tilted, &cache, settings);
  ASSERT_EQ(moved.count, 4);
  EXPECT_EQ(moved.points[0].id.incident, other);
  EXPECT_NEAR(moved.points[0].depth, -moved.distance, 1e-15);
}

TEST(Halfspace, BadInputIsInvalidInputWithAMessage) {
  const Box box{Vec(1, 1, 1), 0.0};
  const Pose ok = Pose::identity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Halfspace& h : {Halfspace{Vec(nan, 0, 1), 0.0}, Halfspace{Vec(0, 0, 2), 0.0}, Halfspace{Vec::Zero(), 0.0},
                             Halfspace{Vec::UnitZ(), -1.0}, Halfspace{Vec::UnitZ(), nan}}) {
    EXPECT_FALSE(validate(h).ok());
    EXPECT_FALSE(validate(h).message.empty());
    EXPECT_EQ(contact(h, ok, box, ok).status, Status::invalid_input);
    EXPECT_EQ(penetration(h, ok, box, ok).status, Status::invalid_input);
    EXPECT_EQ(distance(h, ok, box, ok).status, Status::invalid_input);
    EXPECT_EQ(intersect(h, ok, box, ok).status, Status::invalid_input);
    EXPECT_EQ(raycast(h, ok, Vec(0, 0, 1), Vec(0, 0, -1)).status, CastStatus::invalid_input);
  }
  EXPECT_EQ(contact(Halfspace{}, ok, Box{Vec(-1, 1, 1), 0.0}, ok).status, Status::invalid_input);
  EXPECT_EQ(contact(Halfspace{}, ok, Polyhedron{}, ok).status, Status::invalid_input);
  Pose bad;
  bad.translation.x() = nan;
  EXPECT_EQ(contact(Halfspace{}, bad, box, ok).status, Status::invalid_input);
  EXPECT_EQ(contact(Halfspace{}, ok, box, bad).status, Status::invalid_input);
  ContactSettings settings;
  settings.contact_distance = nan;
  EXPECT_EQ(contact(Halfspace{}, ok, box, ok, nullptr, settings).status, Status::invalid_input);
  EXPECT_TRUE(validate(Halfspace{Vec(0, 0, 1 + 1e-9), 0.0}).ok());  // a rounded unit vector
}

TEST(Halfspace, RaycastHitsWhereTheRayCrossesTheSurface) {
  const Halfspace h{Vec::UnitZ(), 0.5};
  const Pose pose = Pose::from_translation(Vec(0, 0, 1));  // surface at z = 1.5
  const RaycastResult hit = raycast(h, pose, Vec(1, 2, 3.5), Vec(0, 0, -4));
  ASSERT_EQ(hit.status, CastStatus::hit);
  EXPECT_DOUBLE_EQ(hit.fraction, 0.5);
  EXPECT_EQ(hit.normal, Vec::UnitZ());
  EXPECT_NEAR(hit.point.z(), 1.5, 1e-15);
  EXPECT_EQ(raycast(h, pose, Vec(1, 2, 3.5), Vec(0, 0, -1)).status, CastStatus::separated);  // ends 0.5 above
  EXPECT_EQ(raycast(h, pose, Vec(1, 2, 3.5), Vec(1, 0, 0)).status, CastStatus::separated);   // parallel
  EXPECT_EQ(raycast(h, pose, Vec(1, 2, 3.5), Vec(0, 0, 1)).status, CastStatus::separated);   // going up
  const RaycastResult inside = raycast(h, pose, Vec(1, 2, 1.0), Vec(0, 0, 1));
  EXPECT_EQ(inside.status, CastStatus::initially_overlapping);
  EXPECT_EQ(inside.fraction, 0.0);
  EXPECT_EQ(inside.normal, Vec::Zero());
}

TEST(Halfspace, QueriesAllocateNothing) {
  const std::vector<Shape> shapes = sample_shapes();
  const Pose pose = Pose::from_translation(Vec(0, 0, 0.05));
  ContactCache cache;
  ContactSettings settings;
  settings.hold = 1e-6;
  const long before = g_allocations.load();
  int points = 0;
  for (const Shape& s : shapes) {
    points += contact(Halfspace{}, Pose::identity(), s, pose, &cache, settings).count;
    points += penetration(Halfspace{}, Pose::identity(), s, pose).status == Status::ok;
    points += distance(Halfspace{}, Pose::identity(), s, pose).status == Status::ok;
  }
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_GT(points, 0);
}

}  // namespace
}  // namespace hedra::collision
