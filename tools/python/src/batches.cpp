// The batch queries: hedra.intersect_many, distance_many, penetration_many,
// contact_many and raycast_many. Arguments are checked with the GIL held
// (poses converted into one vector); the C++ batch and the copy into the
// new numpy arrays run with it released. Row i is the single query on row i
// (the C++ batch guarantees the same bits for any thread count).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <hedra/collision/batch.hpp>

#include "args.hpp"
#include "columns.hpp"
#include "queries.hpp"
#include "shapes.hpp"

namespace hedra::python {

void bind_batches(py::module_& m);

namespace {

using namespace collision;

collision::ParallelSettings parallel_settings(int threads) {
  collision::ParallelSettings parallel;
  parallel.threads = threads;
  return parallel;
}

// The checked arguments of a pair batch (poses converted block by block).
struct PairBatch {
  PairBatch(py::handle a_, py::handle poses_a_, py::handle b_, py::handle poses_b_, py::handle threads_)
      : a(to_shape(a_, "a")),
        poses_a(to_pose_array(poses_a_, "poses_a")),
        b(to_shape(b_, "b")),
        poses_b(to_pose_array(poses_b_, "poses_b")),
        rows(broadcast_rows(poses_a.rows(), "poses_a", poses_b.rows(), "poses_b")),
        parallel(parallel_settings(to_threads(threads_))) {}
  const Shape& a;
  PoseArray poses_a;
  const Shape& b;
  PoseArray poses_b;
  std::size_t rows;
  collision::ParallelSettings parallel;
};

// Rows per block: poses are converted (with the GIL: a bad one raises) and
// the C++ batch runs (without it) block by block, into reused buffers of
// poses and results, copied into the columns after each block. Buffers for
// every row (about 350 bytes a row) cost more than the queries of cheap
// pairs: 245 ns a row instead of 118 for sphere-sphere distance beyond
// 10 000 rows. Rows are independent, so blocks change no bit.
constexpr std::size_t kBlockRows = 4096;

// One side's poses for a block: a broadcast pose converted once.
class BlockPoses {
 public:
  BlockPoses(const PoseArray& array, std::size_t block) : array_(array), once_(array.rows() == 1) {
    poses_.resize(once_ ? 1 : block);
    if (once_) array_.convert(0, 1, poses_.data());
  }
  collision::PoseSpan load(std::size_t begin, std::size_t count) {
    if (once_) return {poses_.data(), 1};
    array_.convert(begin, count, poses_.data());
    return {poses_.data(), count};
  }

