// The exact reference for hedra::collision's queries: the signed distance
// between two posed shapes, computed independently of hedra's GJK and EPA
// (and of its support mappings) from the convex hull of the Minkowski
// difference of the shapes' cores, built by qhull.
//
// Every shape splits into a core point set and a radius:
//   sphere    its centre,                      radius + margin
//   capsule   the two segment end points,      radius + margin
//   box       its 8 corners,                   margin
//   hull      its vertices,                    margin
//   cylinder  2n rim points (two inscribed n-gons), margin
//   cone      the apex and an inscribed n-gon, margin
// The points go to world coordinates recentred on the pair's midpoint
// c = t_a + (t_b - t_a)/2 (t_b - t_a is exact for nearby bodies, so bodies at
// 1e6 lose nothing of their own size), and D = {a_i - b_j} is formed.
//
// Signed distance. For a convex set K and the origin,
//   sd(K) = max over unit n of (-h_K(n)),   h_K(n) = max_{x in K} n . x,
// the distance when the origin is outside, minus the depth inside; the
// maximiser n is the normal from A toward B. With D's hull and radii
// R = r_a + r_b: sd(A, B) = sd(D) - R (h of a set grown by a ball of radius
// R is h + R). From qhull's hull of D (facet planes n_f . x + o_f = 0,
// outward n_f):
//   origin outside (some o_f > 0): sd = min over facet triangles of the
//     distance to the triangle; normal = -v/|v| at the closest point v;
//   inside: sd = max_f o_f (the nearest facet plane); normal = that n_f.
// Witnesses: the closest point of D (its barycentric coordinates on a
// triangle of differences a_i - b_j) gives the points on the cores, then
// point_a += r_a n, point_b -= r_b n, so point_b - point_a = sd n.
//
// Lower dimensions. qhull needs a full-dimensional input; D is a point
// (sphere-sphere), a segment (sphere-capsule, parallel capsules) or flat
// (capsule-capsule, a flat hull against a sphere) in common cases. The
// affine dimension is measured first (farthest point from a point, a line, a
// plane); a thickness below 64 eps of D's size counts as flat and is added
// to the error bound; then the distance is computed in 0D/1D/2D directly
// (closest point on a segment, on a planar convex polygon). The origin never
// lies strictly inside a flat D: sd(D) >= 0 and the normal is not unique when
// the origin touches D.
//
// Curved shapes (cylinders, cones) are bracketed: the inscribed polygons make
// a subset of the true shape, so sd_inscribed >= sd_true (h is monotone in the
// set); and for any unit n, sd_true >= -h_true(n) - R with h_true the exact
// support function (closed forms written here). The bracket
// [max_k -h_true(n_k) - R, min_k sd_inscribed_k] starts from octagons and is
// refined by adding the exact support points of the cores for a 3x3 grid of
// directions around the current normal n_k (spacing pi/8, then 4 times
// smaller every pass, 2 times when the normal moved out of the grid). The points lie on the true surface, so the
// polygons stay inscribed; passes stop when the bracket is narrower than 1e-12 of the size, or after 16 passes
// (measured on the 425 scene queries: median 0.13 ms, 90th percentile 12 ms, at most 0.33 s for two separated curved
// shapes; widest bracket 2.7e-11 of the pair's size). `distance` is the
// bracket's midpoint and `error_bound` its half width (plus rounding). The
// normal of a curved pair is not certified (normal_unique is false).
//
// Self-check (polytope cores): the answer is compared with the certified
// lower bound -h_D(n) - R along its own normal n and along -v/|v| (v the
// closest point found); a disagreement beyond rounding is added to the
// error bound. qhull's facet planes on needles of aspect ~1e9 carry rounding
// far above its precision estimate (a needle 1.66e-6 from a segment came
// out 1.87e-6 +- 3e-11; 870 of 1000 random needles a hair from a point
// outside the claimed bound): such answers now come with a bound that holds,
// often a wide one (then the reference cannot judge closer than that).
//
// Cores of revolution (segments, cylinders, cones, points) whose axes are
// nearly parallel: the polygons' bracket is merged with the meridian one.
// With parallel axes D is a solid of revolution whose section is the convex
// hull of the sums of both sections (at most 16 points; the polygon by brute
// force over point pairs), and the signed distance is the 2D one of the
// origin's (radial, axial) position; axes theta apart move the core with
// the smaller bounding radius R by at most theta R, the bracket's half
// width. Nearly coaxial deep pairs, whose depth is almost the same over a
// circle of directions, had brackets up to 1.5e-2 wide from the polygons
// alone (they converge as the square of their angular resolution).
//
// Overlapping pairs of revolution whose meridian bracket is still wider
// than the target (tilted beyond theta R ~ 1e-12 of the size): cutting
// planes on the difference's own support points s_D(n) = s_A(n) - s_B(-n),
// which all lie in D. Their hull P (qhull) is inside D, so the origin's
// depth in P bounds the depth from below; every sampled n gives
// h_D(n) >= depth (closed forms) from above. From a Fibonacci sphere of 1 024
// directions and the axes, each pass adds the support point along the
// normal of every facet of P lying more than half the target below the best
// h_D(n) found (it cuts that facet off), until the bracket is within the
// target or P has max_support_points points. The polygons then stop after
// their first pass. Measured on tests/collision/exact_reference_test's 48
// nearly coaxial pairs: 1.3e-12 of the size wide at worst with the centres
// apart (2 000 to 5 000 points, 0.3 to 2 s); coincident centres leave a whole
// ring of depths within theta R, which inscribed hulls resolve only with
// about 1/sqrt(theta) points: 2.6e-6 of the size at theta = 4e-6 with 8 000
// (the meridian's 2 theta R is the tighter below about 1e-6).
//
// A curved core against a core of points (box, hull, segment): a
// bracket over the azimuth phi of the curved core's meridian planes, where
// h_D is the 2D support function of the section's points plus the other
// core's, projected; its minimum over the polar angle is exact (gift
// wrapping), and between azimuths every point moves at most L = max |q_perp|
// per radian (best first over intervals of phi, a budget of
// max_azimuth_evaluations). It resolves small pegs deep in a hole (a ring of nearly equal
// depths, brackets up to 1e-2 of the size wide from the polygons alone) to
// about 1e-12; merged with the polygons', which then stop after one pass.
//
// Uniqueness of the normal (polytope cores): separated by more than the
// tolerance, the closest point v is unique and so is -v/|v|. Otherwise the
// facets whose plane lies within the tolerance of the best one are the
// candidates; the normal is unique when they all agree within 1e-8 rad.
//
// Costs: |A| |B| points through qhull (milliseconds for a few thousand;
// refinement stops at a point budget). Failures (non-finite input, invalid shape, qhull error) give
// ok == false with the reason; nothing is guessed.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/shapes.hpp>
#include <string>
#include <vector>

