// The result classes of single queries (hedra.IntersectResult, ...), and
// the status table shared with batches and scenes.
#include "results.hpp"

#include <hedra/collision/manifold.hpp>
#include <hedra/collision/raycast.hpp>
#include <sstream>

namespace hedra::python {
namespace {

using namespace collision;

constexpr const char* kStatusNames[] = {
    "ok",  "max_iterations", "degenerate",           "invalid_input", "polytope_full", "stalled",
    "hit", "separated",      "initially_overlapping"};

std::string number(double x) { return py::repr(py::float_(x)); }
std::string vector_text(const Eigen::Vector3d& v) {
  return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]";
}

// Binds the members every result with a signed or unsigned distance has.
template <class Result, class Class>
void bind_distance_members(Class& c) {
  c.def_property_readonly("status", [](const Result& r) { return status_word(r.status); })
      .def_property_readonly("intersecting", [](const Result& r) { return r.intersecting; })
      .def_property_readonly("distance", [](const Result& r) { return r.distance; })
      .def_property_readonly("normal", [](const Result& r) { return vector_array(r.normal); })
      .def_property_readonly("point_a", [](const Result& r) { return vector_array(r.point_a); })
      .def_property_readonly("point_b", [](const Result& r) { return vector_array(r.point_b); });
}

template <class Result>
std::string distance_repr(const char* name, const Result& r) {
  return std::string(name) + "(status='" + status_word(r.status) + "', distance=" + number(r.distance) +
         ", normal=" + vector_text(r.normal) + ", intersecting=" + (r.intersecting ? "True" : "False") + ")";
}

}  // namespace

std::int8_t status_code(Status status) {
  switch (status) {
    case Status::ok:
      return 0;
    case Status::max_iterations:
      return 1;
    case Status::degenerate:
      return 2;
    case Status::invalid_input:
      return 3;
    case Status::polytope_full:
      return 4;
    case Status::stalled:
      return 5;
  }
  return 3;
}

std::int8_t status_code(CastStatus status) {
  switch (status) {
    case CastStatus::hit:
      return 6;
    case CastStatus::separated:
      return 7;
    case CastStatus::initially_overlapping:
      return 8;
    case CastStatus::max_iterations:
      return 1;
    case CastStatus::stalled:
      return 5;
    case CastStatus::degenerate:
      return 2;
    case CastStatus::invalid_input:
      return 3;
  }
  return 3;
}

const char* status_word(Status status) { return kStatusNames[status_code(status)]; }
const char* status_word(CastStatus status) { return kStatusNames[status_code(status)]; }

py::tuple status_names() {
  py::tuple names(std::size(kStatusNames));
  for (std::size_t i = 0; i < std::size(kStatusNames); ++i) names[i] = py::str(kStatusNames[i]);
  return names;
}

py::array_t<double> vector_array(const Eigen::Vector3d& v) {
  py::array_t<double> out(3);
  put(out.mutable_data(), v);
  return out;
}

