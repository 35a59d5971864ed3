// hedra.Scene: bodies (shape, pose, collision filter) in a
// collision::World, and pairs(): every pair within max_distance through the
// World's broadphase, the query on each candidate, sorted by (a, b). The
// GIL is released while the World works; a mutex keeps another Python
// thread from changing the scene meanwhile.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <hedra/collision/world.hpp>
#include <mutex>
#include <sstream>

#include "args.hpp"
#include "columns.hpp"
#include "queries.hpp"
#include "shapes.hpp"

namespace hedra::python {

void bind_scene(py::module_& m);

namespace {

using namespace collision;

class Scene {
 public:
  std::uint32_t add(py::handle shape, py::handle pose, py::handle group, py::handle mask) {
    const Shape& s = to_shape(shape, "shape");
    const Pose p = to_pose(pose, "pose");
    const auto g = static_cast<std::uint32_t>(to_integer(group, "group", 0, 0xFFFFFFFFll));
    const auto k = static_cast<std::uint32_t>(to_integer(mask, "mask", 0, 0xFFFFFFFFll));
    const auto lock = lock_without_gil();
    const std::uint32_t body = world_.add(s, p, g, k);
    if (body == World::kInvalidBody) throw py::value_error("shape: not accepted by the scene (invalid shape or pose)");
    return body;
  }

  void ignore_pair(py::handle i, py::handle j) {
    const std::uint32_t a = body_index(i, "i"), b = body_index(j, "j");
    if (a == b) throw py::value_error("ignore_pair: i and j are the same body (" + std::to_string(a) + ")");
    const auto lock = lock_without_gil();
    world_.ignore_pair(a, b);
  }

  void set_pose(py::handle i, py::handle pose) {
    const std::uint32_t body = body_index(i, "i");
    const Pose p = to_pose(pose, "pose");
    const auto lock = lock_without_gil();
    world_.set_pose(body, p);
  }

  void set_poses(py::handle poses) {
    const PoseBatch batch = to_pose_batch(poses, "poses");
    if (batch.single || batch.rows() != size())
      throw py::value_error("poses: expected " + std::to_string(size()) + " poses (one per body), got " +
                            (batch.single ? std::string("one pose") : std::to_string(batch.rows())));
    const auto lock = lock_without_gil();
    world_.set_poses(batch.poses.data(), batch.rows());
  }

  py::dict pairs(py::handle max_distance, py::handle query, py::handle threads) {
    PairSettings settings;
    settings.max_distance = to_non_negative(max_distance, "max_distance");
    settings.query = to_query(query);
    settings.parallel.threads = to_threads(threads);
    const QueryKind kind = settings.query == PairQuery::intersect     ? QueryKind::intersect
                           : settings.query == PairQuery::distance    ? QueryKind::distance
                           : settings.query == PairQuery::penetration ? QueryKind::penetration
                                                                      : QueryKind::contact;
    std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
    {
      py::gil_scoped_release release;
      lock.lock();
      world_.pairs(settings, found_);
    }
    py::dict dict;
    const auto m = static_cast<py::ssize_t>(found_.size());
    std::int64_t* a = add_column<std::int64_t>(dict, "a", {m});
    std::int64_t* b = add_column<std::int64_t>(dict, "b", {m});
    const Columns columns = add_columns(dict, kind, found_.size());
    {
      py::gil_scoped_release fill;
      for (std::size_t i = 0; i < found_.size(); ++i) {
        a[i] = found_[i].a, b[i] = found_[i].b;
        put_row(columns, i, found_[i]);
      }
    }
    return dict;
  }

  std::size_t size() const { return world_.size(); }

 private:
  // The scene's lock, waited for without the GIL (pairs() may hold it).
  std::unique_lock<std::mutex> lock_without_gil() {
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) {
      py::gil_scoped_release release;
      lock.lock();
    }
    return lock;
  }

  std::uint32_t body_index(py::handle i, const char* name) const {
    if (size() == 0) throw py::value_error(std::string(name) + ": the scene has no bodies");
    return static_cast<std::uint32_t>(to_integer(i, name, 0, static_cast<std::int64_t>(size()) - 1));
  }

  static PairQuery to_query(py::handle query) {
    if (!py::isinstance<py::str>(query))
      throw py::type_error("query: expected one of 'intersect', 'distance', 'penetration', 'contact'");
    const std::string q = py::str(query);
    if (q == "intersect") return PairQuery::intersect;
    if (q == "distance") return PairQuery::distance;
    if (q == "penetration") return PairQuery::penetration;
    if (q == "contact") return PairQuery::contact;
    throw py::value_error("query: expected one of 'intersect', 'distance', 'penetration', 'contact', got '" + q + "'");
  }

  World world_;
  std::vector<PairResult> found_;
  std::mutex mutex_;
};

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Scene>(m, "Scene", "Bodies (shape, pose, collision filter) and the query over all their pairs.")
      .def(py::init<>())
      .def("add", &Scene::add, py::arg("shape"), py::arg("pose"), py::arg("group") = 1, py::arg("mask") = 0xFFFFFFFFu,
           "Adds a body; returns its index (0, 1, 2, ... in order of adding; never renumbered).")
      .def("ignore_pair", &Scene::ignore_pair, py::arg("i"), py::arg("j"), "Never report the pair (i, j).")
      .def("set_pose", &Scene::set_pose, py::arg("i"), py::arg("pose"), "Moves body i.")
      .def("set_poses", &Scene::set_poses, py::arg("poses"), "Moves every body: (N, 7) or (N, 4, 4), N = len(scene).")
      .def("pairs", &Scene::pairs, py::kw_only(), py::arg("max_distance") = 0.0, py::arg("query") = "penetration",
           py::arg("threads") = 0,
           "Every pair (a < b) passing the filters within max_distance, sorted by (a, b), with the query's arrays.")
      .def("__len__", &Scene::size)
      .def("__repr__", [](const Scene& s) { return "Scene(<" + std::to_string(s.size()) + " bodies>)"; });
}

}  // namespace hedra::python
