// Shared helpers of the quickhull tests: a replayable random source, point
// dumps at full precision, and checks of a hull that do not trust the code
// under test (containment against planes fitted here, volume by the
// divergence theorem, combinatorial signatures in input indices).
//
// Tolerance policy: hedra derives eps (QuickhullResult::tolerance) from the
// recentred extent of the input. quickhull.cpp's containment pass puts back
// every point more than 6 eps in front of a face of the finished hull (6 =
// eps for a near-duplicate of a vertex, which is dropped, plus 4 eps by which
// a vertex may sit off its merged face's plane, plus eps of slack), so no
// point may lie more than kOutsideFactor = 6 eps in front of a face. That
// bound is the algorithm's stated rule, not a measurement: never raise it to
// make a test pass (mesh.tolerance() = 8 eps + rounding is the looser public
// promise, checked separately).
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cfloat>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <hedra/hull/half_edge_mesh.hpp>
#include <hedra/hull/quickhull.hpp>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace hedra::test {

inline constexpr double kOutsideFactor = 6.0;
inline constexpr double kPi = 3.14159265358979323846;

// Uniform and normal variates built directly on mt19937_64's bit stream (whose
// output the standard fixes), so that a seed replays the same cloud with any
// standard library; std::*_distribution are implementation-defined.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  // Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n).
  std::uint64_t below(std::uint64_t n) { return engine_() % n; }
  // Standard normal (Box-Muller; the second variate is discarded for
  // simplicity of replay).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
  }
  Eigen::Vector3d in_cube(double half = 1.0) {
    return {uniform(-half, half), uniform(-half, half), uniform(-half, half)};
  }
  Eigen::Vector3d in_ball(double radius = 1.0) {
    for (;;) {
      const Eigen::Vector3d p = in_cube(1.0);
      if (p.squaredNorm() <= 1.0) return radius * p;
    }
  }
  Eigen::Vector3d gaussian() { return {normal(), normal(), normal()}; }
  Eigen::Vector3d on_sphere(double radius = 1.0) {
    for (;;) {
      const Eigen::Vector3d g = gaussian();
      const double n = g.norm();
      if (n > 1e-3) return radius * g / n;
    }
  }
  // A random rotation (unit quaternion from four normals).
  Eigen::Matrix3d rotation() {
    Eigen::Quaterniond q(normal(), normal(), normal(), normal());
    q.normalize();
    return q.toRotationMatrix();
  }
  std::mt19937_64& engine() { return engine_; }

 private:
  std::mt19937_64 engine_;
};

// Deterministic shuffle (std::shuffle's use of the engine is unspecified).
inline void shuffle_points(std::vector<Eigen::Vector3d>& points, Rng& rng) {
  for (std::size_t i = points.size(); i > 1; --i) std::swap(points[i - 1], points[rng.below(i)]);
}

// C++ initialiser list of the points at full precision, ready to paste into a
// regression test.
inline std::string format_points(const std::vector<Eigen::Vector3d>& points) {
  std::string s = "{\n";
  char line[128];
  for (const auto& p : points) {
    std::snprintf(line, sizeof line, "  {%.17g, %.17g, %.17g},\n", p.x(), p.y(), p.z());
    s += line;
  }
  s += "}\n";
  return s;
}

// Largest absolute coordinate after centring on the bounding box: the scale
// of the input the way hedra sees it.
inline double centred_extent(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return 0.0;
  Eigen::Vector3d lo = points[0];
  Eigen::Vector3d hi = points[0];
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return 0.5 * (hi - lo).maxCoeff();
}

