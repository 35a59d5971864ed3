// Argument checking (args.hpp): conversion of Python objects to checked C++
// values, with TypeError / ValueError messages that name the argument.
#include "args.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

namespace hedra::python {
namespace {

std::string type_name(py::handle object) { return py::str(py::type::handle_of(object).attr("__name__")); }

std::string shape_text(const py::array& a) {
  std::ostringstream out;
  out << '(';
  for (py::ssize_t d = 0; d < a.ndim(); ++d) out << (d ? ", " : "") << a.shape(d);
  out << (a.ndim() == 1 ? ",)" : ")");
  return out.str();
}

std::string index_text(const py::array& a, py::ssize_t flat) {
  std::ostringstream out;
  std::vector<py::ssize_t> index(static_cast<std::size_t>(a.ndim()));
  for (py::ssize_t d = a.ndim() - 1; d >= 0; --d) {
    index[d] = flat % a.shape(d);
    flat /= a.shape(d);
  }
  out << '[';
  for (std::size_t d = 0; d < index.size(); ++d) out << (d ? ", " : "") << index[d];
  out << ']';
  return out.str();
}

// The kinds numpy reads as real numbers: floats and integers. Anything else
// is a wrong type, named in the message.
void check_real_kind(const py::array& a, const char* name, const char* what) {
  const char kind = a.dtype().kind();
  if (kind == 'f' || kind == 'i' || kind == 'u') return;
  const char* got = kind == 'b'                  ? "booleans"
                    : kind == 'c'                ? "complex numbers"
                    : kind == 'U' || kind == 'S' ? "strings"
                    : kind == 'O'                ? "Python objects (None, or a mix of types?)"
                                                 : "a non-numeric dtype";
  type_error(name,
             std::string("expected ") + what + ", got " + got + " (dtype " + std::string(py::str(a.dtype())) + ")");
}

py::array as_numpy(py::handle object, const char* name, const char* what) {
  if (object.is_none()) type_error(name, std::string("expected ") + what + ", got None");
  if (PyUnicode_Check(object.ptr()) || PyBytes_Check(object.ptr()))
    type_error(name, std::string("expected ") + what + ", got a string");
  try {
    return py::module_::import("numpy").attr("asarray")(object);
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_ValueError)) value_error(name, std::string("cannot be read as ") + what + ": " + e.what());
    type_error(name, std::string("cannot be read as ") + what + ": " + e.what());
  }
}

void check_finite(const py::array_t<double>& a, const char* name) {
  const double* data = a.data();
  const py::ssize_t n = a.size();
  for (py::ssize_t i = 0; i < n; ++i) {
    if (std::isfinite(data[i])) continue;
    value_error(name, std::string(std::isnan(data[i]) ? "NaN" : "infinity") +
                          (a.ndim() > 0 ? " at " + index_text(a, i) : std::string()));
  }
}

// "name" or "name[row]" (row >= 0): built only for a message.
std::string row_name(const char* name, long row) {
  return row < 0 ? std::string(name) : std::string(name) + "[" + std::to_string(row) + "]";
}

// A pose from 7 or 16 checked-finite numbers; `name` and `row` (-1: not in a
// batch) name it in messages.
Pose pose_from_vector7(const double* v, const char* name, long row) {
  const Eigen::Vector3d t(v[0], v[1], v[2]);
  if (t.cwiseAbs().maxCoeff() > collision::max_coordinate)
    value_error(row_name(name, row), "translation beyond 1e60 (hedra's largest coordinate)");
  const double largest = std::max(std::max(std::abs(v[3]), std::abs(v[4])), std::max(std::abs(v[5]), std::abs(v[6])));
  const double norm =
      largest > 0.0 ? largest * Eigen::Vector4d(v[3] / largest, v[4] / largest, v[5] / largest, v[6] / largest).norm()
                    : 0.0;
  if (!(norm >= 1e-12)) {
    std::ostringstream out;
    out << "zero quaternion (norm " << norm << " < 1e-12; the order is [x, y, z, qw, qx, qy, qz])";
    value_error(row_name(name, row), out.str());
  }
  return Pose::from_quaternion(Eigen::Quaterniond(v[3], v[4], v[5], v[6]), t);
}

