// Tests of the mass properties against closed forms worked out independently
// of the implementation: boxes (I = m/12 (b^2 + c^2), ...), the corner
// tetrahedron (by direct integration: int x^2 = a^3 b c / 60, int xy =
// a^2 b^2 c / 120), the regular tetrahedron (I = m a^2 / 20), regular prisms
// (polar moment of the n-gon A R^2 (2 + cos(2 pi / n)) / 6); invariance under
// a 1e6 translation; R I R^T for rotated boxes; flat, segment and point
// meshes; bad input.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <hedra/hull/mass.hpp>
#include <random>

#include "test_meshes.hpp"

namespace hedra::hull {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

double max_abs(const Matrix3d& m) { return m.cwiseAbs().maxCoeff(); }

Matrix3d box_inertia(double mass, const Vector3d& size) {
  const Vector3d s2 = size.cwiseProduct(size);
  return Vector3d(mass / 12 * (s2.y() + s2.z()), mass / 12 * (s2.x() + s2.z()), mass / 12 * (s2.x() + s2.y()))
      .asDiagonal();
}

Matrix3d random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

HalfEdgeMesh transformed(const HalfEdgeMesh& m, const Matrix3d& R, const Vector3d& t) {
  std::vector<Vector3d> pts;
  for (const auto& v : m.vertices) pts.push_back(R * v.position + t);
  return test::mesh_from(pts, m.polygons());
}

TEST(Mass, UnitCube) {
  const MassProperties p = mass_properties(test::unit_cube());
  EXPECT_EQ(p.status, MassStatus::ok);
  EXPECT_NEAR(p.volume, 1.0, 1e-15);
  EXPECT_NEAR(p.mass, 1.0, 1e-15);
  EXPECT_NEAR(p.surface_area, 6.0, 1e-14);
  EXPECT_LT((p.centroid - Vector3d(0.5, 0.5, 0.5)).norm(), 1e-15);
  EXPECT_LT(max_abs(p.inertia - Matrix3d::Identity() / 6.0), 1e-15);
}

TEST(Mass, BoxesWithDensity) {
  const Vector3d lo(-1, 2, 0.5), hi(2, 2.5, 4.5);
  const Vector3d size = hi - lo;
  const double density = 7.5;
  const HalfEdgeMesh box = test::make_box(lo, hi);
  const MassProperties p = mass_properties(box, density);
  const double vol = size.prod();
  EXPECT_NEAR(p.volume, vol, 1e-14 * vol);
  EXPECT_NEAR(p.mass, density * vol, 1e-14 * density * vol);
  EXPECT_NEAR(p.surface_area, 2 * (size.x() * size.y() + size.y() * size.z() + size.x() * size.z()), 1e-13);
  EXPECT_LT((p.centroid - 0.5 * (lo + hi)).norm(), 1e-14);
  const Matrix3d expected = box_inertia(density * vol, size);
  EXPECT_LT(max_abs(p.inertia - expected), 1e-14 * max_abs(expected));
  // The single-value accessors agree.
  EXPECT_EQ(volume(box), p.volume);
  EXPECT_EQ(surface_area(box), p.surface_area);
  EXPECT_EQ(centroid(box), p.centroid);
  EXPECT_EQ(inertia_tensor(box, density), p.inertia);
  EXPECT_LT(max_abs(inertia_tensor(box) - expected / density), 1e-14 * max_abs(expected));
}

TEST(Mass, CornerTetrahedron) {
  const double a = 2, b = 3, c = 5;
  const HalfEdgeMesh tet = test::make_tetrahedron({0, 0, 0}, {a, 0, 0}, {0, b, 0}, {0, 0, c});
  const MassProperties p = mass_properties(tet);
  const double m = a * b * c / 6;
  EXPECT_NEAR(p.volume, m, 1e-14);
  EXPECT_LT((p.centroid - Vector3d(a, b, c) / 4).norm(), 1e-15);
  // About the corner: int x^2 = m a^2 / 10, int x y = m a b / 20; shifted to
  // the centroid (a, b, c) / 4: Ixx = 3 m (b^2 + c^2) / 80, Ixy = m a b / 80.
  Matrix3d expected;
  expected << 3 * m * (b * b + c * c) / 80, m * a * b / 80, m * a * c / 80,  //
      m * a * b / 80, 3 * m * (a * a + c * c) / 80, m * b * c / 80,          //
      m * a * c / 80, m * b * c / 80, 3 * m * (a * a + b * b) / 80;
  EXPECT_LT(max_abs(p.inertia - expected), 1e-14 * max_abs(expected)) << p.inertia << "\n\n" << expected;
  const double hyp = 0.5 * Vector3d(b * c, a * c, a * b).norm();
  EXPECT_NEAR(p.surface_area, 0.5 * (a * b + b * c + a * c) + hyp, 1e-14);
}

TEST(Mass, RegularTetrahedronIsIsotropic) {
  // Alternate corners of a cube of side s: edge s sqrt(2), volume s^3 / 3.
  const double s = 1.5;
  const HalfEdgeMesh tet = test::make_tetrahedron({0, 0, 0}, {s, s, 0}, {s, 0, s}, {0, s, s});
  const MassProperties p = mass_properties(tet, 2.0);
  const double edge = s * std::sqrt(2.0), m = 2.0 * s * s * s / 3;
  EXPECT_NEAR(p.mass, m, 1e-14);
  EXPECT_LT((p.centroid - Vector3d(s, s, s) / 2).norm(), 1e-15);
  EXPECT_LT(max_abs(p.inertia - m * edge * edge / 20 * Matrix3d::Identity()), 1e-14);
  EXPECT_NEAR(p.surface_area, std::sqrt(3.0) * edge * edge, 1e-14);
}

TEST(Mass, RegularPrisms) {
  for (int n : {3, 4, 5, 8, 17}) {
    const double R = 1.3, h = 0.7;
    const HalfEdgeMesh prism = test::make_prism(test::regular_polygon(n, R, {2, -1}, 0.3), -4.0, -4.0 + h);
    const MassProperties p = mass_properties(prism);
    const double theta = 2 * M_PI / n;
    const double base_area = 0.5 * n * R * R * std::sin(theta);
    const double m = base_area * h;
    const double polar = m * R * R * (2 + std::cos(theta)) / 6;  // about the axis
    const double side = 2 * R * std::sin(theta / 2);
    SCOPED_TRACE(n);
    EXPECT_NEAR(p.volume, m, 1e-14);
    EXPECT_NEAR(p.surface_area, 2 * base_area + n * side * h, 1e-13);
    EXPECT_LT((p.centroid - Vector3d(2, -1, -4 + h / 2)).norm(), 1e-14);
    const Matrix3d expected = Vector3d(polar / 2 + m * h * h / 12, polar / 2 + m * h * h / 12, polar).asDiagonal();
    EXPECT_LT(max_abs(p.inertia - expected), 1e-14) << p.inertia;
  }
}

TEST(Mass, TranslationByAMillionKeepsAccuracy) {
  // At 1e6 coordinates are spaced 1.2e-10 apart, so the translated meshes
  // (exact for the boxes and the tetrahedron, rounded by that much for the
  // others) must agree to about 1e-10 of the mesh's own size; a computation
  // about the world origin would cancel terms of 1e12 and lose ~1e-4.
  std::mt19937_64 rng(3);
  const Vector3d offset(1e6, -2e6, 3.5e6);
  const HalfEdgeMesh meshes[] = {test::unit_cube(), test::make_box({0, 0, 0}, {0.25, 2, 0.5}),
                                 test::make_tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}),
                                 test::make_prism(test::regular_polygon(7, 1.0), 0, 1),
                                 test::random_convex_solid(rng, 1.0)};
  for (const HalfEdgeMesh& mesh : meshes) {
    const MassProperties here = mass_properties(mesh);
    const MassProperties far = mass_properties(test::translated(mesh, offset));
    ASSERT_EQ(far.status, MassStatus::ok);
    EXPECT_NEAR(far.volume, here.volume, 1e-9 * here.volume);
    EXPECT_NEAR(far.surface_area, here.surface_area, 1e-9 * here.surface_area);
    EXPECT_LT((far.centroid - offset - here.centroid).norm(), 1e-9);
    EXPECT_LT(max_abs(far.inertia - here.inertia), 1e-9 * max_abs(here.inertia)) << far.inertia << "\n\n"
                                                                                 << here.inertia;
  }
  // And the cube at the offset against the closed form directly.
  const MassProperties cube = mass_properties(test::translated(test::unit_cube(), offset));
  EXPECT_NEAR(cube.volume, 1.0, 1e-9);
  EXPECT_LT(max_abs(cube.inertia - Matrix3d::Identity() / 6.0), 1e-9);
}

