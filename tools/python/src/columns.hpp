// Batch and scene answers as dicts of new numpy arrays ("columns"): the
// arrays are allocated with the GIL held, then filled from the C++ results
// with it released.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>
#include <vector>

#include "results.hpp"

namespace hedra::python {

namespace py = pybind11;

// A new array of `shape` put into dict[key]; returns its data.
template <class T>
T* add_column(py::dict& dict, const char* key, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(std::move(shape));
  dict[key] = a;
  return a.mutable_data();
}

// The columns a query fills; null pointers are columns it does not have.
struct Columns {
  std::int8_t* status = nullptr;
  bool* intersecting = nullptr;
  double* distance = nullptr;
  double* normal = nullptr;
  double* point_a = nullptr;
  double* point_b = nullptr;
  double* error_bound = nullptr;
  std::int64_t* count = nullptr;
  double* points = nullptr;
  double* depths = nullptr;
};

enum class QueryKind { intersect, distance, penetration, contact };

// The dict with every column of `kind` for n rows (status, intersecting;
// then distance, normal, point_a, point_b, error_bound; contact: count,
// points, depths).
inline Columns add_columns(py::dict& dict, QueryKind kind, std::size_t n) {
  const auto rows = static_cast<py::ssize_t>(n);
  Columns c;
  c.status = add_column<std::int8_t>(dict, "status", {rows});
  c.intersecting = add_column<bool>(dict, "intersecting", {rows});
  if (kind == QueryKind::intersect) return c;
  c.distance = add_column<double>(dict, "distance", {rows});
  c.normal = add_column<double>(dict, "normal", {rows, 3});
  c.point_a = add_column<double>(dict, "point_a", {rows, 3});
  c.point_b = add_column<double>(dict, "point_b", {rows, 3});
  c.error_bound = add_column<double>(dict, "error_bound", {rows});
  if (kind != QueryKind::contact) return c;
  c.count = add_column<std::int64_t>(dict, "count", {rows});
  c.points = add_column<double>(dict, "points", {rows, collision::kMaxContactPoints, 3});
  c.depths = add_column<double>(dict, "depths", {rows, collision::kMaxContactPoints});
  return c;
}

// Row i of the columns from one result (any of the four query results, or
// the scene's pair result: members a result lacks are not written).
template <class R>
void put_row(const Columns& c, std::size_t i, const R& r) {
  c.status[i] = status_code(r.status);
  c.intersecting[i] = r.intersecting;
  if constexpr (!std::is_same_v<R, collision::IntersectResult>) {
    if (!c.distance) return;  // an intersect query's columns
    c.distance[i] = r.distance;
    put(c.normal + 3 * i, r.normal);
    put(c.point_a + 3 * i, r.point_a);
    put(c.point_b + 3 * i, r.point_b);
    if (c.error_bound) c.error_bound[i] = r.error_bound;
    if constexpr (!std::is_same_v<R, collision::DistanceResult> && !std::is_same_v<R, collision::PenetrationResult>) {
      if (c.count) {
        c.count[i] = r.count;
        for (int k = 0; k < collision::kMaxContactPoints; ++k) {
          const bool used = k < r.count;
          put(c.points + 3 * (collision::kMaxContactPoints * i + k),
              used ? r.points[k].point : Eigen::Vector3d::Zero().eval());
          c.depths[collision::kMaxContactPoints * i + k] = used ? r.points[k].depth : 0.0;
        }
      }
    }
  }
}

}  // namespace hedra::python