// Error-free transformations (Knuth's two-sum, an fma for the product) and a
// correctly rounded sum of many terms (Shewchuk's non-overlapping partials,
// the algorithm behind Python's math.fsum). They make the face normals below
// accurate to the last bit however thin the face; needs -ffp-contract=off
// (hedra_warnings sets it).
namespace exact {
inline void two_sum(double a, double b, double& sum, double& err) {
  sum = a + b;
  const double b_virtual = sum - a;
  const double a_virtual = sum - b_virtual;
  err = (a - a_virtual) + (b - b_virtual);
}
inline void two_product(double a, double b, double& product, double& err) {
  product = a * b;
  err = std::fma(a, b, -product);
}
inline double sum(const std::vector<double>& terms) {
  thread_local std::vector<double> partials;  // reused: this runs per triangle
  partials.clear();
  for (double x : terms) {
    std::size_t kept = 0;
    for (double y : partials) {
      double hi = 0.0;
      double lo = 0.0;
      two_sum(x, y, hi, lo);
      if (lo != 0.0) partials[kept++] = lo;
      x = hi;
    }
    partials.resize(kept);
    partials.push_back(x);
  }
  double total = 0.0;
  for (auto it = partials.rbegin(); it != partials.rend(); ++it) total += *it;
  return total;
}
// Appends the exact terms of (a1 - a0) * (b1 - b0) to `terms`.
inline void append_difference_product(double a1, double a0, double b1, double b0, double sign,
                                      std::vector<double>& terms) {
  double da = 0.0;
  double da_err = 0.0;
  double db = 0.0;
  double db_err = 0.0;
  two_sum(a1, -a0, da, da_err);
  two_sum(b1, -b0, db, db_err);
  for (double x : {da, da_err}) {
    for (double y : {db, db_err}) {
      double p = 0.0;
      double e = 0.0;
      two_product(x, y, p, e);
      terms.push_back(sign * p);
      terms.push_back(sign * e);
    }
  }
}
}  // namespace exact

// A face plane fitted here rather than taken from the mesh. The normal is
// Newell's, sum over edges of (p_i - a) x (p_{i+1} - a) around an anchor
// vertex a, evaluated exactly and rounded once: a face a billionth as wide as
// it is long still gets its normal to ~1e-16 rad, where plain floating point
// loses everything to cancellation. The offset averages the vertices'
// heights along that normal, relative to the anchor (an input point, so far
// from the origin nothing cancels).
struct LocalPlane {
  Eigen::Vector3d anchor;  // a vertex of the face
  Eigen::Vector3d normal;  // unit, outward
  double offset = 0.0;     // normal . (x - anchor) on the plane

  double signed_distance(const Eigen::Vector3d& p) const { return normal.dot(p - anchor) - offset; }
};

inline LocalPlane fitted_plane(const hull::HalfEdgeMesh& mesh, hull::Index f) {
  std::vector<Eigen::Vector3d> ring;
  for (hull::Index v : mesh.face_vertices(f)) ring.push_back(mesh.position(v));
  LocalPlane plane;
  plane.anchor = ring[0];
  Eigen::Vector3d n;
  std::vector<double> terms;
  for (int axis = 0; axis < 3; ++axis) {
    // Component `axis` of (p - a) x (q - a) is (p_j - a_j)(q_k - a_k) - (p_k - a_k)(q_j - a_j).
    const int j = (axis + 1) % 3;
    const int k = (axis + 2) % 3;
    terms.clear();
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Eigen::Vector3d& p = ring[i];
      const Eigen::Vector3d& q = ring[(i + 1) % ring.size()];
      const Eigen::Vector3d& a = plane.anchor;
      exact::append_difference_product(p[j], a[j], q[k], a[k], 1.0, terms);
      exact::append_difference_product(p[k], a[k], q[j], a[j], -1.0, terms);
    }
    n[axis] = exact::sum(terms);
  }
  plane.normal = n.normalized();
  double height = 0.0;
  for (const auto& p : ring) height += plane.normal.dot(p - plane.anchor);
  plane.offset = height / static_cast<double>(ring.size());
  return plane;
}

// How far points lie outside the hull, by this file's own geometry: distance
// in front of the fitted face planes (solid), off the plane or outside an edge
// (flat polygon), to the segment or to the point. 0 or less when inside.
class OutsideMeasure {
 public:
  explicit OutsideMeasure(const hull::HalfEdgeMesh& mesh) : mesh_(mesh), dim_(mesh.dimension()) {
    if (dim_ == 3) {
      for (hull::Index f = 0; f < mesh.face_count(); ++f) planes_.push_back(fitted_plane(mesh, f));
    } else if (dim_ == 2) {
      planes_.push_back(fitted_plane(mesh, 0));
      // The face lies to the left of e seen from the normal side: e x n
      // points out of the polygon, within its plane.
      for (hull::Index e : mesh.face_edges(0)) {
        LocalPlane side;
        side.anchor = mesh.position(mesh.origin(e));
        side.normal = mesh.edge_vector(e).cross(planes_[0].normal).normalized();
        sides_.push_back(side);
      }
    }
  }

