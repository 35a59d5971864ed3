// Support mappings: exactness of the polyhedron hill-climb against brute
// force (random hulls x directions x start vertices, plateaus included:
// boxes, prisms and face-normal directions whose maximisers are whole faces),
// the analytic shapes against dense samples of their surfaces, the
// ConvexPolyhedron builder (recentring, adjacency) and shape validation.
//
// "Exact" means: the climbed vertex's support value equals the brute-force
// maximum up to the rounding of one dot product, 4 eps |d| R with R the hull's
// bounding radius (ties between vertices whose values differ only by rounding
// cannot be decided otherwise). A wrong local maximum misses by a face's
// worth, many orders above that.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/detail/support.hpp>
#include <limits>
#include <random>
#include <vector>

namespace hedra::collision {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

std::shared_ptr<const ConvexPolyhedron> make_hull(const std::vector<Eigen::Vector3d>& points) {
  ConvexPolyhedron::BuildResult built = ConvexPolyhedron::build(points);
  EXPECT_TRUE(built.ok()) << built.message;
  return built.polyhedron;
}

Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Vector3d d(g(rng), g(rng), g(rng));
  return d.normalized();
}

std::vector<Eigen::Vector3d> random_ball_points(std::mt19937_64& rng, int n, bool on_sphere) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i) {
    const double r = on_sphere ? 1.0 : std::cbrt(u(rng));
    p.push_back(r * random_unit(rng));
  }
  return p;
}

// A right prism over a regular n-gon: two n-gon faces and n rectangles, every
// one a plateau for its normal.
std::vector<Eigen::Vector3d> prism(int n, double radius, double half_height) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    p.emplace_back(radius * std::cos(a), radius * std::sin(a), -half_height);
    p.emplace_back(radius * std::cos(a), radius * std::sin(a), half_height);
  }
  return p;
}

// A box sampled with a grid on every face: many coplanar points, 8 vertices.
std::vector<Eigen::Vector3d> gridded_box(const Eigen::Vector3d& h, int k) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j <= k; ++j)
      for (int l = 0; l <= k; ++l) {
        if (i != 0 && i != k && j != 0 && j != k && l != 0 && l != k) continue;
        p.emplace_back(h.x() * (2.0 * i / k - 1.0), h.y() * (2.0 * j / k - 1.0), h.z() * (2.0 * l / k - 1.0));
      }
  return p;
}

struct ClimbStats {
  long checks = 0;
  long exact = 0;  // bit-identical support value
  double worst = 0.0;
};

// Every direction from every given start: climb vs brute force.
void check_climb(const ConvexPolyhedron& poly, const std::vector<Eigen::Vector3d>& directions,
                 const std::vector<hull::Index>& starts, ClimbStats& stats) {
  for (const Eigen::Vector3d& d : directions) {
    double brute = -std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& v : poly.vertices()) brute = std::max(brute, d.dot(v));
    const hull::Index scanned = polyhedron_support_scan(poly, d);
    ASSERT_EQ(d.dot(poly.vertex(scanned)), brute);
    // The hull is convex to within its own tolerance (nearly coplanar faces
    // left unmerged can form a plateau tilted by up to it), so the climb is
    // exact to that, or to the rounding of the dot products if larger.
    const double tolerance = std::max(4.0 * kEps * poly.bounding_radius(), poly.mesh().tolerance()) * d.norm();
    for (hull::Index s : starts) {
      const hull::Index climbed = polyhedron_support_climb(poly, d, s);
      ASSERT_LT(climbed, poly.vertex_count());
      const double value = d.dot(poly.vertex(climbed));
      const double miss = brute - value;
      ++stats.checks;
      if (miss == 0.0) ++stats.exact;
      stats.worst = std::max(stats.worst, miss / std::max(tolerance, 1e-300));
      ASSERT_LE(miss, tolerance) << "start " << s << " direction " << d.transpose() << " vertices "
                                 << poly.vertex_count();
    }
  }
}

