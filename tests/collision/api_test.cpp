// The embedding API's traps closed: shapes whose sizes cannot be swapped
// silently, poses that are not rigid motions, a ray without a direction,
// and one argument order (..., cache, settings) for every pairwise query.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <hedra/collision/cast.hpp>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>
#include <hedra/collision/time_of_impact.hpp>
#include <limits>
#include <type_traits>

namespace {

using namespace hedra::collision;
using Vec = Eigen::Vector3d;

// ---- shapes: radius first, and named factories ---------------------------

// Capsule, Cylinder and Cone list their fields in one order (radius, then
// half length: the scene format's and Bullet's). A capsule lying on its side
// on the ground sinks by its radius, as the cylinder written the same way.
TEST(ShapeOrder, CapsuleWrittenLikeCylinderIsTheSameSize) {
  const Box ground{Vec(5.0, 5.0, 1.0), 0.0};  // top face at z = 1
  const Pose lying{Eigen::AngleAxisd(M_PI / 2, Vec::UnitX()).toRotationMatrix(), Vec(0.0, 0.0, 1.0)};
  const PenetrationResult capsule = penetration(ground, Pose::identity(), Capsule{0.3, 0.5}, lying);
  const PenetrationResult cylinder = penetration(ground, Pose::identity(), Cylinder{0.3, 0.5}, lying);
  ASSERT_EQ(capsule.status, Status::ok);
  ASSERT_EQ(cylinder.status, Status::ok);
  EXPECT_NEAR(capsule.distance, -0.3, 1e-9);
  EXPECT_NEAR(cylinder.distance, -0.3, 1e-9);
  const Capsule c{0.3, 0.5};
  EXPECT_EQ(c.radius, 0.3);
  EXPECT_EQ(c.half_length, 0.5);
}

TEST(ShapeOrder, FactoriesSayTheSameAsTheAggregates) {
  const Capsule capsule = make_capsule(Radius{0.3}, HalfLength{0.5}, Margin{0.01});
  EXPECT_EQ(capsule.radius, 0.3);
  EXPECT_EQ(capsule.half_length, 0.5);
  EXPECT_EQ(capsule.margin, 0.01);
  const Cylinder cylinder = make_cylinder(Radius{0.3}, HalfLength{0.5});
  EXPECT_EQ(cylinder.radius, 0.3);
  EXPECT_EQ(cylinder.half_length, 0.5);
  EXPECT_EQ(cylinder.margin, 0.0);
  const Cone cone = make_cone(Radius{0.3}, HalfLength{0.5});
  EXPECT_EQ(cone.radius, 0.3);
  EXPECT_EQ(cone.half_length, 0.5);
  const Sphere sphere = make_sphere(Radius{2.0}, Margin{0.5});
  EXPECT_EQ(sphere.radius, 2.0);
  EXPECT_EQ(sphere.margin, 0.5);
  const Box box = make_box(HalfExtents{1.0, 2.0, 3.0});
  EXPECT_EQ(box.half_extents, Vec(1.0, 2.0, 3.0));
  EXPECT_EQ(make_box(HalfExtents{Vec(1.0, 2.0, 3.0)}, Margin{0.1}).margin, 0.1);
}

// The sizes only go in by name and in their order: swapped, bare or
// unnamed ({0.3}) arguments do not compile.
static_assert(std::is_invocable_v<decltype(&make_capsule), Radius, HalfLength, Margin>);
static_assert(!std::is_invocable_v<decltype(&make_capsule), HalfLength, Radius, Margin>);
static_assert(!std::is_invocable_v<decltype(&make_capsule), double, double, double>);
static_assert(!std::is_invocable_v<decltype(&make_cylinder), HalfLength, Radius, Margin>);
static_assert(!std::is_invocable_v<decltype(&make_cone), HalfLength, Radius, Margin>);
static_assert(!std::is_convertible_v<double, Radius>);
static_assert(!std::is_convertible_v<double, HalfLength>);
static_assert(!std::is_convertible_v<double, Margin>);

// ---- one argument order: (..., cache, settings) --------------------------

static_assert(std::is_same_v<decltype(&shape_cast),
                             CastResult (*)(const Shape&, const Pose&, const Vec&, const Shape&, const Pose&, const Vec&,
                                            GjkCache*, const ShapeCastSettings&)>);
static_assert(std::is_same_v<decltype(&time_of_impact), CastResult (*)(const Shape&, const Sweep&, const Shape&,
                                                                        const Sweep&, GjkCache*, const ToiSettings&)>);
static_assert(std::is_same_v<decltype(&distance), DistanceResult (*)(const Shape&, const Pose&, const Shape&,
                                                                      const Pose&, GjkCache*, const GjkSettings&)>);
static_assert(
    std::is_same_v<decltype(&penetration), PenetrationResult (*)(const Shape&, const Pose&, const Shape&, const Pose&,
                                                                 GjkCache*, const PenetrationSettings&)>);

TEST(ArgumentOrder, CastAndTimeOfImpactTakeCacheThenSettings) {
  GjkCache cache;
  ShapeCastSettings cast;
  cast.target_distance = 0.5;
  const CastResult r = shape_cast(Sphere{1.0}, Pose::identity(), Vec::Zero(), Sphere{1.0},
                                  Pose::from_translation(Vec(5.0, 0.0, 0.0)), Vec(-4.0, 0.0, 0.0), &cache, cast);
  ASSERT_EQ(r.status, CastStatus::hit);
  EXPECT_NEAR(r.fraction, 2.5 / 4.0, 1e-8);  // centres 2.5 apart: distance 0.5
  EXPECT_TRUE(cache.valid);
  ToiSettings toi;
  toi.target_distance = 0.5;
  GjkCache toi_cache;
  const Sweep still{Pose::identity(), Pose::identity()};
  const Sweep moving{Pose::from_translation(Vec(5.0, 0.0, 0.0)), Pose::from_translation(Vec(1.0, 0.0, 0.0))};
  const CastResult t = time_of_impact(Sphere{1.0}, still, Sphere{1.0}, moving, &toi_cache, toi);
  ASSERT_EQ(t.status, CastStatus::hit);
  EXPECT_NEAR(t.fraction, 2.5 / 4.0, 1e-6);
  EXPECT_TRUE(toi_cache.valid);
}

}  // namespace