  double operator()(const Eigen::Vector3d& p) const {
    if (dim_ == 0) return (p - mesh_.position(0)).norm();
    if (dim_ == 1) {
      const Eigen::Vector3d a = mesh_.position(0);
      const Eigen::Vector3d d = mesh_.position(1) - a;
      const double t = std::clamp(d.dot(p - a) / d.squaredNorm(), 0.0, 1.0);
      return (t * d - (p - a)).norm();
    }
    double worst = dim_ == 2 ? std::abs(planes_[0].signed_distance(p)) : -std::numeric_limits<double>::infinity();
    for (const LocalPlane& plane : dim_ == 2 ? sides_ : planes_) worst = std::max(worst, plane.signed_distance(p));
    return worst;
  }

 private:
  const hull::HalfEdgeMesh& mesh_;
  int dim_;
  std::vector<LocalPlane> planes_;
  std::vector<LocalPlane> sides_;
};

struct Farthest {
  double distance = 0.0;
  std::size_t index = 0;
};
inline Farthest farthest_outside(const hull::HalfEdgeMesh& mesh, const std::vector<Eigen::Vector3d>& points) {
  const OutsideMeasure measure(mesh);
  Farthest worst{-std::numeric_limits<double>::infinity(), 0};
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double d = measure(points[i]);
    if (d > worst.distance) worst = {d, i};
  }
  return worst;
}

// Bound for hedra's own max_outside_distance, which measures against the
// mesh's world-space planes (normal . x = offset): beyond the containment
// slack, such an offset cannot be represented closer than the rounding of
// |x| far from the origin, so that representational floor is added.
inline double reported_outside_bound(double tolerance, const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d lo = points[0];
  Eigen::Vector3d hi = points[0];
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double far = (0.5 * (lo + hi)).cwiseAbs().sum();
  return kOutsideFactor * (tolerance + 3 * DBL_EPSILON * far);
}

// Volume by the divergence theorem: tetrahedra from one hull vertex r to a fan
// of each face, each determinant det(a - r, b - r, c - r) evaluated exactly
// (error-free differences and products, correctly rounded sum). Relative to a
// vertex of a convex hull every tetrahedron is non-negative (up to the
// tolerance), so summing the rounded tetrahedra loses nothing either. Plain
// floating point gets needles and slivers (a cluster pair 1e-12 wide) wrong
// by orders of magnitude. 0 for a flat or lower-dimensional hull.
inline double mesh_volume(const hull::HalfEdgeMesh& mesh) {
  if (mesh.dimension() != 3) return 0.0;
  const Eigen::Vector3d r = mesh.position(0);
  std::vector<double> terms;
  std::vector<double> tetrahedra;
  auto diff = [&](const Eigen::Vector3d& p, int axis) {
    std::array<double, 2> d{};
    exact::two_sum(p[axis], -r[axis], d[0], d[1]);
    return d;
  };
  for (hull::Index f = 0; f < mesh.face_count(); ++f) {
    std::vector<Eigen::Vector3d> ring;
    for (hull::Index v : mesh.face_vertices(f)) ring.push_back(mesh.position(v));
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
      const Eigen::Vector3d* rows[3] = {&ring[0], &ring[i], &ring[i + 1]};
      terms.clear();
      // det = sum over permutations (x, y, z) of sign * a_x * b_y * c_z.
      static constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
      for (int k = 0; k < 6; ++k) {
        const double sign = k < 3 ? 1.0 : -1.0;
        const auto x = diff(*rows[0], kPerm[k][0]);
        const auto y = diff(*rows[1], kPerm[k][1]);
        const auto z = diff(*rows[2], kPerm[k][2]);
        for (double xi : x) {
          for (double yi : y) {
            double p = 0.0;
            double e = 0.0;
            exact::two_product(xi, yi, p, e);
            for (double w : {p, e}) {
              for (double zi : z) {
                double p2 = 0.0;
                double e2 = 0.0;
                exact::two_product(w, zi, p2, e2);
                if (p2 != 0.0) terms.push_back(sign * p2);
                if (e2 != 0.0) terms.push_back(sign * e2);
              }
            }
          }
        }
      }
      tetrahedra.push_back(exact::sum(terms));
    }
  }
  return exact::sum(tetrahedra) / 6.0;
}

