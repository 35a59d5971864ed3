// Results and statuses of the Python module. Single queries return the C++
// result structs wrapped as read-only Python classes (vectors as new numpy
// arrays, statuses as words); batches and scenes return dicts of numpy
// arrays whose "status" column holds codes into hedra.STATUS_NAMES.
//
// STATUS_NAMES is one table for every query: hedra::collision::Status's
// words first (ok = 0), then the continuous queries' own verdicts. Codes
// never change once published; new words are only appended.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <cstdint>
#include <hedra/collision/cast_result.hpp>
#include <hedra/collision/query.hpp>

namespace hedra::python {

namespace py = pybind11;

std::int8_t status_code(collision::Status status);
std::int8_t status_code(collision::CastStatus status);
const char* status_word(collision::Status status);
const char* status_word(collision::CastStatus status);
py::tuple status_names();

// A new (3,) float64 array.
py::array_t<double> vector_array(const Eigen::Vector3d& v);
// Copies v into out[0..3).
inline void put(double* out, const Eigen::Vector3d& v) { out[0] = v.x(), out[1] = v.y(), out[2] = v.z(); }

void bind_results(py::module_& m);

}  // namespace hedra::python
