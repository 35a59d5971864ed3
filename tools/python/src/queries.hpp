// Settings classes and single queries of the Python module.
#pragma once

#include <pybind11/pybind11.h>

#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>

namespace hedra::python {

namespace py = pybind11;

// settings=None gives the defaults; anything but a T raises TypeError.
template <class T>
T to_settings(py::handle object, const char* expected) {
  if (object.is_none()) return T{};
  if (!py::isinstance<T>(object))
    throw py::type_error(std::string("settings: expected hedra.") + expected + " or None, got " +
                         std::string(py::str(py::type::handle_of(object).attr("__name__"))));
  return object.cast<T>();
}

// The four leading arguments of a pair query, checked in order.
struct Pair {
  Pair(py::handle a, py::handle pose_a, py::handle b, py::handle pose_b);
  const collision::Shape& a;
  collision::Pose pose_a;
  const collision::Shape& b;
  collision::Pose pose_b;
};

void bind_settings(py::module_& m);
void bind_queries(py::module_& m);

}  // namespace hedra::python