std::vector<Eigen::Vector3d> directions_for(const ConvexPolyhedron& poly, std::mt19937_64& rng, int random_count) {
  std::vector<Eigen::Vector3d> dirs;
  for (int i = 0; i < random_count; ++i) dirs.push_back(random_unit(rng));
  // Plateaus: face normals (whole faces tie), axes (edges of boxes tie).
  for (const hull::Face& f : poly.mesh().faces) dirs.push_back(f.plane.normal);
  for (int a = 0; a < 3; ++a) {
    dirs.push_back(Eigen::Vector3d::Unit(a));
    dirs.push_back(-Eigen::Vector3d::Unit(a));
  }
  return dirs;
}

std::vector<hull::Index> starts_for(const ConvexPolyhedron& poly, std::mt19937_64& rng, int count) {
  std::uniform_int_distribution<hull::Index> pick(0, static_cast<hull::Index>(poly.vertex_count() - 1));
  std::vector<hull::Index> s = {0, static_cast<hull::Index>(poly.vertex_count() - 1)};
  for (int i = 0; i < count; ++i) s.push_back(pick(rng));
  return s;
}

TEST(PolyhedronSupport, ClimbMatchesBruteForceOnRandomHulls) {
  std::mt19937_64 rng(20240531);
  std::uniform_int_distribution<int> size(4, 200);
  ClimbStats stats;
  for (int trial = 0; trial < 1000; ++trial) {
    const auto poly = make_hull(random_ball_points(rng, size(rng), trial % 2 == 0));
    ASSERT_TRUE(poly);
    ASSERT_EQ(poly->dimension(), 3);
    check_climb(*poly, directions_for(*poly, rng, 20), starts_for(*poly, rng, 6), stats);
  }
  EXPECT_GT(stats.checks, 50000);
  // Almost every answer is bit-exact; the rest are rounding-level ties.
  EXPECT_GT(stats.exact, stats.checks * 99 / 100);
}

// The climb over whole neighbour rows, steepest ascent, first maximum in
// row order: what polyhedron_support_climb must return, ties included, now
// that it leaves out the part of a row its last step has already compared.
hull::Index climb_over_whole_rows(const ConvexPolyhedron& poly, const Eigen::Vector3d& d, hull::Index current) {
  double current_value = dot3(d, poly.vertex(current));
  for (std::size_t step = 0; step < poly.vertex_count(); ++step) {
    hull::Index best = current;
    double best_value = current_value;
    for (const hull::Index* it = poly.neighbors_begin(current); it != poly.neighbors_end(current); ++it) {
      const double value = dot3(d, poly.vertex(*it));
      if (value > best_value) {
        best_value = value;
        best = *it;
      }
    }
    if (best == current) return current;
    current = best;
    current_value = best_value;
  }
  return current;
}

// Every edge slot u -> w: the two ranges lie in w's row, in order, and what
// they leave out of it is u and neighbours of u only, u always; on a hull of
// triangles (random points) at least u and the two apexes of the edge (a
// third common neighbour next to them goes too).
void check_entry_rows(const ConvexPolyhedron& poly, bool triangulated) {
  for (hull::Index u = 0; u < poly.vertex_count(); ++u) {
    for (const hull::Index* slot = poly.neighbors_begin(u); slot != poly.neighbors_end(u); ++slot) {
      const hull::Index w = *slot;
      const ConvexPolyhedron::EntryRows& e = poly.entry_rows(static_cast<std::size_t>(slot - poly.neighbors()));
      const std::uint32_t begin = poly.neighbor_offset(w), end = poly.neighbor_offset(w + 1);
      ASSERT_LE(begin, e.first_begin);
      ASSERT_LE(e.first_begin, e.first_end);
      ASSERT_LE(e.first_end, e.second_begin);
      ASSERT_LE(e.second_begin, end);
      std::size_t left_out = 0;
      bool u_left_out = false;
      for (std::uint32_t q = begin; q < end; ++q) {
        if ((q >= e.first_begin && q < e.first_end) || q >= e.second_begin) continue;
        const hull::Index x = poly.neighbors()[q];
        ++left_out;
        u_left_out = u_left_out || x == u;
        ASSERT_TRUE(x == u || std::find(poly.neighbors_begin(u), poly.neighbors_end(u), x) != poly.neighbors_end(u))
            << "slot " << u << " -> " << w << " leaves out " << x;
      }
      ASSERT_TRUE(u_left_out);
      if (triangulated && end - begin > 3) {
        EXPECT_GE(left_out, 3u);
      }
    }
  }
}