 private:
  const PoseArray& array_;
  bool once_;
  std::vector<Pose> poses_;
};

// Calls run(poses_a, poses_b, count, results) block by block and copies the
// results into the columns of `kind`; only the conversion of poses holds
// the GIL.
template <class Result, class Run>
py::dict run_batch(const PairBatch& p, QueryKind kind, Run&& run) {
  const std::size_t block = std::min(p.rows, kBlockRows);
  BlockPoses poses_a(p.poses_a, block), poses_b(p.poses_b, block);
  std::vector<Result> results(block);
  py::dict dict;
  const Columns columns = add_columns(dict, kind, p.rows);
  for (std::size_t begin = 0; begin < p.rows; begin += block) {
    const std::size_t count = std::min(block, p.rows - begin);
    const collision::PoseSpan span_a = poses_a.load(begin, count), span_b = poses_b.load(begin, count);
    py::gil_scoped_release release;
    run(span_a, span_b, count, results.data());
    for (std::size_t i = 0; i < count; ++i) put_row(columns, begin + i, results[i]);
  }
  return dict;
}

// raycast_many: rays (N, 3) or one (3,) broadcast, against one posed shape.
py::dict raycast_rows(py::handle shape, py::handle pose, py::handle origins, py::handle directions,
                      py::handle max_fraction, py::handle threads, py::handle settings) {
  const Shape& sh = to_shape(shape, "shape");
  const Pose p = to_pose(pose, "pose");
  const py::array_t<double> o = to_real_array(origins, "origins");
  const py::array_t<double> d = to_real_array(directions, "directions");
  const auto rows_of = [](const py::array_t<double>& a, const char* name) -> py::ssize_t {
    if (a.ndim() == 1 && a.shape(0) == 3) return -1;  // one, broadcast
    if (a.ndim() == 2 && a.shape(1) == 3) return a.shape(0);
    value_error(name, "expected shape (N, 3) or (3,)");
  };
  const py::ssize_t no = rows_of(o, "origins"), nd = rows_of(d, "directions");
  if (no >= 0 && nd >= 0 && no != nd)
    throw py::value_error("origins has " + std::to_string(no) + " rows and directions has " + std::to_string(nd) +
                          ": they must have the same length (or one (3,), broadcast)");
  const auto rows = static_cast<std::size_t>(std::max<py::ssize_t>(std::max(no, nd), no < 0 && nd < 0 ? 1 : 0));
  const double f = to_non_negative(max_fraction, "max_fraction");
  const collision::ParallelSettings parallel = parallel_settings(to_threads(threads));
  const RaycastSettings s = to_settings<RaycastSettings>(settings, "RaycastSettings");
  std::vector<Eigen::Vector3d> ov(rows), dv(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    const double* oi = o.data() + (no < 0 ? 0 : 3 * i);
    const double* di = d.data() + (nd < 0 ? 0 : 3 * i);
    ov[i] = {oi[0], oi[1], oi[2]};
    dv[i] = {di[0], di[1], di[2]};
    if (dv[i].isZero(0.0))
      value_error(nd < 0 ? "directions" : "directions[" + std::to_string(i) + "]",
                  "a zero vector (a ray needs a direction)");
  }
  std::vector<RaycastResult> results(rows);
  py::dict dict;
  const auto n = static_cast<py::ssize_t>(rows);
  bool* hit = add_column<bool>(dict, "hit", {n});
  double* fraction = add_column<double>(dict, "fraction", {n});
  double* point = add_column<double>(dict, "point", {n, 3});
  double* normal = add_column<double>(dict, "normal", {n, 3});
  double* error_bound = add_column<double>(dict, "error_bound", {n});
  std::int8_t* status = add_column<std::int8_t>(dict, "status", {n});
  {
    py::gil_scoped_release release;
    collision::raycast_many(sh, p, ov.data(), dv.data(), rows, f, results.data(), parallel, s);
    for (std::size_t i = 0; i < rows; ++i) {
      const RaycastResult& r = results[i];
      hit[i] = r.hit, fraction[i] = r.fraction, error_bound[i] = r.error_bound;
      status[i] = status_code(r.status);
      put(point + 3 * i, r.point), put(normal + 3 * i, r.normal);
    }
  }
  return dict;
}

}  // namespace

void bind_batches(py::module_& m) {
  m.def(
      "intersect_many",
      [](py::handle a, py::handle poses_a, py::handle b, py::handle poses_b, py::handle threads, py::handle settings) {
        const PairBatch p(a, poses_a, b, poses_b, threads);
        const GjkSettings s = to_settings<GjkSettings>(settings, "GjkSettings");
        return run_batch<IntersectResult>(
            p, QueryKind::intersect,
            [&](collision::PoseSpan pa, collision::PoseSpan pb, std::size_t count, IntersectResult* out) {
              collision::intersect_many(p.a, pa, p.b, pb, count, out, p.parallel, s);
            });
      },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::kw_only(), py::arg("threads") = 0,
      py::arg("settings") = py::none(),
      "intersect() on N pose pairs: a dict of arrays 'intersecting' (N,) bool and 'status' (N,) int8.");
  m.def(
      "distance_many",
      [](py::handle a, py::handle poses_a, py::handle b, py::handle poses_b, py::handle threads, py::handle settings) {
        const PairBatch p(a, poses_a, b, poses_b, threads);
        const GjkSettings s = to_settings<GjkSettings>(settings, "GjkSettings");
        return run_batch<DistanceResult>(
            p, QueryKind::distance,
            [&](collision::PoseSpan pa, collision::PoseSpan pb, std::size_t count, DistanceResult* out) {
              collision::distance_many(p.a, pa, p.b, pb, count, out, p.parallel, s);
            });
      },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::kw_only(), py::arg("threads") = 0,
      py::arg("settings") = py::none(),
      "distance() on N pose pairs: a dict of arrays distance, normal, point_a, point_b, intersecting, error_bound, "
      "status.");
  m.def(
      "penetration_many",
      [](py::handle a, py::handle poses_a, py::handle b, py::handle poses_b, py::handle threads, py::handle settings) {
        const PairBatch p(a, poses_a, b, poses_b, threads);
        const PenetrationSettings s = to_settings<PenetrationSettings>(settings, "PenetrationSettings");
        return run_batch<PenetrationResult>(
            p, QueryKind::penetration,
            [&](collision::PoseSpan pa, collision::PoseSpan pb, std::size_t count, PenetrationResult* out) {
              collision::penetration_many(p.a, pa, p.b, pb, count, out, p.parallel, s);
            });
      },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::kw_only(), py::arg("threads") = 0,
      py::arg("settings") = py::none(),
      "penetration() on N pose pairs: a dict of arrays distance (signed), normal, point_a, point_b, intersecting, "
      "error_bound, status.");
  m.def(
      "contact_many",
      [](py::handle a, py::handle poses_a, py::handle b, py::handle poses_b, py::handle contact_distance,
         py::handle threads, py::handle settings) {
        const PairBatch p(a, poses_a, b, poses_b, threads);
        ContactSettings s = to_settings<ContactSettings>(settings, "ContactSettings");
        s.contact_distance = to_non_negative(contact_distance, "contact_distance");
        return run_batch<ContactResult>(
            p, QueryKind::contact,
            [&](collision::PoseSpan pa, collision::PoseSpan pb, std::size_t count, ContactResult* out) {
              collision::contact_many(p.a, pa, p.b, pb, count, out, p.parallel, s);
            });
      },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::kw_only(),
      py::arg("contact_distance") = 0.0, py::arg("threads") = 0, py::arg("settings") = py::none(),
      "contact() on N pose pairs: the arrays of penetration_many plus count (N,), points (N, 4, 3) "
      "and depths (N, 4), unused slots zero.");
  m.def("raycast_many", &raycast_rows, py::arg("shape"), py::arg("pose"), py::arg("origins"), py::arg("directions"),
        py::kw_only(), py::arg("max_fraction") = 1.0, py::arg("threads") = 0, py::arg("settings") = py::none(),
        "raycast() of N rays (origins and directions (N, 3), or one (3,) broadcast) against one posed shape: a dict "
        "of arrays hit, fraction, point, normal, error_bound, status.");
}

}  // namespace hedra::python
