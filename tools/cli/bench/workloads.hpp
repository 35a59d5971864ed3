// `hedra bench`'s workloads: families of posed shape pairs generated from a
// seed, each pair with its exact reference (tools/reference: the signed
// distance from the origin to qhull's hull of the cores' Minkowski
// difference, plus the radii; cylinders and cones bracketed between
// inscribed polygons refined with exact support points, the bracket's half
// width stated as the reference's error bound).
//
// Families (every pair is asked one question: the signed distance, i.e. a
// `penetration` query; the swept quantity of the extreme families is the
// case's `parameter`, used by the stability report):
//   poly-separated    hulls of 8-64 vertices apart by 1e-3 .. 1 of their size
//   poly-penetrating  the same overlapping by 1e-3 .. 0.3 of their size
//   touching          signed distance 0: hull on hull (a vertex on a face),
//                     box face on box face, box edge on a face, box corner on
//                     a face, crossed box edges (placed by the reference's
//                     own normal: B moved by -distance * normal)
//   deep              coincident and deep pairs of every kind of shape,
//                     centres apart by 0 or 1e-4 .. 0.3 of the size
//                     (parameter: that fraction)
//   parallel          box on box and hull slab on box, faces 1e-9 .. 1e-4 rad
//                     from parallel, 1e-3 of the size apart or deep
//                     (parameter: the angle)
//   thin              plates and needles of aspect 1e2 .. 1e4 against boxes
//                     and hulls, apart or overlapping by half the thickness
//                     (parameter: the aspect)
//   scale             a hull 1e-3 .. 1e3 across against a 2e3-wide box or
//                     hull, apart or overlapping by a third of the small one
//                     (parameter: the ratio of the sizes, 1 .. 1e6)
//   far               poly pairs translated together by 1 .. 1e6
//                     (parameter: the offset)
//   large-hull        a 1 000 .. 20 000-vertex hull against a 16-vertex hull
//                     (parameter: the vertex count)
//   rounded           spheres, capsules, boxes and hulls with margins
//   curved            cylinders and cones against each other and polytopes
//   degenerate        flat, segment and point hulls, and hulls of points
//                     repeated many times, against boxes and hulls
// Pairs are steered to a target signed distance with the reference itself
// (B moved along the reference's normal by the difference, a few times), so
// the exact value of every case is the reference computed at its final
// pose, never the target. Hull pairs keep their input points, and the
// reference uses those rather than hedra's quickhull vertices.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/shapes.hpp>
#include <limits>
#include <string>
#include <vector>

#include "cli/compare/compare.hpp"

namespace hedra::tool::bench {

struct BenchCase {
  std::string family;
  std::string label;  // what the pair is, e.g. "box face on box face"
  // The family's swept quantity (NaN where the family sweeps none).
  double parameter = std::numeric_limits<double>::quiet_NaN();
  collision::Shape a;
  collision::Pose pose_a;
  collision::Shape b;
  collision::Pose pose_b;
  // Input points of polyhedra in their local frames (empty for other
  // shapes): the reference hulls them itself.
  std::vector<Eigen::Vector3d> points_a;
  std::vector<Eigen::Vector3d> points_b;
  // The exact signed distance (reference.exact) and the pair's size
  // (reference.pair_size, as `hedra compare` measures it); the tolerances
  // of ReferenceAnswer are set by the runner, per method.
  ReferenceAnswer reference;
};

struct FamilyInfo {
  const char* name;
  const char* parameter;  // name of the swept quantity, or "" when none
  const char* description;
};

// Every family, in report order.
const std::vector<FamilyInfo>& families();
const FamilyInfo* find_family(const std::string& name);

struct WorkloadOptions {
  std::uint64_t seed = 1;
  bool quick = false;  // a few cases a family (the test suite's run)
};

// The cases of one family (seeded by the seed and the family's name, so a
// family's cases do not depend on which other families run). Cases whose
// reference failed are dropped and counted in `dropped` with the reasons
// in `notes`.
struct FamilyCases {
  std::vector<BenchCase> cases;
  std::size_t dropped = 0;
  std::vector<std::string> notes;
};
FamilyCases make_family(const std::string& family, const WorkloadOptions& options);

// The reference of a posed pair (input points used for polyhedra).
ReferenceAnswer case_reference(const BenchCase& c);

}  // namespace hedra::tool::bench