TEST(PolyhedronSupport, ClimbLeavesOutOnlyWhatItsLastStepCompared) {
  std::mt19937_64 rng(20261126);
  std::uniform_int_distribution<int> size(4, 150);
  std::vector<std::vector<Eigen::Vector3d>> inputs = {gridded_box({1.0, 2.0, 3.0}, 6)};
  for (int n : {3, 4, 5, 8, 17, 64}) inputs.push_back(prism(n, 1.0, n % 2 ? 0.01 : 5.0));
  const std::size_t shaped = inputs.size();
  for (int trial = 0; trial < 300; ++trial) inputs.push_back(random_ball_points(rng, size(rng), trial % 2 == 0));
  long checks = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const auto poly = make_hull(inputs[i]);
    ASSERT_TRUE(poly);
    check_entry_rows(*poly, i >= shaped);
    for (const Eigen::Vector3d& d : directions_for(*poly, rng, 20)) {
      for (hull::Index s : starts_for(*poly, rng, 4)) {
        ASSERT_EQ(polyhedron_support_climb(*poly, d, s), climb_over_whole_rows(*poly, d, s))
            << "start " << s << " direction " << d.transpose() << " vertices " << poly->vertex_count();
        ++checks;
      }
    }
  }
  EXPECT_GT(checks, 20000);
}

TEST(PolyhedronSupport, ClimbIsExactOnPlateaus) {
  std::mt19937_64 rng(7);
  ClimbStats stats;
  std::vector<std::vector<Eigen::Vector3d>> inputs = {gridded_box({1.0, 2.0, 3.0}, 6),
                                                      gridded_box({1e-3, 1e3, 1.0}, 3)};
  for (int n : {3, 4, 5, 8, 17, 64}) inputs.push_back(prism(n, 1.0, n % 2 ? 0.01 : 5.0));
  for (const auto& points : inputs) {
    const auto poly = make_hull(points);
    ASSERT_TRUE(poly);
    // Rotated copies too: the ties then differ by rounding only.
    check_climb(*poly, directions_for(*poly, rng, 200), starts_for(*poly, rng, 8), stats);
    const Eigen::Matrix3d r = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    std::vector<Eigen::Vector3d> rotated;
    for (const auto& p : points) rotated.push_back(r * p);
    const auto rotated_poly = make_hull(rotated);
    check_climb(*rotated_poly, directions_for(*rotated_poly, rng, 200), starts_for(*rotated_poly, rng, 8), stats);
  }
  const auto box = make_hull(gridded_box({1.0, 2.0, 3.0}, 6));
  EXPECT_EQ(box->vertex_count(), 8u);  // coplanar grid points merged away
  EXPECT_GT(stats.checks, 10000);
}

TEST(PolyhedronSupport, ClimbOnFlatHulls) {
  std::mt19937_64 rng(11);
  ClimbStats stats;
  for (int trial = 0; trial < 50; ++trial) {
    // Random points in a tilted plane: a flat polygon with two faces.
    const Eigen::Vector3d e1 = random_unit(rng);
    const Eigen::Vector3d e2 = e1.unitOrthogonal();
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 200; ++i) points.push_back(u(rng) * e1 + u(rng) * e2);
    const auto poly = make_hull(points);
    ASSERT_EQ(poly->dimension(), 2);
    std::vector<Eigen::Vector3d> dirs = directions_for(*poly, rng, 40);
    dirs.push_back(e1.cross(e2));  // the whole polygon ties
    check_climb(*poly, dirs, starts_for(*poly, rng, 4), stats);
  }
  EXPECT_GT(stats.checks, 5000);
}

TEST(PolyhedronSupport, DispatchAndHintOnLargeHull) {
  std::mt19937_64 rng(3);
  const auto poly = make_hull(random_ball_points(rng, 20000, true));
  ASSERT_GT(poly->vertex_count(), hill_climb_crossover());
  // Directions rotating slowly, the hint carried along as a cache would.
  PolyhedronCore core{poly.get(), 0};
  Eigen::Vector3d d = random_unit(rng);
  const Eigen::Matrix3d step = Eigen::AngleAxisd(0.05, random_unit(rng)).toRotationMatrix();
  for (int i = 0; i < 500; ++i) {
    d = step * d;
    const Eigen::Vector3d s = core.support(d);
    EXPECT_EQ(d.dot(s), d.dot(poly->vertex(polyhedron_support_scan(*poly, d))));
  }
}