Pose pose_from_matrix4(const double* m, const char* name, long row) {
  if (m[12] != 0.0 || m[13] != 0.0 || m[14] != 0.0 || m[15] != 1.0)
    value_error(row_name(name, row), "the last row of a 4x4 pose must be 0 0 0 1 (hedra takes rigid transforms only)");
  Pose pose;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) pose.rotation(i, j) = m[4 * i + j];
    pose.translation(i) = m[4 * i + 3];
  }
  const double off = (pose.rotation.transpose() * pose.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(off <= 1e-6)) {
    std::ostringstream out;
    out << "the rotation of a 4x4 pose is not orthonormal (|R^T R - I| = " << off
        << " > 1e-6): a scaled or sheared transform";
    value_error(row_name(name, row), out.str());
  }
  if (!(pose.rotation.determinant() > 0.0))
    value_error(row_name(name, row), "the rotation of a 4x4 pose is a reflection (det < 0)");
  if (pose.translation.cwiseAbs().maxCoeff() > collision::max_coordinate)
    value_error(row_name(name, row), "translation beyond 1e60 (hedra's largest coordinate)");
  return pose;
}

const char* kPoseWhat = "a pose: a 7-vector [x, y, z, qw, qx, qy, qz] or a 4x4 rigid transform";

}  // namespace

void type_error(const std::string& name, const std::string& what) { throw py::type_error(name + ": " + what); }
void value_error(const std::string& name, const std::string& what) { throw py::value_error(name + ": " + what); }

double to_double(py::handle object, const char* name) {
  PyObject* o = object.ptr();
  if (PyFloat_CheckExact(o)) return PyFloat_AS_DOUBLE(o);
  if (PyBool_Check(o)) type_error(name, "expected a real number, got a bool");
  if (PyLong_Check(o)) {
    const double value = PyLong_AsDouble(o);
    if (value == -1.0 && PyErr_Occurred()) {
      PyErr_Clear();
      value_error(name, "integer too large for a double");
    }
    return value;
  }
  if (PyFloat_Check(o)) return PyFloat_AsDouble(o);
  const py::array a = as_numpy(object, name, "a real number");
  if (a.ndim() != 0) type_error(name, "expected a real number, got an array of shape " + shape_text(a));
  check_real_kind(a, name, "a real number");
  return py::cast<double>(a.attr("item")());
}

double to_finite(py::handle object, const char* name) {
  const double value = to_double(object, name);
  if (!std::isfinite(value)) value_error(name, std::isnan(value) ? "NaN" : "infinity");
  return value;
}

double to_non_negative(py::handle object, const char* name) {
  const double value = to_finite(object, name);
  if (value < 0.0) {
    std::ostringstream out;
    out << "must be >= 0, got " << value;
    value_error(name, out.str());
  }
  return value;
}

std::int64_t to_integer(py::handle object, const char* name, std::int64_t low, std::int64_t high) {
  PyObject* o = object.ptr();
  if (PyBool_Check(o)) type_error(name, "expected an integer, got a bool");
  if (!PyLong_Check(o)) {
    // numpy integers and other exact integers through __index__ (floats have none).
    if (object.is_none() || !PyIndex_Check(o)) type_error(name, "expected an integer, got " + type_name(object));
  }
  py::int_ as_int = py::reinterpret_steal<py::int_>(PyNumber_Index(o));
  if (!as_int) {
    PyErr_Clear();
    type_error(name, "expected an integer, got " + type_name(object));
  }
  int overflow = 0;
  const long long value = PyLong_AsLongLongAndOverflow(as_int.ptr(), &overflow);
  if (overflow != 0 || value < low || value > high) {
    std::ostringstream out;
    out << "must be an integer in [" << low << ", " << high << "], got " << std::string(py::str(as_int));
    value_error(name, out.str());
  }
  return value;
}

