// The penetration depth of two overlapping boxes from the separating-axis
// test, certified (sat_depth.cpp; the argument in docs/design.md, "SAT's
// depth for overlapping boxes").
//
// The depth is min over the faces of the Minkowski difference D of the
// distance from the origin to the face's plane; for two boxes those faces'
// normals are among the 15 axes (3 face normals of each, 9 cross products
// of their edge directions), so the smallest overlap over the 15 is the
// exact depth. Each axis's overlap comes with an error term (rounding, and
// 1 / sin of the edges' angle for an edge axis); the answer is the smallest
// overlap, its error bound the gap to the smallest certified lower bound
// over all 15. Edge directions within 1e-13 rad of parallel leave a face of
// D thinner than that times the edges' length, which the bound absorbs.
// The answer is given only when the bound is within EPA's tolerance and
// witness points on both surfaces were found; otherwise GJK and EPA run
// (and always when the boxes are apart: penetration() then answers what
// distance() does, bit for bit).
// Hulls keep GJK and EPA: SAT over a box and a 12-edge hull (144 edge
// pairs through the Gauss-map test) took about 1.2x their instructions on
// the bench's parallel pairs; two boxes take 0.76x.
#pragma once

#include <Eigen/Core>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/detail/sat.hpp>
#include <hedra/collision/settings.hpp>

namespace hedra::collision::detail {

struct SatDepth {
  double distance = 0.0;                             // minus the depth (<= 0), cores
  double error_bound = 0.0;                          // the true depth is within this of -distance
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, A toward B, A's core frame
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  SatAxis axis;         // the winning axis and its features
  int axes_tested = 0;  // face axes and edge pairs measured
};

// Two box cores, B placed in A's core frame by b_in_a: true with `out` when
// they overlap (or touch), have no zero extent, and the depth is certified
// within max(relative * depth, absolute * scale) of `settings`; false when
// the bound or the witnesses fell short.
bool sat_depth(const Box& a, const Box& b, const RelativePose& b_in_a, double scale, const EpaSettings& settings,
               SatDepth& out);

}  // namespace hedra::collision::detail