TEST(Mass, RotatedBoxIsRotatedInertia) {
  std::mt19937_64 rng(17);
  const Vector3d size(0.5, 1.25, 3.0);
  const HalfEdgeMesh box = test::make_box(-size / 2, size / 2);
  const Matrix3d I = box_inertia(size.prod(), size);
  for (int i = 0; i < 20; ++i) {
    const Matrix3d R = random_rotation(rng);
    const Vector3d t(10 * i, -3.0 * i, 0.5);
    const MassProperties p = mass_properties(transformed(box, R, t));
    ASSERT_EQ(p.status, MassStatus::ok);
    EXPECT_NEAR(p.volume, size.prod(), 1e-13);
    EXPECT_LT((p.centroid - t).norm(), 1e-13);
    const Matrix3d expected = R * I * R.transpose();
    EXPECT_LT(max_abs(p.inertia - expected), 1e-13) << p.inertia << "\n\n" << expected;
    // Symmetric, with the principal moments of the box.
    EXPECT_LT(max_abs(p.inertia - p.inertia.transpose()), 1e-15);
    Eigen::SelfAdjointEigenSolver<Matrix3d> eig(p.inertia);
    Vector3d principal = I.diagonal();
    std::sort(principal.data(), principal.data() + 3);
    EXPECT_LT((eig.eigenvalues() - principal).norm(), 1e-13);
  }
}