int to_threads(py::handle object) { return static_cast<int>(to_integer(object, "threads", 0, 4096)); }

py::array_t<double> to_real_array(py::handle object, const char* name) {
  using Exact = py::array_t<double, py::array::c_style>;
  if (Exact::check_(object)) {
    auto a = py::reinterpret_borrow<py::array_t<double>>(object);
    check_finite(a, name);
    return a;
  }
  const py::array a = as_numpy(object, name, "an array of real numbers");
  check_real_kind(a, name, "an array of real numbers");
  auto converted = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!converted) {
    PyErr_Clear();
    type_error(name, "cannot be converted to float64");
  }
  check_finite(converted, name);
  return converted;
}

py::array_t<double> to_real_array(py::handle object, const char* name, const std::vector<py::ssize_t>& shape,
                                  const char* expected) {
  py::array_t<double> a = to_real_array(object, name);
  bool ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t d = 0; ok && d < shape.size(); ++d) ok = shape[d] < 0 || a.shape(d) == shape[d];
  if (!ok) value_error(name, std::string("expected shape ") + expected + ", got " + shape_text(a));
  return a;
}

Eigen::Vector3d to_vector3(py::handle object, const char* name) {
  const py::array_t<double> a = to_real_array(object, name, {3}, "(3,)");
  const double* d = a.data();
  return {d[0], d[1], d[2]};
}

Pose to_pose(py::handle object, const char* name) {
  const py::array_t<double> a = to_real_array(object, name);
  if (a.ndim() == 1 && a.shape(0) == 7) return pose_from_vector7(a.data(), name, -1);
  if (a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4) return pose_from_matrix4(a.data(), name, -1);
  value_error(name, std::string("expected ") + kPoseWhat + ", got shape " + shape_text(a));
}

PoseArray to_pose_array(py::handle object, const char* name) {
  PoseArray batch;
  batch.array = to_real_array(object, name);
  batch.name = name;
  const py::array_t<double>& a = batch.array;
  if ((a.ndim() == 1 && a.shape(0) == 7) || (a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4)) {
    batch.single = true;
    batch.width = a.ndim() == 1 ? 7 : 16;
    return batch;
  }
  const bool rows7 = a.ndim() == 2 && a.shape(1) == 7;
  const bool rows16 = a.ndim() == 3 && a.shape(1) == 4 && a.shape(2) == 4;
  if (!rows7 && !rows16)
    value_error(name, "expected a batch of poses, (N, 7) or (N, 4, 4), or one pose, (7,) or (4, 4); got shape " +
                          shape_text(a));
  batch.width = rows7 ? 7 : 16;
  return batch;
}

void PoseArray::convert(std::size_t begin, std::size_t count, Pose* out) const {
  const double* d = array.data();
  for (std::size_t i = begin; i < begin + count; ++i) {
    const long row = single ? -1 : static_cast<long>(i);
    const double* v = d + (single ? 0 : width * i);
    out[i - begin] = width == 7 ? pose_from_vector7(v, name, row) : pose_from_matrix4(v, name, row);
  }
}

PoseBatch to_pose_batch(py::handle object, const char* name) {
  const PoseArray array = to_pose_array(object, name);
  PoseBatch batch;
  batch.single = array.single;
  batch.poses.resize(array.rows());
  array.convert(0, array.rows(), batch.poses.data());
  return batch;
}

std::size_t broadcast_rows(std::size_t rows_a, const char* name_a, std::size_t rows_b, const char* name_b) {
  if (rows_a == rows_b) return rows_a;
  if (rows_a == 1) return rows_b;
  if (rows_b == 1) return rows_a;
  std::ostringstream out;
  out << name_a << " has " << rows_a << " poses and " << name_b << " has " << rows_b
      << ": batches must have the same length (or one pose, broadcast)";
  throw py::value_error(out.str());
}

}  // namespace hedra::python