// Large solid hulls keep extreme vertices of a few fixed directions; a climb
// without a hint starts from the best of them, one with a hint from the
// better of the two. Either way it must end on a maximiser.
TEST(PolyhedronSupport, ClimbFromStartVerticesOnLargeHulls) {
  std::mt19937_64 rng(31);
  const auto poly = make_hull(random_ball_points(rng, 3000, true));
  ASSERT_GE(poly->vertex_count(), ConvexPolyhedron::kStartMinVertices);
  ASSERT_EQ(poly->start_blocks().size(), ConvexPolyhedron::kStartDirections / 4);
  const auto small = make_hull(random_ball_points(rng, 100, true));
  EXPECT_TRUE(small->start_blocks().empty());
  std::vector<hull::Index> starts = {hull::kInvalidIndex, 0, 1};
  ClimbStats stats;
  check_climb(*poly, directions_for(*poly, rng, 300), starts, stats);
  EXPECT_EQ(stats.exact, stats.checks);
}

// The vectorised scans (SSE2, and AVX2 where the processor has it) walk the
// vertices in four lanes and padded blocks: each must give the serial scan's
// index (the first maximiser) bit for bit,
// ties, a zero direction, infinities and NaN included, for every count
// modulo 4 (padding).
TEST(PolyhedronSupport, BlockScanIsTheFirstMaximiserLikeTheSerialScan) {
  std::mt19937_64 rng(29);
  std::vector<std::vector<Eigen::Vector3d>> inputs = {gridded_box({1.0, 2.0, 3.0}, 2), {Eigen::Vector3d(1, 2, 3)}};
  inputs.push_back({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)});
  for (int n : {3, 4, 5, 6, 7, 8, 9, 17, 64}) inputs.push_back(prism(n, 1.0, 0.5));
  for (int n : {4, 5, 6, 7, 30, 31, 33, 100}) inputs.push_back(random_ball_points(rng, n, true));
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  long checks = 0;
  [[maybe_unused]] long avx2_checks = 0;
  for (const auto& points : inputs) {
    const auto poly = make_hull(points);
    ASSERT_TRUE(poly);
    ASSERT_EQ(poly->vertex_blocks().size(), (poly->vertex_count() + 3) / 4);
    std::vector<Eigen::Vector3d> dirs = directions_for(*poly, rng, 50);
    for (int a = 0; a < 3; ++a) {
      dirs.push_back(inf * Eigen::Vector3d::Unit(a));
      dirs.push_back(-inf * Eigen::Vector3d::Unit(a));
      dirs.push_back(nan * Eigen::Vector3d::Unit(a));
    }
    dirs.push_back(Eigen::Vector3d::Zero());
    dirs.push_back(Eigen::Vector3d(nan, nan, nan));
    dirs.push_back(Eigen::Vector3d(inf, -inf, 1.0));
    for (const Eigen::Vector3d& d : dirs) {
      const hull::Index serial = polyhedron_support_scan_serial(*poly, d);
      ASSERT_EQ(polyhedron_support_scan(*poly, d), serial)
          << "direction " << d.transpose() << " vertices " << poly->vertex_count();
      // Each vectorised variant on its own, whichever the dispatch picks.
      const double start = d.dot(poly->vertex(0));
      const auto& blocks = poly->vertex_blocks();
      const BlockBest sse2 = first_block_max_sse2(blocks.data(), blocks.size(), d, start);
      ASSERT_EQ(sse2.position < 0.0 ? 0 : static_cast<hull::Index>(sse2.position), serial) << d.transpose();
#if defined(HEDRA_AVX2_SCAN)
#  if defined(HEDRA_AVX2_DISPATCH)
      if (kProcessorHasAvx2)
#  endif
      {
        const BlockBest avx2 = first_block_max_avx2(blocks.data(), blocks.size(), d, start);
        ASSERT_EQ(avx2.position < 0.0 ? 0 : static_cast<hull::Index>(avx2.position), serial) << d.transpose();
        ++avx2_checks;
      }
#endif
      ++checks;
    }
  }
  EXPECT_GT(checks, 1000);
