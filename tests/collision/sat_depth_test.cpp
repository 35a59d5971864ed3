// penetration() on two overlapping boxes answers from SAT's 15 axes
// (collision/src/sat_depth.cpp): closed-form depths, the same boxes as
// hulls (GJK and EPA) within the two error bounds, and the exact reference.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/query.hpp>
#include <random>

#include "collision_test_support.hpp"

namespace hedra::collision::testing {
namespace {

Eigen::Matrix3d rotation_of(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

std::vector<Vec> corners(const Vec& h) {
  std::vector<Vec> out;
  for (int i = 0; i < 8; ++i) out.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  return out;
}

// The witnesses' contract: point_b - point_a = distance * normal, each
// point on its shape's surface (its support value along the normal).
void expect_witnesses(const Box& a, const Pose& pa, const Box& b, const Pose& pb, const PenetrationResult& r,
                      double tol) {
  EXPECT_LT((r.point_b - r.point_a - r.distance * r.normal).norm(), tol);
  const Vec na = pa.rotation.transpose() * r.normal, nb = pb.rotation.transpose() * -r.normal;
  EXPECT_NEAR(r.normal.dot(r.point_a), r.normal.dot(pa.apply(support(a, na))), tol);
  EXPECT_NEAR(-r.normal.dot(r.point_b), -r.normal.dot(pb.apply(support(b, nb))), tol);
}

TEST(SatDepth, AxisAlignedBoxesClosedForm) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.05, 1.0);
  int checked = 0;
  for (int i = 0; i < 500; ++i) {
    const Box a{Vec(size(rng), size(rng), size(rng)), 0.0}, b{Vec(size(rng), size(rng), size(rng)), 0.0};
    const Pose pa{Eigen::Matrix3d::Identity(), Vec(u(rng), u(rng), u(rng))};
    const Pose pb{Eigen::Matrix3d::Identity(), Vec(u(rng), u(rng), u(rng))};
    const Vec overlap = (a.half_extents + b.half_extents) - (pb.translation - pa.translation).cwiseAbs();
    if (overlap.minCoeff() <= 0.0) continue;
    int k = 0;
    overlap.minCoeff(&k);
    ++checked;
    const PenetrationResult r = penetration(a, pa, b, pb);
    ASSERT_EQ(r.status, Status::ok);
    EXPECT_EQ(r.gjk_iterations, 0);  // answered before GJK
    EXPECT_NEAR(r.distance, -overlap[k], 1e-14);
    EXPECT_LE(r.error_bound, 1e-10 * std::max(a.half_extents.norm(), b.half_extents.norm()));
    EXPECT_NEAR(std::abs(r.normal[k]), 1.0, 1e-15);
    expect_witnesses(a, pa, b, pb, r, 1e-12);
  }
  EXPECT_GT(checked, 100);
}

// Both boxes turned by one rotation and moved far from the origin: the
// depth of the axis-aligned pair; and rounded boxes: the cores' depth plus
// both margins.
TEST(SatDepth, RotatedFarAndRoundedClosedForm) {
  std::mt19937_64 rng(32);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Matrix3d q = rotation_of(rng);
    const Vec far = (i % 2 ? 1e6 : 1.0) * Vec(1.0, -2.0, 0.5);
    const Box a{Vec(1.0, 0.5, 0.25), i % 3 ? 0.0 : 0.05}, b{Vec(0.5, 0.4, 0.3), i % 3 ? 0.0 : 0.02};
    const double depth = 0.1 + 1e-3 * i;  // along A's z: 0.25 + 0.3 + margins - offset
    const double margins = a.margin + b.margin;
    const Vec local(0.2, -0.1, 0.55 + margins - depth);
    const Pose pa{q, far}, pb{q, far + q * local};
    const PenetrationResult r = penetration(a, pa, b, pb);
    ASSERT_EQ(r.status, Status::ok);
    EXPECT_NEAR(r.distance, -depth, 1e-15 * far.norm() + 1e-13);
    EXPECT_LT((r.normal - q.col(2)).norm(), 1e-12);
    if (margins == 0.0) expect_witnesses(a, pa, b, pb, r, 1e-15 * far.norm() + 1e-12);
  }
}