void bind_results(py::module_& m) {
  py::class_<IntersectResult>(m, "IntersectResult", "What hedra.intersect() answers.")
      .def_property_readonly("status", [](const IntersectResult& r) { return status_word(r.status); })
      .def_property_readonly("intersecting", [](const IntersectResult& r) { return r.intersecting; })
      .def_readonly("iterations", &IntersectResult::iterations)
      .def("__repr__", [](const IntersectResult& r) {
        return std::string("IntersectResult(status='") + status_word(r.status) +
               "', intersecting=" + (r.intersecting ? "True" : "False") + ")";
      });

  py::class_<DistanceResult> distance(m, "DistanceResult", "What hedra.distance() answers (unsigned).");
  bind_distance_members<DistanceResult>(distance);
  distance.def_readonly("error_bound", &DistanceResult::error_bound)
      .def_readonly("iterations", &DistanceResult::iterations)
      .def("__repr__", [](const DistanceResult& r) { return distance_repr("DistanceResult", r); });

  py::class_<PenetrationResult> penetration(m, "PenetrationResult",
                                            "What hedra.penetration() answers (signed: < 0 is the depth).");
  bind_distance_members<PenetrationResult>(penetration);
  penetration.def_readonly("error_bound", &PenetrationResult::error_bound)
      .def_readonly("gjk_iterations", &PenetrationResult::gjk_iterations)
      .def_readonly("epa_iterations", &PenetrationResult::epa_iterations)
      .def("__repr__", [](const PenetrationResult& r) { return distance_repr("PenetrationResult", r); });

  py::class_<ContactResult> contact(m, "ContactResult",
                                    "What hedra.contact() answers: up to four points midway between the surfaces.");
  bind_distance_members<ContactResult>(contact);
  contact.def_readonly("error_bound", &ContactResult::error_bound)
      .def_readonly("count", &ContactResult::count)
      .def_property_readonly("points",
                             [](const ContactResult& r) {
                               py::array_t<double> out({static_cast<py::ssize_t>(r.count), py::ssize_t{3}});
                               for (int k = 0; k < r.count; ++k) put(out.mutable_data() + 3 * k, r.points[k].point);
                               return out;
                             })
      .def_property_readonly("depths",
                             [](const ContactResult& r) {
                               py::array_t<double> out(static_cast<py::ssize_t>(r.count));
                               for (int k = 0; k < r.count; ++k) out.mutable_data()[k] = r.points[k].depth;
                               return out;
                             })
      .def_property_readonly("path", [](const ContactResult& r) { return to_string(r.path); })
      .def("__repr__", [](const ContactResult& r) {
        std::ostringstream out;
        out << "ContactResult(status='" << status_word(r.status) << "', distance=" << number(r.distance)
            << ", normal=" << vector_text(r.normal) << ", count=" << r.count << ")";
        return out.str();
      });

  py::class_<RaycastResult>(m, "RaycastResult", "What hedra.raycast() answers.")
      .def_property_readonly("status", [](const RaycastResult& r) { return status_word(r.status); })
      .def_readonly("hit", &RaycastResult::hit)
      .def_readonly("started_inside", &RaycastResult::started_inside)
      .def_readonly("fraction", &RaycastResult::fraction)
      .def_property_readonly("point", [](const RaycastResult& r) { return vector_array(r.point); })
      .def_property_readonly("normal", [](const RaycastResult& r) { return vector_array(r.normal); })
      .def_readonly("error_bound", &RaycastResult::error_bound)
      .def("__repr__", [](const RaycastResult& r) {
        return std::string("RaycastResult(status='") + status_word(r.status) + "', hit=" + (r.hit ? "True" : "False") +
               ", fraction=" + number(r.fraction) + ", point=" + vector_text(r.point) + ")";
      });

  py::class_<CastResult>(m, "CastResult", "What hedra.shape_cast() and hedra.time_of_impact() answer.")
      .def_property_readonly("status", [](const CastResult& r) { return status_word(r.status); })
      .def_readonly("hit", &CastResult::hit)
      .def_readonly("initially_overlapping", &CastResult::initially_overlapping)
      .def_readonly("fraction", &CastResult::fraction)
      .def_readonly("distance", &CastResult::distance)
      .def_property_readonly("normal", [](const CastResult& r) { return vector_array(r.normal); })
      .def_property_readonly("point_a", [](const CastResult& r) { return vector_array(r.point_a); })
      .def_property_readonly("point_b", [](const CastResult& r) { return vector_array(r.point_b); })
      .def_readonly("error_bound", &CastResult::error_bound)
      .def_readonly("iterations", &CastResult::iterations)
      .def("__repr__", [](const CastResult& r) {
        return std::string("CastResult(status='") + status_word(r.status) + "', fraction=" + number(r.fraction) +
               ", distance=" + number(r.distance) + ", normal=" + vector_text(r.normal) + ")";
      });
}

}  // namespace hedra::python