#if defined(HEDRA_AVX2_SCAN) && !defined(HEDRA_AVX2_DISPATCH)
  EXPECT_EQ(avx2_checks, checks);  // compiled for AVX2: always checked
#endif
}

TEST(ConvexPolyhedron, RecentredOnCentroidWithOffsetKept) {
  // A unit cube far from the origin: offset is its centre, vertices +-0.5.
  const Eigen::Vector3d far(1e6, -2e6, 3e6);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 8; ++i) points.push_back(far + Eigen::Vector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  points.push_back(far + Eigen::Vector3d(0.5, 0.5, 0.5));  // interior
  const auto poly = make_hull(points);
  ASSERT_EQ(poly->vertex_count(), 8u);
  EXPECT_LT((poly->offset() - (far + Eigen::Vector3d::Constant(0.5))).norm(), 1e-9);
  for (const Eigen::Vector3d& v : poly->vertices()) EXPECT_NEAR(v.cwiseAbs().maxCoeff(), 0.5, 1e-9);
  EXPECT_NEAR(poly->bounding_radius(), std::sqrt(0.75), 1e-9);
  EXPECT_TRUE(poly->mesh().validate().ok()) << poly->mesh().validate().to_string();
  // Each vertex has exactly 3 neighbours on a cube, each at distance 1.
  for (hull::Index v = 0; v < 8; ++v) {
    ASSERT_EQ(poly->neighbors_end(v) - poly->neighbors_begin(v), 3);
    for (const hull::Index* w = poly->neighbors_begin(v); w != poly->neighbors_end(v); ++w)
      EXPECT_NEAR((poly->vertex(*w) - poly->vertex(v)).norm(), 1.0, 1e-9);
  }
  // The full-shape support adds the offset back.
  const Polyhedron shape{poly, 0.0};
  EXPECT_LT((support(Shape(shape), Eigen::Vector3d(1, 1, 1)) - (far + Eigen::Vector3d::Ones())).norm(), 1e-9);
}

TEST(ConvexPolyhedron, DegenerateInputsAndErrors) {
  const auto point = make_hull({Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1, 2, 3)});
  EXPECT_EQ(point->dimension(), 0);
  EXPECT_EQ(point->offset(), Eigen::Vector3d(1, 2, 3));
  const auto segment = make_hull({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(1, 0, 0)});
  EXPECT_EQ(segment->dimension(), 1);
  EXPECT_EQ(segment->vertex_count(), 2u);
  EXPECT_NEAR(polyhedron_support(*segment, {-1, 0, 0}, 0) == 0 ? segment->vertex(0).x() : segment->vertex(1).x(), -1.0,
              1e-12);

  EXPECT_EQ(ConvexPolyhedron::build({}).error, ShapeError::empty_points);
  const auto nan = ConvexPolyhedron::build({Eigen::Vector3d(0, 0, std::nan(""))});
  EXPECT_EQ(nan.error, ShapeError::non_finite);
  EXPECT_FALSE(nan.polyhedron);
}

TEST(ShapeValidation, RejectsNegativeAndNonFinite) {
  EXPECT_TRUE(validate(Shape(Sphere{1.0, 0.0})).ok());
  EXPECT_TRUE(validate(Shape(Sphere{0.0, 0.0})).ok());  // a point is a valid sphere
  EXPECT_EQ(validate(Shape(Sphere{-1.0, 0.0})).error, ShapeError::negative_size);
  EXPECT_EQ(validate(Shape(Capsule{std::nan(""), 1.0, 0.0})).error, ShapeError::non_finite);
  EXPECT_EQ(validate(Shape(Box{{1.0, -2.0, 1.0}, 0.0})).error, ShapeError::negative_size);
  EXPECT_EQ(validate(Shape(Cylinder{1.0, 1.0, -0.1})).error, ShapeError::negative_margin);
  EXPECT_EQ(validate(Shape(Cone{1.0, INFINITY, 0.0})).error, ShapeError::non_finite);
  EXPECT_EQ(validate(Shape(Polyhedron{nullptr, 0.0})).error, ShapeError::null_polyhedron);
  EXPECT_NE(validate(Shape(Sphere{-1.0, 0.0})).message.find("-1"), std::string::npos);
}

