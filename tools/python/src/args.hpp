// Argument checking for the Python module: every argument that comes from
// Python goes through one of these, which either return a checked C++ value
// or throw TypeError / ValueError naming the argument.
//
//   TypeError   the wrong kind of object: None, a string, bytes, a complex
//               number, a bool, an arbitrary object, an array of such;
//   ValueError  the right kind but a wrong value: a NaN or infinity, a wrong
//               shape, a negative size, a zero quaternion, a 4x4 that is not
//               rigid, arrays of different lengths.
//
// Arrays are converted to float64 C-contiguous copies only when they are not
// already that (numpy's asarray), then read in place while the caller holds
// them. Poses: a 7-vector [x, y, z, qw, qx, qy, qz] (quaternion scalar first,
// normalised; norm below 1e-12 raises) or a 4x4 rigid transform (|R^T R - I|
// entrywise within 1e-6, det R > 0, last row exactly 0 0 0 1); batches are
// (N, 7) or (N, 4, 4), and a single pose broadcasts.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <cstdint>
#include <hedra/collision/pose.hpp>
#include <string>
#include <vector>

namespace hedra::python {

namespace py = pybind11;
using collision::Pose;

// The Python exceptions, with the argument's name in front of the message.
[[noreturn]] void type_error(const std::string& name, const std::string& what);
[[noreturn]] void value_error(const std::string& name, const std::string& what);

// A real number: a Python int or float or a numpy real scalar (not a bool,
// a string, None or a complex). finite() adds the NaN/infinity check.
double to_double(py::handle object, const char* name);
double to_finite(py::handle object, const char* name);
// finite and >= 0 (sizes, margins, distances).
double to_non_negative(py::handle object, const char* name);
// An integer (Python int or numpy integer, not a bool or a float) in
// [low, high].
std::int64_t to_integer(py::handle object, const char* name, std::int64_t low, std::int64_t high);
// threads= : 0 (all cores) or a positive count.
int to_threads(py::handle object);

// A real array as float64, C-contiguous (a new array only when needed),
// every entry finite. TypeError for non-numeric input (strings, objects,
// complex, bool), ValueError for NaN/infinity or an array numpy cannot form.
py::array_t<double> to_real_array(py::handle object, const char* name);
// The same with its shape checked: `shape` lists the expected extents, -1
// for any. `expected` is how the message describes it, e.g. "(N, 3)".
py::array_t<double> to_real_array(py::handle object, const char* name, const std::vector<py::ssize_t>& shape,
                                  const char* expected);
Eigen::Vector3d to_vector3(py::handle object, const char* name);

// One pose (7-vector or 4x4).
Pose to_pose(py::handle object, const char* name);

// A batch of poses as given: (N, 7), (N, 4, 4), or one pose (7,) / (4, 4)
// that broadcasts (single; rows() is then 1). Its type, shape and
// finiteness are checked when made; each pose's own rules (a zero
// quaternion, a 4x4 that is not rigid) when converted, a block at a time.
struct PoseArray {
  py::array_t<double> array;
  const char* name = "";
  std::size_t width = 7;  // 7 or 16 numbers a pose
  bool single = false;
  std::size_t rows() const { return single ? 1 : static_cast<std::size_t>(array.shape(0)); }
  // Poses [begin, begin + count) into out (ValueError naming the row).
  void convert(std::size_t begin, std::size_t count, Pose* out) const;
};
PoseArray to_pose_array(py::handle object, const char* name);

// Every pose of a batch converted at once.
struct PoseBatch {
  std::vector<Pose> poses;
  bool single = false;
  std::size_t rows() const { return poses.size(); }
};
PoseBatch to_pose_batch(py::handle object, const char* name);

// The number of rows of two batches that broadcast against each other (a
// single pose or a batch of one broadcasts); ValueError naming both when
// they differ.
std::size_t broadcast_rows(std::size_t rows_a, const char* name_a, std::size_t rows_b, const char* name_b);

}  // namespace hedra::python
