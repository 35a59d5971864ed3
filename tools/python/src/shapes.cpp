// hedra.Shape and its six subclasses: construction with checked arguments,
// read-only properties, repr and pickling. A ConvexHull's vertices, faces and
// triangles are in the frame of its input points (the C++ hull stores them
// recentred on its centroid: offset() is added back).
#include "shapes.hpp"

#include <pybind11/numpy.h>

#include <array>
#include <hedra/hull/mass.hpp>
#include <sstream>

#include "args.hpp"

namespace hedra::python {
namespace {

using namespace collision;

template <class Object, class Value>
Object make(Value value) {
  const ShapeValidation check = validate(Shape{value});
  if (!check.ok()) throw py::value_error(check.message);
  Object object;
  object.shape = value;
  return object;
}

template <class Value>
const Value& get(const ShapeObject& object) {
  return std::get<Value>(object.shape);
}

std::string number(double x) { return py::repr(py::float_(x)); }

py::array_t<double> vector_array(const Eigen::Vector3d& v) {
  py::array_t<double> out(3);
  std::copy(v.data(), v.data() + 3, out.mutable_data());
  return out;
}

const ConvexPolyhedron& hull_of(const ShapeObject& object) { return *get<Polyhedron>(object).hull; }

HullObject make_hull(py::handle points_object, double margin) {
  const py::array_t<double> a = to_real_array(points_object, "points", {-1, 3}, "(N, 3)");
  if (a.shape(0) == 0) value_error("points", "no points (a convex hull needs at least one)");
  HullObject object;
  object.points.resize(static_cast<std::size_t>(a.shape(0)));
  std::copy(a.data(), a.data() + a.size(), object.points.front().data());
  ConvexPolyhedron::BuildResult built;
  {
    py::gil_scoped_release release;
    built = ConvexPolyhedron::build(object.points);
  }
  if (!built.ok()) value_error("points", built.message);
  const Polyhedron shape{built.polyhedron, margin};
  const ShapeValidation check = validate(Shape{shape});
  if (!check.ok()) throw py::value_error(check.message);
  object.shape = shape;
  return object;
}

py::array_t<double> hull_vertices(const ShapeObject& object) {
  const ConvexPolyhedron& hull = hull_of(object);
  py::array_t<double> out({static_cast<py::ssize_t>(hull.vertex_count()), py::ssize_t{3}});
  double* d = out.mutable_data();
  for (std::size_t i = 0; i < hull.vertex_count(); ++i) {
    const Eigen::Vector3d p = hull.vertex(static_cast<hull::Index>(i)) + hull.offset();
    d[3 * i] = p.x(), d[3 * i + 1] = p.y(), d[3 * i + 2] = p.z();
  }
  return out;
}

py::list hull_faces(const ShapeObject& object) {
  py::list faces;
  for (const auto& polygon : hull_of(object).mesh().polygons()) {
    py::array_t<std::int64_t> face(static_cast<py::ssize_t>(polygon.size()));
    std::copy(polygon.begin(), polygon.end(), face.mutable_data());
    faces.append(face);
  }
  return faces;
}

// Each face fanned from its first vertex (faces are convex polygons).
py::array_t<std::int64_t> hull_triangles(const ShapeObject& object) {
  const auto polygons = hull_of(object).mesh().polygons();
  std::size_t count = 0;
  for (const auto& polygon : polygons) count += polygon.size() >= 3 ? polygon.size() - 2 : 0;
  py::array_t<std::int64_t> out({static_cast<py::ssize_t>(count), py::ssize_t{3}});
  std::int64_t* d = out.mutable_data();
  for (const auto& polygon : polygons)
    for (std::size_t k = 2; k < polygon.size(); ++k) {
      *d++ = polygon[0], *d++ = polygon[k - 1], *d++ = polygon[k];
    }
  return out;
}

py::array_t<double> points_array(const HullObject& o) {
  py::array_t<double> out({static_cast<py::ssize_t>(o.points.size()), py::ssize_t{3}});
  std::copy(o.points.front().data(), o.points.front().data() + 3 * o.points.size(), out.mutable_data());
  return out;
}

// The radius of a ball about the shape's own origin that holds it (for a
// hull the C++ radius is about its centroid).
double origin_bounding_radius(const ShapeObject& object) {
  if (const auto* p = std::get_if<Polyhedron>(&object.shape)) return p->hull->offset().norm() + bounding_radius(*p);
  return bounding_radius(object.shape);
}

double margin_of(const ShapeObject& object) {
  return std::visit([](const auto& s) { return s.margin; }, object.shape);
}

// The six shape classes (all final) and how to reach the ShapeObject
// inside an instance, filled by bind_shapes(): to_shape() compares the
// object's type pointer with these instead of pybind11's isinstance and
// cast, which look the type up in hash maps twice (1 500 instructions, a
// third of a single query's overhead).
struct ShapeType {
  PyTypeObject* type = nullptr;
  const ShapeObject* (*get)(void* value) = nullptr;
};
std::array<ShapeType, 6> shape_types;

template <class Object>
void register_shape_type(std::size_t slot, const py::handle& cls) {
  shape_types[slot] = {reinterpret_cast<PyTypeObject*>(cls.ptr()),
                       [](void* value) -> const ShapeObject* { return static_cast<const Object*>(value); }};
}

// Capsule, Cylinder and Cone share (radius, half_length, margin).
template <class Object, class Value>
void bind_round(py::module_& m, const char* name, const char* doc) {
  const std::string class_name = name;
  py::class_<Object, ShapeObject>(m, name, py::is_final(), doc)
      .def(py::init([](py::object radius, py::object half_length, py::object margin) {
             return make<Object>(Value{to_non_negative(radius, "radius"), to_non_negative(half_length, "half_length"),
                                       to_non_negative(margin, "margin")});
           }),
           py::arg("radius"), py::arg("half_length"), py::kw_only(), py::arg("margin") = 0.0)
      .def_property_readonly("radius", [](const ShapeObject& o) { return get<Value>(o).radius; })
      .def_property_readonly("half_length", [](const ShapeObject& o) { return get<Value>(o).half_length; })
      .def("__repr__",
           [class_name](const ShapeObject& o) {
             const auto& s = get<Value>(o);
             return class_name + "(radius=" + number(s.radius) + ", half_length=" + number(s.half_length) +
                    ", margin=" + number(s.margin) + ")";
           })
      .def(py::pickle(
          [](const ShapeObject& o) {
            const auto& s = get<Value>(o);
            return py::make_tuple(s.radius, s.half_length, s.margin);
          },
          [class_name](const py::tuple& t) {
            if (t.size() != 3) throw py::value_error(class_name + ": bad pickled state");
            return make<Object>(Value{to_non_negative(t[0], "radius"), to_non_negative(t[1], "half_length"),
                                      to_non_negative(t[2], "margin")});
          }));
}

void bind_hull(py::module_& m) {
  py::class_<HullObject, ShapeObject>(
      m, "ConvexHull", py::is_final(),
      "The convex hull of `points` (N, 3) (quickhull). Flat or collinear points give a flat, segment or point hull.")
      .def(py::init([](py::object points, py::object margin) {
             return make_hull(points, to_non_negative(margin, "margin"));
           }),
           py::arg("points"), py::kw_only(), py::arg("margin") = 0.0)
      .def_property_readonly("vertices", &hull_vertices, "The hull's vertices (V, 3), in the frame of the points.")
      .def_property_readonly("faces", &hull_faces,
                             "The faces: a list of int64 arrays of vertex indices, counter-clockwise from outside.")
      .def_property_readonly("triangles", &hull_triangles,
                             "The faces fanned into triangles (T, 3) int64, counter-clockwise from outside.")
      .def_property_readonly(
          "volume", [](const ShapeObject& o) { return hull::mass_properties(hull_of(o).mesh()).volume; },
          "The hull's volume (margin not included; 0 when flat).")
      .def_property_readonly(
          "area", [](const ShapeObject& o) { return hull::mass_properties(hull_of(o).mesh()).surface_area; },
          "The hull's surface area (margin not included).")
      .def_property_readonly(
          "centroid", [](const ShapeObject& o) { return vector_array(hull_of(o).offset()); },
          "The hull's centroid (solid; area centroid when flat), in the frame of the points.")
      .def_property_readonly("points", &points_array, "The points the hull was built from (N, 3).")
      .def("__repr__",
           [](const ShapeObject& o) {
             const ConvexPolyhedron& h = hull_of(o);
             std::ostringstream out;
             out << "ConvexHull(<" << h.vertex_count() << " vertices, " << h.mesh().face_count()
                 << " faces>, margin=" << number(get<Polyhedron>(o).margin) << ")";
             return out.str();
           })
      .def(py::pickle([](const HullObject& o) { return py::make_tuple(points_array(o), get<Polyhedron>(o).margin); },
                      [](const py::tuple& t) {
                        if (t.size() != 2) throw py::value_error("ConvexHull: bad pickled state");
                        return make_hull(t[0], to_non_negative(t[1], "margin"));
                      }));
}

}  // namespace

const collision::Shape& to_shape(py::handle object, const char* name) {
  PyTypeObject* type = Py_TYPE(object.ptr());
  for (const ShapeType& known : shape_types) {
    if (known.type != type) continue;
    auto* instance = reinterpret_cast<py::detail::instance*>(object.ptr());
    void* value =
        instance->simple_layout ? instance->simple_value_holder[0] : instance->get_value_and_holder().value_ptr();
    if (value == nullptr) type_error(name, "a hedra shape whose __init__ was never called");
    return known.get(value)->shape;
  }
  type_error(name, "expected a hedra shape (Sphere, Box, Capsule, Cylinder, Cone, ConvexHull), got " +
                       std::string(py::str(py::type::handle_of(object).attr("__name__"))));
}

void bind_shapes(py::module_& m) {
  py::class_<ShapeObject>(m, "Shape",
                          "Base class of hedra's shapes (immutable, validated when made; every size a half).")
      .def_property_readonly("margin", &margin_of, "The rounding radius added all around (>= 0).")
      .def_property_readonly("bounding_radius", &origin_bounding_radius,
                             "Radius of a ball about the shape's origin holding the whole shape, margin included.");

  py::class_<SphereObject, ShapeObject>(m, "Sphere", py::is_final(), "A ball of `radius` about the origin.")
      .def(py::init([](py::object radius, py::object margin) {
             return make<SphereObject>(Sphere{to_non_negative(radius, "radius"), to_non_negative(margin, "margin")});
           }),
           py::arg("radius"), py::kw_only(), py::arg("margin") = 0.0)
      .def_property_readonly("radius", [](const ShapeObject& o) { return get<Sphere>(o).radius; })
      .def("__repr__",
           [](const ShapeObject& o) {
             const auto& s = get<Sphere>(o);
             return "Sphere(radius=" + number(s.radius) + ", margin=" + number(s.margin) + ")";
           })
      .def(py::pickle(
          [](const ShapeObject& o) { return py::make_tuple(get<Sphere>(o).radius, get<Sphere>(o).margin); },
          [](const py::tuple& t) {
            if (t.size() != 2) throw py::value_error("Sphere: bad pickled state");
            return make<SphereObject>(Sphere{to_non_negative(t[0], "radius"), to_non_negative(t[1], "margin")});
          }));

  py::class_<BoxObject, ShapeObject>(m, "Box", py::is_final(),
                                     "An axis-aligned box centred on the origin, given by its `half_extents`.")
      .def(py::init([](py::object half_extents, py::object margin) {
             const Eigen::Vector3d h = to_vector3(half_extents, "half_extents");
             if ((h.array() < 0.0).any()) value_error("half_extents", "must be >= 0");
             return make<BoxObject>(Box{h, to_non_negative(margin, "margin")});
           }),
           py::arg("half_extents"), py::kw_only(), py::arg("margin") = 0.0)
      .def_property_readonly("half_extents",
                             [](const ShapeObject& o) { return vector_array(get<Box>(o).half_extents); })
      .def("__repr__",
           [](const ShapeObject& o) {
             const auto& s = get<Box>(o);
             return "Box(half_extents=[" + number(s.half_extents.x()) + ", " + number(s.half_extents.y()) + ", " +
                    number(s.half_extents.z()) + "], margin=" + number(s.margin) + ")";
           })
      .def(py::pickle(
          [](const ShapeObject& o) {
            const auto& s = get<Box>(o);
            return py::make_tuple(py::make_tuple(s.half_extents.x(), s.half_extents.y(), s.half_extents.z()), s.margin);
          },
          [](const py::tuple& t) {
            if (t.size() != 2) throw py::value_error("Box: bad pickled state");
            return make<BoxObject>(Box{to_vector3(t[0], "half_extents"), to_non_negative(t[1], "margin")});
          }));

  bind_round<CapsuleObject, Capsule>(
      m, "Capsule", "The segment from (0, 0, -half_length) to (0, 0, +half_length) swept by a ball of `radius`.");
  bind_round<CylinderObject, Cylinder>(
      m, "Cylinder", "A cylinder of `radius` about the z axis, from z = -half_length to +half_length.");
  bind_round<ConeObject, Cone>(
      m, "Cone", "A cone about the z axis: apex at (0, 0, +half_length), base disc of `radius` at z = -half_length.");

  bind_hull(m);

  register_shape_type<SphereObject>(0, m.attr("Sphere"));
  register_shape_type<BoxObject>(1, m.attr("Box"));
  register_shape_type<CapsuleObject>(2, m.attr("Capsule"));
  register_shape_type<CylinderObject>(3, m.attr("Cylinder"));
  register_shape_type<ConeObject>(4, m.attr("Cone"));
  register_shape_type<HullObject>(5, m.attr("ConvexHull"));
}

}  // namespace hedra::python