// Thin plates crossing and stacked: 1e-4 thick, overlapping by 1e-5.
TEST(SatDepth, ThinPlatesClosedForm) {
  const double t = 1e-4;
  const Box plate{Vec(1.0, 1.0, t), 0.0};
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(0.7, Vec::UnitZ()).toRotationMatrix();
  const Pose pa{Eigen::Matrix3d::Identity(), Vec::Zero()};
  const Pose stacked{yaw, Vec(0.3, 0.2, 2.0 * t - 1e-5)};
  const PenetrationResult r = penetration(plate, pa, plate, stacked);
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_NEAR(r.distance, -1e-5, 1e-16);
  EXPECT_LT((r.normal - Vec::UnitZ()).norm(), 1e-15);
  expect_witnesses(plate, pa, plate, stacked, r, 1e-15);
  // A smaller plate standing through A near A's edge (y = 0.999): out
  // sideways past A's edge, 1 + t - 0.999.
  const Box small{Vec(0.3, 0.3, t), 0.0};
  const Eigen::Matrix3d stand = Eigen::AngleAxisd(M_PI / 2, Vec::UnitX()).toRotationMatrix();
  const Pose through{stand, Vec(0.0, 0.999, 0.0)};
  const PenetrationResult s = penetration(plate, pa, small, through);
  ASSERT_EQ(s.status, Status::ok);
  EXPECT_NEAR(s.distance, -(1.0 + t - 0.999), 1e-15);
  EXPECT_LT((s.normal - Vec::UnitY()).norm(), 1e-15);
  expect_witnesses(plate, pa, small, through, s, 1e-15);
}

// Random pairs, near-parallel faces (1e-12 .. 1e-2 rad), thin plates,
// deep overlaps and far from the origin: SAT's answer against the same
// boxes as hulls (GJK and EPA) within both error bounds plus rounding, and
// against the exact reference.
TEST(SatDepth, AgreesWithEpaAndTheExactReference) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.1, 1.0), expo(-12.0, -2.0);
  int checked = 0, by_sat = 0;
  for (int i = 0; i < 600; ++i) {
    const int kind = i % 4;  // random, near-parallel, thin plate, deep
    Vec ha(size(rng), size(rng), size(rng)), hb(size(rng), size(rng), size(rng));
    if (kind == 2) ha.z() = hb.z() = 1e-3 * size(rng);
    const Box a{ha, 0.0}, b{hb, 0.0};
    const Eigen::Matrix3d ra = rotation_of(rng);
    Eigen::Matrix3d rb = rotation_of(rng);
    if (kind == 1 || kind == 2)
      rb = ra * Eigen::AngleAxisd(std::pow(10.0, expo(rng)), random_unit(rng)).toRotationMatrix() *
           Eigen::AngleAxisd(u(rng) * M_PI, Vec::UnitZ()).toRotationMatrix();
    const Vec far = (i % 5 == 0 ? 1e5 : 0.0) * Vec(1.0, 1.0, -1.0);
    const double spread = kind == 3 ? 0.1 : 1.0;
    Vec offset(spread * u(rng), spread * u(rng), spread * u(rng));
    if (kind == 1 || kind == 2) offset = ra * Vec(0.3 * u(rng), 0.3 * u(rng), (ha.z() + hb.z()) * (1.0 - 0.1 * size(rng)));
    const Pose pa{ra, far}, pb{rb, far + offset};
    const PenetrationResult r = penetration(a, pa, b, pb);
    if (r.distance > 0.0) continue;
    ++checked;
    by_sat += r.gjk_iterations == 0;
    ASSERT_EQ(r.status, Status::ok) << i;
    const double scale = std::max(ha.norm(), hb.norm());
    const double rounding = 1e-13 * (scale + far.norm() * 1e-2);
    const Polyhedron ha_hull{make_hull(corners(ha)), 0.0}, hb_hull{make_hull(corners(hb)), 0.0};
    const PenetrationResult e = penetration(ha_hull, pa, hb_hull, pb);
    ASSERT_EQ(e.status, Status::ok) << i;
    EXPECT_NEAR(r.distance, e.distance, r.error_bound + e.error_bound + rounding) << i << " kind " << kind;
    const reference::ExactResult x = reference::exact_signed_distance(a, pa, b, pb);
    ASSERT_TRUE(x.ok) << x.reason;
    EXPECT_NEAR(r.distance, x.distance, r.error_bound + x.error_bound + rounding) << i << " kind " << kind;
    if (x.normal_unique && x.normal_spread == 0.0) EXPECT_LT((r.normal - x.normal).norm(), 1e-6) << i;
    expect_witnesses(a, pa, b, pb, r, 1e-9 * scale + rounding);
  }
  EXPECT_GT(checked, 300);
  EXPECT_GT(by_sat, checked * 9 / 10);
}

}  // namespace
}  // namespace hedra::collision::testing