TEST(Mass, RandomSolidsSatisfyTheTriangleInequalityOfInertia) {
  // For any solid the principal moments obey I1 + I2 >= I3; and the centroid
  // is inside (behind every face plane).
  std::mt19937_64 rng(23);
  for (int i = 0; i < 50; ++i) {
    const HalfEdgeMesh mesh = test::random_convex_solid(rng, 2.0);
    const MassProperties p = mass_properties(mesh);
    ASSERT_EQ(p.status, MassStatus::ok);
    EXPECT_GT(p.volume, 0);
    Eigen::SelfAdjointEigenSolver<Matrix3d> eig(p.inertia);
    const Vector3d e = eig.eigenvalues();
    EXPECT_GT(e(0), 0);
    EXPECT_GE(e(0) + e(1), e(2) * (1 - 1e-12));
    for (Index f = 0; f < mesh.face_count(); ++f) EXPECT_LT(mesh.plane(f).signed_distance(p.centroid), 0);
  }
}

TEST(Mass, FlatSegmentAndPoint) {
  // A flat right triangle: area centroid at the average of its corners.
  const HalfEdgeMesh tri = test::make_flat_polygon({{0, 0, 1}, {3, 0, 1}, {0, 3, 1}});
  MassProperties p = mass_properties(tri);
  EXPECT_EQ(p.status, MassStatus::flat);
  EXPECT_EQ(p.volume, 0.0);
  EXPECT_EQ(p.mass, 0.0);
  EXPECT_NEAR(p.surface_area, 2 * 4.5, 1e-14);  // both sides
  EXPECT_LT((p.centroid - Vector3d(1, 1, 1)).norm(), 1e-15);
  EXPECT_EQ(p.inertia, Matrix3d::Zero());
  // A flat quadrilateral whose area centroid differs from its vertex average.
  const HalfEdgeMesh quad = test::make_flat_polygon({{0, 0, 0}, {4, 0, 0}, {4, 1, 0}, {0, 3, 0}});
  p = mass_properties(quad);
  EXPECT_EQ(p.status, MassStatus::flat);
  // Trapezoid = rectangle 4x1 (centroid (2, 0.5), area 4) + triangle (0,1),
  // (4,1), (0,3) (centroid (4/3, 5/3), area 4).
  EXPECT_LT((p.centroid - Vector3d((2 + 4.0 / 3) / 2, (0.5 + 5.0 / 3) / 2, 0)).norm(), 1e-15);

  p = mass_properties(test::make_vertices_only({{1, 2, 3}, {3, 2, 1}}, 1e-12));
  EXPECT_EQ(p.status, MassStatus::flat);
  EXPECT_EQ(p.centroid, Vector3d(2, 2, 2));
  EXPECT_EQ(p.surface_area, 0.0);
  p = mass_properties(test::make_vertices_only({{1, 2, 3}}, 1e-12));
  EXPECT_EQ(p.centroid, Vector3d(1, 2, 3));
}

TEST(Mass, InvalidInputGivesZerosNotNaN) {
  MassProperties p = mass_properties(HalfEdgeMesh());
  EXPECT_EQ(p.status, MassStatus::invalid_input);
  EXPECT_EQ(p.centroid, Vector3d::Zero());
  p = mass_properties(test::unit_cube(), std::nan(""));
  EXPECT_EQ(p.status, MassStatus::invalid_input);
  EXPECT_EQ(p.volume, 0.0);
  p = mass_properties(test::unit_cube(), -1.0);
  EXPECT_EQ(p.status, MassStatus::invalid_input);
  HalfEdgeMesh nan = test::unit_cube();
  nan.vertices[2].position.y() = std::numeric_limits<double>::infinity();
  p = mass_properties(nan);
  EXPECT_EQ(p.status, MassStatus::invalid_input);
  EXPECT_TRUE(p.inertia.allFinite());
  EXPECT_TRUE(p.centroid.allFinite());
  // Coordinates whose cubes overflow: reported, not inf or NaN.
  p = mass_properties(test::make_box(Vector3d::Constant(-1e120), Vector3d::Constant(1e120)));
  EXPECT_EQ(p.status, MassStatus::invalid_input);
  EXPECT_TRUE(p.inertia.allFinite());
  EXPECT_EQ(p.volume, 0.0);
  // Zero density is valid: geometry without mass.
  p = mass_properties(test::unit_cube(), 0.0);
  EXPECT_EQ(p.status, MassStatus::ok);
  EXPECT_EQ(p.mass, 0.0);
  EXPECT_EQ(p.volume, 1.0);
}

}  // namespace
}  // namespace hedra::hull
