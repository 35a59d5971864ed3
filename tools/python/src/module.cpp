// The Python module `hedra` (pybind11): hedra's shapes, queries, batches
// and scenes over numpy arrays. The contract is docs/python.md: names and
// meanings other programs rely on. This file only assembles the parts:
//   args.*      every argument checked (TypeError / ValueError naming it)
//   shapes.*    Sphere, Box, Capsule, Cylinder, Cone, ConvexHull
//   results.*   result classes, STATUS_NAMES
//   queries.*   settings classes and single queries
//   batches.cpp *_many over pose arrays, the GIL released
//   scene.cpp   Scene: many bodies, pairs() through the World's broadphase
#include <pybind11/pybind11.h>

#include "queries.hpp"
#include "results.hpp"
#include "shapes.hpp"

#ifndef HEDRA_VERSION_STRING
#  error "HEDRA_VERSION_STRING must be defined by the build (the project's version)"
#endif

namespace hedra::python {
void bind_batches(py::module_& m);
void bind_scene(py::module_& m);
}  // namespace hedra::python

PYBIND11_MODULE(hedra, m) {
  namespace hp = hedra::python;
  m.doc() =
      "hedra: convex collision detection (GJK, EPA, exact curved paths, SAT manifolds) over numpy arrays.\n"
      "Poses are 4x4 rigid transforms or 7-vectors [x, y, z, qw, qx, qy, qz] (quaternion scalar first).\n"
      "See docs/python.md.";
  m.attr("__version__") = HEDRA_VERSION_STRING;
  m.attr("STATUS_NAMES") = hp::status_names();
  hp::bind_shapes(m);
  hp::bind_results(m);
  hp::bind_settings(m);
  hp::bind_queries(m);
  hp::bind_batches(m);
  hp::bind_scene(m);
}
