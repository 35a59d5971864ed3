// Settings classes (hedra.GjkSettings, ...: every field checked when set)
// and the single queries: intersect, distance, penetration, contact,
// raycast, shape_cast, time_of_impact. Single queries keep the GIL (they
// take about a microsecond; releasing it would cost a tenth of that).
#include "queries.hpp"

#include <hedra/collision/cast.hpp>
#include <hedra/collision/time_of_impact.hpp>

#include "args.hpp"
#include "results.hpp"
#include "shapes.hpp"

namespace hedra::python {
namespace {

using namespace collision;

template <class T, class Class>
void int_field(Class& c, const char* name, int T::*member, const char* doc) {
  c.def_property(
      name, [member](const T& t) { return t.*member; },
      [member, name](T& t, py::handle v) { t.*member = static_cast<int>(to_integer(v, name, 1, 1000000)); }, doc);
}

template <class T, class Class>
void real_field(Class& c, const char* name, double T::*member, const char* doc) {
  c.def_property(
      name, [member](const T& t) { return t.*member; },
      [member, name](T& t, py::handle v) { t.*member = to_non_negative(v, name); }, doc);
}

// T(**fields): each keyword set as an attribute (checked by its setter).
template <class T, class Class>
void keyword_init(Class& c) {
  c.def(py::init([](const py::kwargs& fields) {
    py::object object = py::cast(T{});
    for (const auto& item : fields) {
      if (!py::hasattr(object, item.first))
        throw py::type_error(std::string(py::str(py::type::handle_of(object).attr("__name__"))) +
                             ": no setting named '" + std::string(py::str(item.first)) + "'");
      object.attr(item.first) = item.second;
    }
    return object.cast<T>();
  }));
}

// shape_cast and time_of_impact take (..., settings, cache) on some
// branches of the library and (..., cache, settings) on others: whichever
// compiles is called.
template <class S>
auto call_shape_cast(int, const Shape& a, const Pose& pa, const Eigen::Vector3d& ta, const Shape& b, const Pose& pb,
                     const Eigen::Vector3d& tb, const S& settings)
    -> decltype(shape_cast(a, pa, ta, b, pb, tb, settings, static_cast<GjkCache*>(nullptr))) {
  return shape_cast(a, pa, ta, b, pb, tb, settings, static_cast<GjkCache*>(nullptr));
}
template <class S>
auto call_shape_cast(long, const Shape& a, const Pose& pa, const Eigen::Vector3d& ta, const Shape& b, const Pose& pb,
                     const Eigen::Vector3d& tb, const S& settings)
    -> decltype(shape_cast(a, pa, ta, b, pb, tb, static_cast<GjkCache*>(nullptr), settings)) {
  return shape_cast(a, pa, ta, b, pb, tb, static_cast<GjkCache*>(nullptr), settings);
}
template <class S>
auto call_toi(int, const Shape& a, const Sweep& sa, const Shape& b, const Sweep& sb, const S& settings)
    -> decltype(time_of_impact(a, sa, b, sb, settings, static_cast<GjkCache*>(nullptr))) {
  return time_of_impact(a, sa, b, sb, settings, static_cast<GjkCache*>(nullptr));
}
template <class S>
auto call_toi(long, const Shape& a, const Sweep& sa, const Shape& b, const Sweep& sb, const S& settings)
    -> decltype(time_of_impact(a, sa, b, sb, static_cast<GjkCache*>(nullptr), settings)) {
  return time_of_impact(a, sa, b, sb, static_cast<GjkCache*>(nullptr), settings);
}

}  // namespace

Pair::Pair(py::handle a_, py::handle pose_a_, py::handle b_, py::handle pose_b_)
    : a(to_shape(a_, "a")),
      pose_a(to_pose(pose_a_, "pose_a")),
      b(to_shape(b_, "b")),
      pose_b(to_pose(pose_b_, "pose_b")) {}

void bind_settings(py::module_& m) {
  py::class_<GjkSettings> gjk(m, "GjkSettings", "GJK's cap and tolerances (intersect, distance; part of the others).");
  keyword_init<GjkSettings>(gjk);
  int_field(gjk, "max_iterations", &GjkSettings::max_iterations, "Iteration cap (status max_iterations beyond).");
  real_field(gjk, "relative_tolerance", &GjkSettings::relative_tolerance, "Stop at this relative distance error.");
  real_field(gjk, "absolute_tolerance", &GjkSettings::absolute_tolerance, "... or this error times the pair's size.");

  py::class_<EpaSettings> epa(m, "EpaSettings", "EPA's cap and tolerances (penetration of overlapping cores).");
  keyword_init<EpaSettings>(epa);
  int_field(epa, "max_iterations", &EpaSettings::max_iterations, "Iteration cap.");
  real_field(epa, "relative_tolerance", &EpaSettings::relative_tolerance, "Stop at this relative depth error.");
  real_field(epa, "absolute_tolerance", &EpaSettings::absolute_tolerance, "... or this error times the pair's size.");
  real_field(epa, "flat_tolerance", &EpaSettings::flat_tolerance, "Extents below this times the size count as flat.");

  py::class_<PenetrationSettings> pen(m, "PenetrationSettings", "Settings of penetration() (GJK, then EPA).");
  keyword_init<PenetrationSettings>(pen);
  pen.def_readwrite("gjk", &PenetrationSettings::gjk).def_readwrite("epa", &PenetrationSettings::epa);
  real_field(pen, "touching_band", &PenetrationSettings::touching_band,
             "Cores closer than this times the size may be touching: EPA runs too.");

  py::class_<ContactSettings> contact(m, "ContactSettings", "Settings of contact() (docs/contacts.md).");
  keyword_init<ContactSettings>(contact);
  contact.def_readwrite("penetration", &ContactSettings::penetration);
  real_field(contact, "relative_bias", &ContactSettings::relative_bias, "Bias towards face contacts, relative.");
  real_field(contact, "absolute_bias", &ContactSettings::absolute_bias, "... and as a fraction of the pair's size.");
  real_field(contact, "face_angle_tolerance", &ContactSettings::face_angle_tolerance,
             "A normal within this angle (radians) of a face normal is that face's.");
  real_field(contact, "parallel_tolerance", &ContactSettings::parallel_tolerance,
             "SAT skips edge pairs closer to parallel than this sine.");
  real_field(contact, "max_sat_edge_pairs", &ContactSettings::max_sat_edge_pairs,
             "Polytope pairs with more edge pairs use the exact normal instead of SAT.");

  py::class_<RaycastSettings> ray(m, "RaycastSettings", "Settings of raycast().");
  keyword_init<RaycastSettings>(ray);
  real_field(ray, "tolerance", &RaycastSettings::tolerance, "A hit is within this times the shape's size.");
  int_field(ray, "max_iterations", &RaycastSettings::max_iterations, "Iteration cap of the GJK ray cast.");

  py::class_<ShapeCastSettings> cast(m, "ShapeCastSettings", "Settings of shape_cast().");
  keyword_init<ShapeCastSettings>(cast);
  real_field(cast, "linear_slop", &ShapeCastSettings::linear_slop, "Added to target_distance.");
  real_field(cast, "tolerance", &ShapeCastSettings::tolerance, "A hit's distance within this times the size.");
  int_field(cast, "max_iterations", &ShapeCastSettings::max_iterations, "Iteration cap.");

  py::class_<ToiSettings> toi(m, "ToiSettings", "Settings of time_of_impact().");
  keyword_init<ToiSettings>(toi);
  toi.def_readwrite("gjk", &ToiSettings::gjk);
  real_field(toi, "linear_slop", &ToiSettings::linear_slop, "Added to target_distance.");
  real_field(toi, "tolerance", &ToiSettings::tolerance, "A hit's distance within this times the size.");
  int_field(toi, "max_iterations", &ToiSettings::max_iterations, "Advancement steps cap.");
}

void bind_queries(py::module_& m) {
  m.def(
      "intersect",
      [](py::handle a, py::handle pose_a, py::handle b, py::handle pose_b, py::handle settings) {
        const GjkSettings s = to_settings<GjkSettings>(settings, "GjkSettings");
        const Pair p(a, pose_a, b, pose_b);
        return intersect(p.a, p.pose_a, p.b, p.pose_b, nullptr, s);
      },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::kw_only(), py::arg("settings") = py::none(),
      "Do the posed shapes overlap or touch? (GJK; stops at the first separating axis.)");
  m.def(
      "distance",
      [](py::handle a, py::handle pose_a, py::handle b, py::handle pose_b, py::handle settings) {
        const GjkSettings s = to_settings<GjkSettings>(settings, "GjkSettings");
        const Pair p(a, pose_a, b, pose_b);
        return distance(p.a, p.pose_a, p.b, p.pose_b, nullptr, s);
      },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::kw_only(), py::arg("settings") = py::none(),
      "Unsigned distance, unit normal from A toward B and closest points (0 and a zero normal when they overlap).");
  m.def(
      "penetration",
      [](py::handle a, py::handle pose_a, py::handle b, py::handle pose_b, py::handle settings) {
        const PenetrationSettings s = to_settings<PenetrationSettings>(settings, "PenetrationSettings");
        const Pair p(a, pose_a, b, pose_b);
        return penetration(p.a, p.pose_a, p.b, p.pose_b, nullptr, s);
      },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::kw_only(), py::arg("settings") = py::none(),
      "Signed distance (< 0: the penetration depth), normal from A toward B and witness points.");
  m.def(
      "contact",
      [](py::handle a, py::handle pose_a, py::handle b, py::handle pose_b, py::handle contact_distance,
         py::handle settings) {
        const Pair p(a, pose_a, b, pose_b);
        ContactSettings s = to_settings<ContactSettings>(settings, "ContactSettings");
        s.contact_distance = to_non_negative(contact_distance, "contact_distance");
        return contact(p.a, p.pose_a, p.b, p.pose_b, nullptr, s);
      },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::kw_only(),
      py::arg("contact_distance") = 0.0, py::arg("settings") = py::none(),
      "A contact manifold: up to four points midway between the surfaces, depths > 0 penetrating.");
  m.def(
      "raycast",
      [](py::handle shape, py::handle pose, py::handle origin, py::handle direction, py::handle max_fraction,
         py::handle settings) {
        const Shape& sh = to_shape(shape, "shape");
        const Pose p = to_pose(pose, "pose");
        const Eigen::Vector3d o = to_vector3(origin, "origin"), d = to_vector3(direction, "direction");
        if (d.isZero(0.0)) value_error("direction", "a zero vector (a ray needs a direction)");
        const double f = to_non_negative(max_fraction, "max_fraction");
        const RaycastSettings s = to_settings<RaycastSettings>(settings, "RaycastSettings");
        return raycast(sh, p, o, d, f, s);
      },
      py::arg("shape"), py::arg("pose"), py::arg("origin"), py::arg("direction"), py::kw_only(),
      py::arg("max_fraction") = 1.0, py::arg("settings") = py::none(),
      "The first point of origin + t direction, t in [0, max_fraction], on the posed shape.");
  m.def(
      "shape_cast",
      [](py::handle a, py::handle pose_a, py::handle translation_a, py::handle b, py::handle pose_b,
         py::handle translation_b, py::handle target_distance, py::handle settings) {
        const Shape& sa = to_shape(a, "a");
        const Pose pa = to_pose(pose_a, "pose_a");
        const Eigen::Vector3d ta = to_vector3(translation_a, "translation_a");
        const Shape& sb = to_shape(b, "b");
        const Pose pb = to_pose(pose_b, "pose_b");
        const Eigen::Vector3d tb = to_vector3(translation_b, "translation_b");
        ShapeCastSettings s = to_settings<ShapeCastSettings>(settings, "ShapeCastSettings");
        s.target_distance = to_non_negative(target_distance, "target_distance");
        return call_shape_cast(0, sa, pa, ta, sb, pb, tb, s);
      },
      py::arg("a"), py::arg("pose_a"), py::arg("translation_a"), py::arg("b"), py::arg("pose_b"),
      py::arg("translation_b"), py::kw_only(), py::arg("target_distance") = 0.0, py::arg("settings") = py::none(),
      "The first t in [0, 1] at which A and B, translated by t times their translations, come within "
      "target_distance (never later than the true contact).");
  m.def(
      "time_of_impact",
      [](py::handle a, py::handle start_a, py::handle end_a, py::handle b, py::handle start_b, py::handle end_b,
         py::handle target_distance, py::handle settings) {
        const Shape& sa = to_shape(a, "a");
        Sweep sweep_a;
        sweep_a.start = to_pose(start_a, "start_a");
        sweep_a.end = to_pose(end_a, "end_a");
        const Shape& sb = to_shape(b, "b");
        Sweep sweep_b;
        sweep_b.start = to_pose(start_b, "start_b");
        sweep_b.end = to_pose(end_b, "end_b");
        ToiSettings s = to_settings<ToiSettings>(settings, "ToiSettings");
        s.target_distance = to_non_negative(target_distance, "target_distance");
        return call_toi(0, sa, sweep_a, sb, sweep_b, s);
      },
      py::arg("a"), py::arg("start_a"), py::arg("end_a"), py::arg("b"), py::arg("start_b"), py::arg("end_b"),
      py::kw_only(), py::arg("target_distance") = 0.0, py::arg("settings") = py::none(),
      "The first t in [0, 1] at which A and B, moving from their start to their end poses (origins linearly, "
      "rotations at constant angular velocity), come within target_distance (never later than the true contact).");
}

}  // namespace hedra::python
