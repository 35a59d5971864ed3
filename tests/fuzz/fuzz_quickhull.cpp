// Fuzz target: quickhull on arbitrary points.
//
// The bytes become up to 512 points (NaN, infinities, subnormals, 1e300,
// duplicates and grids all reachable, see fuzz_input.hpp), sometimes shifted
// far from the origin or scaled down. Checked, for every input:
//   - empty input gives empty_input, any non-finite coordinate
//     non_finite_input, a span over hull::max_input_extent or a widest
//     span under hull::min_input_extent (but not 0) out_of_range_input, and
//     every other input a hull (status ok: the
//     iteration cap and topology failures are never expected);
//   - the hull passes the mesh validator at its own tolerance, its
//     dimension is 0..3, its vertices are input points;
//   - every input point lies within mesh.tolerance() of the hull.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <hedra/hull/quickhull.hpp>
#include <vector>

#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hedra::fuzz::FuzzInput in(data, size);
  const unsigned mode = in.byte();
  const double shift = (mode & 1) ? in.finite_double(1e7) * 1e5 : 0.0;
  const double scale = (mode & 2) ? 1e-3 : 1.0;
  std::vector<Eigen::Vector3d> points;
  const std::size_t limit = 512;
  while (in.remaining() > 0 && points.size() < limit) {
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) p[k] = in.any_double() * scale + shift;
    points.push_back(p);
    // Duplicates and near-duplicates of earlier points.
    if ((mode & 4) && !points.empty() && in.byte() % 3 == 0) {
      const Eigen::Vector3d q = points[in.below(static_cast<unsigned>(points.size()))];
      points.push_back(q * (1.0 + std::ldexp(1.0, -52 + static_cast<int>(in.byte() % 8))));
    }
  }
  bool finite = true;
  for (const Eigen::Vector3d& p : points) finite = finite && p.allFinite();

  if (std::getenv("HEDRA_FUZZ_VERBOSE") != nullptr)  // replaying a finding: print the input at full precision
    for (const Eigen::Vector3d& p : points) std::fprintf(stderr, "{%.17g, %.17g, %.17g},\n", p.x(), p.y(), p.z());
  hedra::hull::QuickhullBuilder builder;
  const hedra::hull::QuickhullResult r = builder.build(points);
  if (points.empty()) {
    HEDRA_FUZZ_CHECK(r.status == hedra::hull::QuickhullStatus::empty_input, "status %s", to_string(r.status));
    return 0;
  }
  if (!finite) {
    HEDRA_FUZZ_CHECK(r.status == hedra::hull::QuickhullStatus::non_finite_input, "status %s", to_string(r.status));
    HEDRA_FUZZ_CHECK(!r.error.empty(), "no message");
    return 0;
  }
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double widest = (hi - lo).maxCoeff();
  if (!(widest <= hedra::hull::max_input_extent) || (widest > 0.0 && widest < hedra::hull::min_input_extent)) {
    HEDRA_FUZZ_CHECK(r.status == hedra::hull::QuickhullStatus::out_of_range_input, "span %g: status %s",
                     (hi - lo).maxCoeff(), to_string(r.status));
    return 0;
  }
  HEDRA_FUZZ_CHECK(r.ok(), "%zu finite points: status %s: %s", points.size(), to_string(r.status), r.error.c_str());
  HEDRA_FUZZ_CHECK(r.dimension >= 0 && r.dimension <= 3, "dimension %d", r.dimension);
  HEDRA_FUZZ_CHECK(std::isfinite(r.tolerance) && r.tolerance >= 0.0, "tolerance %g", r.tolerance);
  const hedra::hull::ValidationReport report = r.mesh.validate();
  HEDRA_FUZZ_CHECK(report.ok(), "%zu points, dimension %d: invalid hull: %s", points.size(), r.dimension,
                   report.errors.empty() ? "" : report.errors.front().c_str());
  HEDRA_FUZZ_CHECK(r.input_index.size() == r.mesh.vertex_count(), "input_index size");
  for (hedra::hull::Index v = 0; v < r.mesh.vertex_count(); ++v) {
    HEDRA_FUZZ_CHECK(r.input_index[v] < points.size(), "input index out of range");
    HEDRA_FUZZ_CHECK(r.mesh.position(v) == points[r.input_index[v]], "vertex %u is not its input point", v);
  }
  const double outside = hedra::hull::max_outside_distance(r.mesh, points);
  HEDRA_FUZZ_CHECK(outside <= r.mesh.tolerance(), "%zu points, dimension %d: a point %.17g outside, tolerance %.17g",
                   points.size(), r.dimension, outside, r.mesh.tolerance());
  return 0;
}