namespace hedra::reference {

struct ExactSettings {
  // Sides of the initial inscribed polygons of cylinders and cones (0: 8).
  int polygon_sides = 0;
  // No refinement pass starts once the difference has more points than this
  // (a curved shape against a large hull): the bracket is then reported as
  // wide as it is.
  std::size_t max_difference_points = 60000;
  // Refinement passes for curved shapes (each one qhull build), until the
  // bracket is narrower than target_width times the larger shape's bounding
  // radius.
  int refinements = 16;
  double target_width = 1e-12;
  // Points of the cutting-plane hull (overlapping curved pairs whose
  // bracket is still wider than the target after the passes above).
  std::size_t max_support_points = 8000;
  // Evaluations of the azimuth bracket (a curved core against a core of
  // points), until its bracket is within the target.
  int max_azimuth_evaluations = 40000;
  // Optional: the input points (local frame) of a Polyhedron shape a or b,
  // used instead of its quickhull vertices so that the reference does not
  // depend on hedra's hull builder either. Ignored for other shapes.
  const std::vector<Eigen::Vector3d>* override_a = nullptr;
  const std::vector<Eigen::Vector3d>* override_b = nullptr;
};

struct ExactResult {
  bool ok = false;
  std::string reason;  // why not ok (empty when ok)

  // Signed distance: > 0 separated, < 0 minus the penetration depth, with
  // |distance - true| <= error_bound.
  double distance = 0.0;
  double error_bound = 0.0;
  // The certified bracket (up to rounding, which error_bound includes):
  // lower <= true <= upper. Equal for polytope pairs.
  double lower = 0.0;
  double upper = 0.0;

  // Unit normal from A toward B (world frame), a maximiser of -h_D(n).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  // The normal is unique (see the top of the file) and exact to rounding:
  // polytope cores only.
  bool normal_unique = false;
  // Largest angle (rad) between candidate normals (0 when one candidate).
  double normal_spread = 0.0;

  // Witness points, world frame: on (or, for curved shapes, on the inscribed
  // polygons of) the shapes, point_b - point_a = distance * normal (for
  // curved shapes with the inscribed distance).
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();

  bool curved = false;                // a cylinder or cone was approximated
  int dimension = 3;                  // affine dimension of the core difference
  int polygon_sides = 0;              // sides used for curved shapes (0 if none)
  std::size_t difference_points = 0;  // |A| |B| of the last qhull input
  std::size_t support_points = 0;     // points of the cutting-plane hull (0: not needed)
  double tolerance = 0.0;             // the rounding tolerance used (scale of D)
};

// Signed distance between two posed hedra::collision shapes.
ExactResult exact_signed_distance(const collision::Shape& a, const collision::Pose& pose_a, const collision::Shape& b,
                                  const collision::Pose& pose_b, const ExactSettings& settings = {});

// Signed distance between the convex hulls of two world point sets (radii
// 0): the polytope case of the above, for tests that hold points.
ExactResult exact_signed_distance(const std::vector<Eigen::Vector3d>& a_points,
                                  const std::vector<Eigen::Vector3d>& b_points);

}  // namespace hedra::reference
