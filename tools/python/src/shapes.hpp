// The shape classes of the Python module: hedra.Sphere, Box, Capsule,
// Cylinder, Cone and ConvexHull, all subclasses of hedra.Shape. Each holds an
// immutable, validated collision::Shape (a ConvexHull also its input points,
// so that it pickles to exactly the same hull); queries read it in place.
#pragma once

#include <pybind11/pybind11.h>

#include <hedra/collision/shapes.hpp>
#include <vector>

namespace hedra::python {

namespace py = pybind11;

struct ShapeObject {
  collision::Shape shape;
  virtual ~ShapeObject() = default;
};
struct SphereObject : ShapeObject {};
struct BoxObject : ShapeObject {};
struct CapsuleObject : ShapeObject {};
struct CylinderObject : ShapeObject {};
struct ConeObject : ShapeObject {};
struct HullObject : ShapeObject {
  std::vector<Eigen::Vector3d> points;  // as given (pickling rebuilds from them)
};

// The shape behind a hedra shape object; TypeError naming `name` otherwise.
const collision::Shape& to_shape(py::handle object, const char* name);

void bind_shapes(py::module_& m);

}  // namespace hedra::python