// The queries' one-dispatch check: the same verdict as validate() and the
// same radius as bounding_radius(), valid or not.
TEST(ShapeValidation, CheckWithRadiusAgreesWithValidateAndBoundingRadius) {
  const auto hull = make_hull({{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}});
  const std::vector<Shape> shapes = {
      Sphere{1.0, 0.5},           Sphere{-1.0, 0.0},        Box{{1.0, 2.0, 3.0}, 0.1},
      Box{{1.0, -2.0, 1.0}, 0.0}, Capsule{0.5, 1.0, 0.0},   Capsule{std::nan(""), 1.0, 0.0},
      Cylinder{1.0, 2.0, 0.0},    Cylinder{1.0, 1.0, -0.1}, Cone{1.0, 2.0, 0.3},
      Cone{1.0, INFINITY, 0.0},   Polyhedron{hull, 0.25},   Polyhedron{nullptr, 0.0}};
  int valid = 0;
  for (const Shape& s : shapes) {
    double radius = -1.0;
    const bool ok = is_valid(s, radius);
    EXPECT_EQ(ok, validate(s).ok());
    EXPECT_EQ(ok, is_valid(s));
    const double expected = bounding_radius(s);
    EXPECT_TRUE(radius == expected || (std::isnan(radius) && std::isnan(expected)));
    valid += ok;
  }
  EXPECT_EQ(valid, 6);
}

// Analytic supports: the returned point lies on the shape and no sample of
// the surface beats it.
TEST(AnalyticSupport, NoSurfaceSampleBeatsTheSupport) {
  std::mt19937_64 rng(5);
  const double r = 0.7, h = 1.3, m = 0.2;
  const std::vector<Shape> shapes = {Sphere{r, m}, Box{{r, h, 0.4}, m}, Capsule{r, h, m}, Cylinder{r, h, m},
                                     Cone{r, h, m}};
  // Dense samples of each core's boundary; the margin adds m along d.
  auto core_samples = [&](const Shape& s) {
    std::vector<Eigen::Vector3d> p;
    const int k = 64;
    for (int i = 0; i < k; ++i) {
      const double a = 2.0 * M_PI * i / k;
      const Eigen::Vector3d rim(std::cos(a), std::sin(a), 0.0);
      for (int j = 0; j <= 4; ++j) {
        const double z = -1.0 + 0.5 * j;
        if (std::holds_alternative<Cylinder>(s)) p.push_back(r * rim + Eigen::Vector3d(0, 0, z * h));
        if (std::holds_alternative<Cone>(s)) p.push_back(0.5 * (1.0 - z) * r * rim + Eigen::Vector3d(0, 0, z * h));
      }
    }
    if (std::holds_alternative<Sphere>(s)) p.push_back(Eigen::Vector3d::Zero());
    if (std::holds_alternative<Capsule>(s)) p = {Eigen::Vector3d(0, 0, -h), Eigen::Vector3d(0, 0, h)};
    if (std::holds_alternative<Box>(s))
      for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? r : -r, i & 2 ? h : -h, i & 4 ? 0.4 : -0.4);
    return p;
  };
  for (const Shape& s : shapes) {
    const double radius = std::holds_alternative<Sphere>(s) || std::holds_alternative<Capsule>(s) ? r + m : m;
    const auto samples = core_samples(s);
    for (int i = 0; i < 2000; ++i) {
      Eigen::Vector3d d = random_unit(rng);
      if (i % 10 == 0) d = Eigen::Vector3d(0, 0, i % 20 == 0 ? 1.0 : -1.0);  // axis: plateaus
      const Eigen::Vector3d sp = support(s, d);
      double best = -INFINITY;
      for (const auto& q : samples) best = std::max(best, d.dot(q) + radius);
      EXPECT_GE(d.dot(sp), best - 1e-14) << s.index();
    }
  }
}

}  // namespace
}  // namespace hedra::collision