// Area as the sum of the fan triangles' areas (used only for allowances).
inline double mesh_area(const hull::HalfEdgeMesh& mesh) {
  double twice = 0.0;
  for (hull::Index f = 0; f < mesh.face_count(); ++f) {
    std::vector<Eigen::Vector3d> ring;
    for (hull::Index v : mesh.face_vertices(f)) ring.push_back(mesh.position(v));
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) twice += (ring[i] - ring[0]).cross(ring[i + 1] - ring[0]).norm();
  }
  return 0.5 * twice;
}

// Hull vertex positions in lexicographic order (compares hulls of inputs that
// differ in order or duplicates).
inline std::vector<std::tuple<double, double, double>> sorted_positions(const hull::HalfEdgeMesh& mesh) {
  std::vector<std::tuple<double, double, double>> out;
  for (const auto& v : mesh.vertices) out.emplace_back(v.position.x(), v.position.y(), v.position.z());
  std::sort(out.begin(), out.end());
  return out;
}

// Input indices of the hull vertices, sorted.
inline std::vector<hull::Index> sorted_input_indices(const hull::QuickhullResult& r) {
  std::vector<hull::Index> out = r.input_index;
  std::sort(out.begin(), out.end());
  return out;
}

// Combinatorics in input indices: each face as its sorted vertex set, faces
// sorted. Equal signatures mean the same vertices and the same faces.
inline std::vector<std::vector<hull::Index>> face_signature(const hull::QuickhullResult& r) {
  std::vector<std::vector<hull::Index>> faces;
  for (hull::Index f = 0; f < r.mesh.face_count(); ++f) {
    std::vector<hull::Index> face;
    for (hull::Index v : r.mesh.face_vertices(f)) face.push_back(r.input_index[v]);
    std::sort(face.begin(), face.end());
    faces.push_back(std::move(face));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// Empty when every hull vertex is bit-for-bit the input point input_index
// names, the indices are in range and no position repeats; else why not.
inline std::string check_vertices_are_input_points(const hull::QuickhullResult& r,
                                                   const std::vector<Eigen::Vector3d>& points) {
  if (r.input_index.size() != r.mesh.vertex_count())
    return "input_index has " + std::to_string(r.input_index.size()) + " entries for " +
           std::to_string(r.mesh.vertex_count()) + " vertices";
  for (std::size_t v = 0; v < r.input_index.size(); ++v) {
    const hull::Index i = r.input_index[v];
    if (i >= points.size())
      return "vertex " + std::to_string(v) + " maps to input " + std::to_string(i) + " (out of range)";
    const Eigen::Vector3d& p = r.mesh.position(static_cast<hull::Index>(v));
    if (!(p.array() == points[i].array()).all()) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "vertex %zu at (%.17g, %.17g, %.17g) but input %u is (%.17g, %.17g, %.17g)", v,
                    p.x(), p.y(), p.z(), i, points[i].x(), points[i].y(), points[i].z());
      return buf;
    }
  }
  const auto positions = sorted_positions(r.mesh);
  if (std::adjacent_find(positions.begin(), positions.end()) != positions.end()) return "two hull vertices coincide";
  return {};
}

