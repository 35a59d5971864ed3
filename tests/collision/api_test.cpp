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
#include <hedra/hull/assert.hpp>
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
                             CastResult (*)(const Shape&, const Pose&, const Vec&, const Shape&, const Pose&,
                                            const Vec&, GjkCache*, const ShapeCastSettings&)>);
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

// ---- poses that are not rotations ---------------------------------------

// Every query of the API on one pair (a box and a sphere 3 apart), each
// answering whether its status is invalid_input.
struct Verdicts {
  bool intersect, distance, penetration, contact, raycast, shape_cast, time_of_impact;
  bool all() const {
    return intersect && distance && penetration && contact && raycast && shape_cast && time_of_impact;
  }
  bool none() const {
    return !intersect && !distance && !penetration && !contact && !raycast && !shape_cast && !time_of_impact;
  }
};

Verdicts invalid_with(const Pose& pose_b) {
  const Shape a = Box{Vec(1.0, 1.0, 1.0), 0.0};
  const Shape b = Sphere{0.5, 0.0};
  const Pose pose_a = Pose::identity();
  const Sweep sweep_b{pose_b, {pose_b.rotation, pose_b.translation - Vec(3.0, 0.0, 0.0)}};
  Verdicts v{};
  v.intersect = intersect(a, pose_a, b, pose_b).status == Status::invalid_input;
  v.distance = distance(a, pose_a, b, pose_b).status == Status::invalid_input;
  v.penetration = penetration(a, pose_a, b, pose_b).status == Status::invalid_input;
  v.contact = contact(a, pose_a, b, pose_b).status == Status::invalid_input;
  v.raycast = raycast(b, pose_b, Vec::Zero(), Vec(4.0, 0.0, 0.0)).status == CastStatus::invalid_input;
  v.shape_cast = shape_cast(a, pose_a, Vec::Zero(), b, pose_b, Vec(-3.0, 0.0, 0.0)).status == CastStatus::invalid_input;
  v.time_of_impact = time_of_impact(a, {pose_a, pose_a}, b, sweep_b).status == CastStatus::invalid_input;
  return v;
}

const Vec kAt(3.0, 0.1, 0.2);

TEST(PoseValidity, RotationScaledByTwoIsInvalidInEveryQuery) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3, Vec(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_TRUE(invalid_with(Pose{r, kAt}).none());
  const Pose scaled{2.0 * r, kAt};
  EXPECT_FALSE(scaled.valid());
  EXPECT_TRUE(invalid_with(scaled).all());
}

TEST(PoseValidity, ReflectionIsInvalidInEveryQuery) {
  const Pose mirror{Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal(), kAt};
  EXPECT_FALSE(mirror.valid());
  EXPECT_TRUE(invalid_with(mirror).all());
  // A rotation by pi (determinant +1, also diagonal) is a rotation.
  EXPECT_TRUE(invalid_with(Pose{Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal(), kAt}).none());
}

// Drift accumulated by integrating a rotation: a small symmetric part added
// to R. Within rotation_tolerance (1e-6 max |R^T R - I|) the pose is
// accepted, beyond it not.
TEST(PoseValidity, AccumulatedDriftWithinAndBeyondTheTolerance) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(1.1, Vec(-1, 2, 0.5).normalized()).toRotationMatrix();
  Eigen::Matrix3d drift;
  drift << 0.2, 0.3, -0.1, 0.3, -0.4, 0.25, -0.1, 0.25, 0.1;  // symmetric, entries <= 0.4
  const auto drifted = [&](double size) { return Pose{r * (Eigen::Matrix3d::Identity() + size * drift), kAt}; };
  const auto error = [](const Pose& p) {
    return (p.rotation.transpose() * p.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  };
  const Pose within = drifted(1e-6);    // |R^T R - I| about 0.8e-6
  const Pose beyond = drifted(1.5e-6);  // about 1.2e-6
  ASSERT_LT(error(within), rotation_tolerance);
  ASSERT_GT(error(beyond), rotation_tolerance);
  EXPECT_TRUE(within.valid());
  EXPECT_TRUE(invalid_with(within).none());
  EXPECT_FALSE(beyond.valid());
  EXPECT_TRUE(invalid_with(beyond).all());
  // A rotation rounded to float (a single-precision engine's transform) is
  // a rotation.
  EXPECT_TRUE((Pose{r.cast<float>().cast<double>(), kAt}.valid()));
}

TEST(PoseValidity, NonFiniteRotationsStayInvalid) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE((Pose{r, kAt}.valid()));
  r(1, 2) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE((Pose{r, kAt}.valid()));
  r(1, 2) = 1e200;  // squares overflow
  EXPECT_FALSE((Pose{r, kAt}.valid()));
  EXPECT_FALSE(Pose::from_quaternion(Eigen::Quaterniond(0, 0, 0, 0), kAt).valid());
  EXPECT_TRUE(Pose::from_quaternion(Eigen::Quaterniond(1e-200, 3e-200, 0, 0), kAt).valid());
}

// ---- a ray needs a direction ----------------------------------------------

TEST(RaycastInput, ZeroOrNonFiniteDirectionIsInvalidInput) {
  const Shape box = Box{Vec(1.0, 1.0, 1.0), 0.0};
  const Pose at = Pose::from_translation(Vec(3.0, 0.0, 0.0));
  EXPECT_EQ(raycast(box, at, Vec::Zero(), Vec::Zero()).status, CastStatus::invalid_input);
  EXPECT_FALSE(raycast(box, at, Vec::Zero(), Vec::Zero()).hit);
  // Even from inside the shape: a zero direction is no ray.
  EXPECT_EQ(raycast(box, at, Vec(3.0, 0.0, 0.0), Vec::Zero()).status, CastStatus::invalid_input);
  EXPECT_EQ(raycast(box, at, Vec::Zero(), Vec(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0)).status,
            CastStatus::invalid_input);
  EXPECT_EQ(raycast(box, at, Vec::Zero(), Vec(std::numeric_limits<double>::infinity(), 0.0, 0.0)).status,
            CastStatus::invalid_input);
  // A tiny direction is still a ray (only zero is rejected).
  EXPECT_EQ(raycast(box, at, Vec::Zero(), Vec(1e-300, 0.0, 0.0), 4e300).status, CastStatus::hit);
}

// ---- assertions: on in Debug or with HEDRA_ENABLE_ASSERTS=ON, else off -----

#ifdef HEDRA_TEST_EXPECT_ASSERTS
TEST(Assertions, OnWhereTheDocsSay) { EXPECT_EQ(HEDRA_ASSERTS_ENABLED, HEDRA_TEST_EXPECT_ASSERTS); }
#endif

}  // namespace
