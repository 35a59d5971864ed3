// EPA on its own (epa.hpp), with hand-made start simplices and support
// types whose Minkowski difference D is known exactly:
//   * every shape of start GJK can hand over: a point, a segment through the
//     origin, a triangle with the origin inside or on an edge, a tetrahedron
//     with the origin on a face, a flat tetrahedron, repeated points;
//   * flat differences (a square, a segment, a point): depth 0, the right
//     dimension, the normal oriented toward `preferred`;
//   * the origin a hair outside D (touching from outside): signed depth;
//   * statuses: max_iterations, polytope_full, degenerate, with finite
//     outputs, a unit normal and an honest error bound in every case;
//   * the polytope's invariants after many expansions: closed two-manifold
//     (mutual adjacency, V - E + F = 2), convex, every face plane unit;
//   * scale: the same problem at 1e-3 and 1e3.
// Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/detail/epa.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <limits>
#include <random>
#include <vector>

namespace hedra::collision {
namespace {

using Vec = Eigen::Vector3d;

// B reduced to one point: D = A - {b}, A shifted by -b.
struct FixedPoint {
  Vec p = Vec::Zero();
  Vec support(const Vec&) const { return p; }
};

// A ball of radius r around c: curved everywhere, EPA never terminates
// exactly on it.
struct Ball {
  Vec c = Vec::Zero();
  double r = 1.0;
  Vec support(const Vec& d) const { return c + r * d.normalized(); }
};

// A support mapping that fails (a corrupt shape).
struct NanSupport {
  Vec support(const Vec&) const { return Vec::Constant(std::nan("")); }
};

// A simplex of D = A - {b} from points a_i of A.
GjkSimplex simplex_of(const std::vector<Vec>& a_points, const Vec& b) {
  GjkSimplex s;
  s.size = static_cast<int>(a_points.size());
  for (int i = 0; i < s.size; ++i) {
    s.a[i] = a_points[i];
    s.b[i] = b;
    s.w[i] = a_points[i] - b;
    s.lambda[i] = 1.0 / s.size;
  }
  return s;
}

double angle(const Vec& u, const Vec& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

void expect_valid(const EpaResult& r, double tol) {
  ASSERT_TRUE(std::isfinite(r.depth) && r.normal.allFinite() && r.point_a.allFinite() && r.point_b.allFinite());
  EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12);
  EXPECT_LT((r.point_a - r.point_b - r.depth * r.normal).norm(), tol);
  EXPECT_GE(r.error_bound, 0.0);
}

// The box [-1,1] x [-2,2] x [-3,3] minus the point (0.3, 0, 0): D is the box
// shifted by -0.3 along x; the nearest face is +x at 0.7.
class BoxMinusPoint : public ::testing::Test {
 protected:
  BoxCore box{{1.0, 2.0, 3.0}};
  FixedPoint b{{0.3, 0.0, 0.0}};
  void expect_answer(const GjkSimplex& s, const char* what) {
    const EpaResult r = epa_penetration(box, b, s, box.bounding_radius(), b.p);
    SCOPED_TRACE(what);
    EXPECT_EQ(r.status, EpaStatus::ok);
    expect_valid(r, 1e-14);
    EXPECT_EQ(r.dimension, 3);
    EXPECT_NEAR(r.depth, 0.7, 1e-14);
    EXPECT_LT(angle(r.normal, Vec::UnitX()), 1e-14);
    EXPECT_NEAR(r.point_a.x(), 1.0, 1e-14);  // on A's +x face
    EXPECT_LE(r.error_bound, 1e-14);
    EXPECT_GT(r.iterations, 0);
  }
};

TEST_F(BoxMinusPoint, FromAPointAtTheOrigin) {
  // w = 0: the point of A at b (inside A; not a support point).
  expect_answer(simplex_of({b.p}, b.p), "point");
}

TEST_F(BoxMinusPoint, FromASegmentThroughTheOrigin) {
  expect_answer(simplex_of({b.p + Vec(0.5, 1.0, 1.0), b.p - Vec(0.5, 1.0, 1.0)}, b.p), "segment");
}

TEST_F(BoxMinusPoint, FromTrianglesWithTheOriginInsideOrOnAnEdge) {
  expect_answer(simplex_of({b.p + Vec(0.6, 0, 0), b.p + Vec(-0.5, 1, 0), b.p + Vec(-0.5, -1, 0)}, b.p), "inside");
  expect_answer(simplex_of({b.p + Vec(0.6, 1, 1), b.p - Vec(0.6, 1, 1), b.p + Vec(0.2, -1.5, 2)}, b.p), "edge");
}

TEST_F(BoxMinusPoint, FromATetrahedronWithTheOriginOnAFace) {  // mujoco_warp#1526
  const std::vector<Vec> tet = {b.p + Vec(0.6, 0, 0), b.p + Vec(-0.5, 1, 0), b.p + Vec(-0.5, -1, 0),
                                b.p + Vec(0.1, 0.2, 2.5)};
  expect_answer(simplex_of(tet, b.p), "on a face");
  // Both orientations of the same tetrahedron.
  expect_answer(simplex_of({tet[1], tet[0], tet[2], tet[3]}, b.p), "swapped");
  // Strictly inside, the ordinary case.
  expect_answer(
      simplex_of({b.p + Vec(0.6, 0, -1), b.p + Vec(-0.5, 1, -1), b.p + Vec(-0.5, -1, -1), b.p + Vec(0.0, 0.0, 2.5)},
                 b.p),
      "inside");
}

TEST_F(BoxMinusPoint, FromAFlatTetrahedronOrRepeatedPoints) {
  // Four points within 1e-15 of the plane z = 0, the origin between them.
  expect_answer(simplex_of({b.p + Vec(0.6, 0.5, 1e-15), b.p + Vec(-0.5, 1, 0), b.p + Vec(-0.5, -1, -1e-15),
                            b.p + Vec(0.6, -0.5, 0)},
                           b.p),
                "flat");
  // A repeated first point (fcl#395, PhysX#509) and a fully repeated simplex.
  expect_answer(simplex_of({b.p + Vec(0.6, 0, 0), b.p + Vec(0.6, 0, 0), b.p + Vec(-0.5, 1, 0)}, b.p), "repeated");
  expect_answer(simplex_of({b.p, b.p, b.p, b.p}, b.p), "all equal");
  // Collinear triangle through the origin.
  expect_answer(simplex_of({b.p + Vec(0.5, 0.5, 0.5), b.p - Vec(0.5, 0.5, 0.5), b.p + Vec(0.25, 0.25, 0.25)}, b.p),
                "collinear");
}

TEST(Epa, FlatDifferencesHaveDepthZeroAndAnOrientedNormal) {
  const FixedPoint at_origin;
  // A square in z = 0 (the simplex: A's point at the origin, inside D): D is
  // flat; its normal, oriented toward `preferred`.
  const BoxCore square{{1.0, 2.0, 0.0}};
  for (const Vec& preferred : {Vec(0.1, 0.2, 1.0), Vec(0.1, 0.2, -1.0)}) {
    const EpaResult r = epa_penetration(square, at_origin, simplex_of({Vec::Zero()}, Vec::Zero()), 2.0, preferred);
    EXPECT_EQ(r.status, EpaStatus::ok);
    expect_valid(r, 1e-15);
    EXPECT_EQ(r.dimension, 2);
    EXPECT_EQ(r.depth, 0.0);
    EXPECT_LT(angle(r.normal, preferred.z() > 0 ? Vec(Vec::UnitZ()) : Vec(-Vec::UnitZ())), 1e-15);
  }
  // A segment along x: any perpendicular, the one nearest `preferred`.
  const BoxCore segment{{1.0, 0.0, 0.0}};
  const EpaResult s =
      epa_penetration(segment, at_origin, simplex_of({Vec::Zero()}, Vec::Zero()), 1.0, Vec(0.7, 0.0, 1.0));
  EXPECT_EQ(s.dimension, 1);
  expect_valid(s, 1e-15);
  EXPECT_EQ(s.depth, 0.0);
  EXPECT_LT(angle(s.normal, Vec::UnitZ()), 1e-15);
  // A point: the normal is `preferred`, or +x without one.
  const BoxCore point{{0.0, 0.0, 0.0}};
  const EpaResult p = epa_penetration(point, at_origin, simplex_of({Vec::Zero()}, Vec::Zero()), 0.0, Vec::Zero());
  EXPECT_EQ(p.dimension, 0);
  expect_valid(p, 1e-15);
  EXPECT_EQ(p.normal, Vec::UnitX());
}

TEST(Epa, OriginAHairOutsideGivesANegativeSignedDepth) {
  // D = the box shifted so that its +x face is 1e-13 short of the origin.
  const BoxCore box{{1.0, 2.0, 3.0}};
  for (double outside : {1e-13, 1e-15, 0.0}) {
    const FixedPoint b{{1.0 + outside, 0.0, 0.0}};
    // GJK's simplex: a triangle of D's +x face around the origin's projection.
    const GjkSimplex s = simplex_of({Vec(1.0, 1.0, 0.0), Vec(1.0, -1.0, 1.0), Vec(1.0, -1.0, -1.0)}, b.p);
    const EpaResult r = epa_penetration(box, b, s, box.bounding_radius(), b.p);
    const double gap = b.p.x() - 1.0;  // exact: what 1 + outside rounded to
    EXPECT_EQ(r.status, EpaStatus::ok);
    expect_valid(r, 1e-15);
    EXPECT_NEAR(r.depth, -gap, 1e-17);
    EXPECT_LT(angle(r.normal, Vec::UnitX()), 1e-15);
    EXPECT_LE(std::abs(r.depth + gap), r.error_bound + 1e-17);
  }
}

TEST(Epa, CurvedDifferenceConvergesWithAnHonestBound) {
  // D = ball(c, R) - {b} = ball(c - b, R): depth R - |c - b| along (b - c).
  // A doubly curved D is EPA's slow case (about 12 iterations per decade of
  // tolerance: the faces shrink around the answer one ring at a time), and
  // a deep one (origin near the centre) needs the whole sphere refined: the
  // query layer never sends balls here (spheres are point cores), so the
  // test keeps to shallow contacts, |c - b| in [0.5, 0.95].
  std::mt19937_64 rng(201);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> offset(0.5, 0.95);
  for (int i = 0; i < 100; ++i) {
    const Vec centre = offset(rng) * Vec(g(rng), g(rng), g(rng)).normalized();
    const FixedPoint b{0.2 * Vec(g(rng), g(rng), g(rng))};
    const Ball ball{centre + b.p, 1.0};
    // A start tetrahedron of support points around the origin.
    std::vector<Vec> a;
    for (const Vec& d : {Vec(1, 1, 1), Vec(1, -1, -1), Vec(-1, 1, -1), Vec(-1, -1, 1)}) a.push_back(ball.support(d));
    const double expected = 1.0 - centre.norm();
    for (double tol : {1e-4, 1e-8}) {
      EpaSettings settings;
      settings.absolute_tolerance = settings.relative_tolerance = tol;
      const EpaResult r = epa_penetration(ball, b, simplex_of(a, b.p), 1.0, b.p, settings);
      ASSERT_EQ(r.status, EpaStatus::ok) << i;
      expect_valid(r, 1e-14);
      // The lower bound: EPA's depth never exceeds the truth; within tol.
      EXPECT_LE(r.depth, expected + 1e-15);
      EXPECT_LE(expected - r.depth, r.error_bound + 1e-15) << i;
      EXPECT_LE(r.error_bound, 2.0 * tol);
      EXPECT_LT(angle(r.normal, -centre), 4.0 * std::sqrt(tol)) << i;
    }
  }
}

TEST(Epa, StatusesKeepOutputsFiniteAndHonest) {
  // A deep ball (the origin 0.1 off its centre): EPA's worst case, every
  // direction nearly as deep as the answer.
  const Ball ball{Vec(0.1, 0.0, 0.0), 1.0};
  const FixedPoint b;
  std::vector<Vec> a;
  for (const Vec& d : {Vec(1, 1, 1), Vec(1, -1, -1), Vec(-1, 1, -1), Vec(-1, -1, 1)}) a.push_back(ball.support(d));
  const GjkSimplex start = simplex_of(a, b.p);
  const double expected = 0.9;

  EpaSettings capped;
  capped.max_iterations = 3;
  const EpaResult r1 = epa_penetration(ball, b, start, 1.0, b.p, capped);
  EXPECT_EQ(r1.status, EpaStatus::max_iterations);
  EXPECT_EQ(r1.iterations, 3);
  expect_valid(r1, 1e-14);
  EXPECT_LE(std::abs(expected - r1.depth), r1.error_bound + 1e-15);
  EXPECT_GT(r1.error_bound, 1e-3);
  // Not converged: the answer is the best support direction, a translation
  // of B that certainly separates (depth >= the true depth).
  EXPECT_GE(r1.depth, expected - 1e-15);

  // Zero tolerance on a ball: the polytope fills up before converging.
  EpaSettings exact;
  exact.absolute_tolerance = exact.relative_tolerance = 0.0;
  exact.max_iterations = 10000;
  const EpaResult r2 = epa_penetration(ball, b, start, 1.0, b.p, exact);
  EXPECT_EQ(r2.status, EpaStatus::polytope_full);
  EXPECT_LT(r2.iterations, 10000);
  expect_valid(r2, 1e-14);
  EXPECT_LE(std::abs(expected - r2.depth), r2.error_bound + 1e-15);
  EXPECT_LT(r2.error_bound, 1e-3);  // it did make progress
  EXPECT_GE(r2.depth, expected - 1e-15);
  // The support direction is far more accurate here than the bound says:
  // the deep ball's depth is nearly flat around the answer.
  EXPECT_LT(r2.depth - expected, 1e-5);

  // A support mapping returning NaN: degenerate, nothing non-finite leaks.
  const NanSupport bad;
  const EpaResult r3 = epa_penetration(bad, b, start, 1.0, b.p);
  EXPECT_EQ(r3.status, EpaStatus::degenerate);
  expect_valid(r3, 1e300);
  EpaSettings loose;
  loose.absolute_tolerance = 1e-2;
  const EpaResult r4 = epa_penetration(ball, b, start, 1.0, b.p, loose);
  EXPECT_EQ(r4.status, EpaStatus::ok);  // the same start converges when it can
  EXPECT_LE(expected - r4.depth, r4.error_bound + 1e-15);
  // An empty simplex (GJK failed before starting).
  GjkSimplex empty;
  const EpaResult r5 = epa_penetration(ball, b, empty, 1.0, b.p);
  EXPECT_EQ(r5.status, EpaStatus::degenerate);
  expect_valid(r5, 1e300);
  // A NaN scale counts as zero: still finite.
  const EpaResult r6 = epa_penetration(ball, b, start, std::nan(""), b.p);
  expect_valid(r6, 1e-14);
}

TEST(Epa, PolytopeStaysAClosedConvexTwoManifold) {
  std::mt19937_64 rng(202);
  std::normal_distribution<double> g(0.0, 1.0);
  epa_detail::Polytope poly;
  const std::array<Vec, 4> tet = {Vec(1, 1, 1), Vec(1, -1, -1), Vec(-1, 1, -1), Vec(-1, -1, 1)};
  for (int i = 0; i < 4; ++i) poly.vertex[i] = {tet[i], tet[i], Vec::Zero()};
  // Positive orientation as epa_penetration arranges it.
  if ((tet[1] - tet[0]).dot((tet[2] - tet[0]).cross(tet[3] - tet[0])) < 0.0) std::swap(poly.vertex[1], poly.vertex[2]);
  poly.vertex_count = 4;
  ASSERT_TRUE(poly.init_tetrahedron());
  int stamp = 0, added = 0;
  for (int k = 0; k < 500 && poly.vertex_count < kEpaMaxVertices; ++k) {
    // A point on the sphere of radius 2 (outside the current polytope, in
    // convex position with every earlier point); the face it sees best.
    const Vec w = 2.0 * Vec(g(rng), g(rng), g(rng)).normalized();
    int start = -1;
    double best = 0.0;
    for (int f = 0; f < poly.face_end; ++f)
      if (poly.face[f].live && poly.face[f].n.dot(w) - poly.face[f].d > best) {
        best = poly.face[f].n.dot(w) - poly.face[f].d;
        start = f;
      }
    if (start < 0) continue;
    const auto result = poly.expand(start, {w, w, Vec::Zero()}, 1e-13, ++stamp);
    ASSERT_NE(result, epa_detail::Polytope::Expansion::invalid) << k;
    if (result == epa_detail::Polytope::Expansion::full) break;
    ++added;
    // Invariants: mutual adjacency with matching edges, unit normals,
    // convexity (every used vertex behind every plane), Euler.
    int live = 0;
    std::vector<bool> used(poly.vertex_count, false);
    for (int f = 0; f < poly.face_end; ++f) {
      const epa_detail::Face& face = poly.face[f];
      if (!face.live) continue;
      ++live;
      EXPECT_NEAR(face.n.norm(), 1.0, 1e-14);
      for (int e = 0; e < 3; ++e) {
        used[face.v[e]] = true;
        const epa_detail::Face& other = poly.face[face.adj[e]];
        ASSERT_TRUE(other.live);
        const int j = face.adj_edge[e];
        EXPECT_EQ(other.adj[j], f);
        EXPECT_EQ(other.v[j], face.v[(e + 1) % 3]);
        EXPECT_EQ(other.v[(j + 1) % 3], face.v[e]);
      }
    }
    int vertices = 0;
    for (int v = 0; v < poly.vertex_count; ++v) {
      if (!used[v]) continue;
      ++vertices;
      for (int f = 0; f < poly.face_end; ++f) {
        if (poly.face[f].live) {
          EXPECT_LE(poly.face[f].n.dot(poly.vertex[v].w) - poly.face[f].d, 1e-12);
        }
      }
    }
    EXPECT_EQ(vertices - 3 * live / 2 + live, 2);  // V - E + F with E = 3F/2
  }
  EXPECT_GT(added, 100);
}

TEST(Epa, SameProblemAtAnyScale) {
  for (double s : {1e-3, 1.0, 1e3}) {
    const BoxCore box{Vec(1.0, 2.0, 3.0) * s};
    const FixedPoint b{Vec(0.3, -0.1, 0.2) * s};
    const GjkSimplex start = simplex_of(
        {b.p + Vec(0.6, 0, 0) * s, b.p + Vec(-0.5, 1, 0) * s, b.p + Vec(-0.5, -1, 0) * s, b.p + Vec(0.0, 0.0, 2.5) * s},
        b.p);
    const EpaResult r = epa_penetration(box, b, start, box.bounding_radius(), b.p);
    EXPECT_EQ(r.status, EpaStatus::ok);
    expect_valid(r, 1e-14 * s);
    EXPECT_NEAR(r.depth, 0.7 * s, 1e-14 * s);
    EXPECT_LT(angle(r.normal, Vec::UnitX()), 1e-14);
  }
}

}  // namespace
}  // namespace hedra::collision