// Empty when `r` passes every check a successful build must pass, else what
// failed: status ok; result.dimension == mesh.dimension(); a tolerance >= 0
// with the mesh's own (validate()'s) no smaller; vertices are input points;
// validate(); every input point within kOutsideFactor * tolerance of the hull
// by this file's measure, and hedra's max_outside_distance within
// reported_outside_bound.
inline std::string soundness_problem(const hull::QuickhullResult& r, const std::vector<Eigen::Vector3d>& points) {
  char buf[320];
  if (!r.ok()) return std::string("status ") + hull::to_string(r.status) + ": " + r.error;
  if (r.dimension != r.mesh.dimension())
    return "result.dimension " + std::to_string(r.dimension) + " but mesh.dimension() " +
           std::to_string(r.mesh.dimension());
  // 0 only for a single distinct point (the extent is 0).
  if (!(r.tolerance >= 0.0) || !(r.mesh.tolerance() >= r.tolerance)) {
    std::snprintf(buf, sizeof buf, "tolerance %.17g, mesh.tolerance() %.17g", r.tolerance, r.mesh.tolerance());
    return buf;
  }
  const std::string why = check_vertices_are_input_points(r, points);
  if (!why.empty()) return why;
  const hull::ValidationReport report = r.mesh.validate();
  if (!report.ok()) return "validate():\n" + report.to_string();
  // Plus what storing the planes in world coordinates adds: mesh.tolerance()
  // is 8 eps + that rounding term (quickhull.hpp).
  const double world_rounding = std::max(0.0, r.mesh.tolerance() - 8 * r.tolerance);
  const double limit = kOutsideFactor * r.tolerance + world_rounding;
  const Farthest mine = farthest_outside(r.mesh, points);
  if (mine.distance > limit) {
    std::snprintf(buf, sizeof buf,
                  "point %zu is %.17g outside = %.3g tolerances (limit %g, own check; %s mesh.tolerance() = %.3g "
                  "tolerances, the documented guarantee)",
                  mine.index, mine.distance, mine.distance / r.tolerance, kOutsideFactor,
                  mine.distance > r.mesh.tolerance() ? "BEYOND" : "within", r.mesh.tolerance() / r.tolerance);
    return buf;
  }
  const double reported = hull::max_outside_distance(r.mesh, points);
  const double bound = reported_outside_bound(r.tolerance, points);
  if (!(reported <= bound)) {
    std::snprintf(buf, sizeof buf, "max_outside_distance %.17g > %.17g (own check: %.17g)", reported, bound,
                  mine.distance);
    return buf;
  }
  return {};
}

// A build that never returns would otherwise only show up as a ctest timeout
// minutes later with nothing to replay. The watchdog is armed around each
// build with a generous deadline (every input here builds in milliseconds);
// when it fires it prints the label (test, seed) and the input at %.17g and
// ends the process with a failure code.
class Watchdog {
 public:
  static Watchdog& instance() {
    static Watchdog* w = new Watchdog;  // never destroyed: its thread outlives static destruction
    return *w;
  }
  void arm(const std::string& label, const std::vector<Eigen::Vector3d>& points, double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    label_ = label;
    points_ = &points;
    deadline_ = std::chrono::steady_clock::now() +
                std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
    armed_ = true;
    wake_.notify_one();
  }
  void disarm() {
    std::lock_guard<std::mutex> lock(mutex_);
    armed_ = false;
  }

 private:
  Watchdog() {
    std::thread([this] { watch(); }).detach();
  }
  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      if (!armed_) {
        wake_.wait(lock);
        continue;
      }
      if (wake_.wait_until(lock, deadline_) == std::cv_status::timeout && armed_ &&
          std::chrono::steady_clock::now() >= deadline_) {
        std::fprintf(stderr, "\nHULL BUILD DID NOT RETURN: %s\n%s", label_.c_str(),
                     points_->size() <= 5000 ? format_points(*points_).c_str() : "(input too large to print)\n");
        std::fflush(stderr);
        std::_Exit(3);
      }
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  bool armed_ = false;
  std::string label_;
  const std::vector<Eigen::Vector3d>* points_ = nullptr;
  std::chrono::steady_clock::time_point deadline_;
};

// builder.build(points) under the watchdog.
inline hull::QuickhullResult guarded_build(hull::QuickhullBuilder& builder, const std::vector<Eigen::Vector3d>& points,
                                           const std::string& label, const hull::QuickhullOptions& options = {}) {
  Watchdog::instance().arm(label, points, 20.0);
  hull::QuickhullResult r = builder.build(points, options);
  Watchdog::instance().disarm();
  return r;
}

// Seed given in HEDRA_REPLAY_SEED, or -1: property tests then run only that
// cloud, printing it in full.
inline long long replay_seed() {
  const char* s = std::getenv("HEDRA_REPLAY_SEED");
  return s ? std::strtoll(s, nullptr, 10) : -1;
}

}  // namespace hedra::test
