// The C++ side of the Python overhead measurement (overhead.py): the same
// queries on the same pairs as the Python loop, called from C++ with Pose
// objects made once. Prints one line per case, "name ns_per_call", the
// median of `repeats` timed loops, timed in the thread's CPU time (a loaded
// machine deschedules the loop; CPU time leaves that out). Not a test: a
// measurement.
//
//   build/bin/python_overhead_cpp [calls] [repeats]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <hedra/collision/query.hpp>
#include <vector>

using namespace hedra::collision;

namespace {

// 32 points on a Fibonacci sphere of radius 0.5 (overhead.py makes the same).
std::vector<Eigen::Vector3d> fibonacci_points(int n) {
  std::vector<Eigen::Vector3d> points;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z), phi = golden * i;
    points.emplace_back(0.5 * r * std::cos(phi), 0.5 * r * std::sin(phi), 0.5 * z);
  }
  return points;
}

double thread_ns() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

template <class Query>
double median_ns(long calls, int repeats, Query&& query) {
  std::vector<double> times;
  volatile double sink = 0.0;
  for (int r = 0; r < repeats; ++r) {
    const double start = thread_ns();
    for (long i = 0; i < calls; ++i) sink = sink + query();
    times.push_back((thread_ns() - start) / static_cast<double>(calls));
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const long calls = argc > 1 ? std::atol(argv[1]) : 200000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 7;
  const Shape sphere = Sphere{0.5};
  const Shape box = Box{{0.5, 0.4, 0.3}};
  const Shape hull = Polyhedron{ConvexPolyhedron::build(fibonacci_points(32)).polyhedron};
  const Pose identity = Pose::identity();
  // [x, y, z, qw, qx, qy, qz] = [1.2, 0.3, 0.1, 0.9, 0.1, 0.3, 0.2], as overhead.py
  const Pose moved = Pose::from_quaternion(Eigen::Quaterniond(0.9, 0.1, 0.3, 0.2), {1.2, 0.3, 0.1});
  const Pose overlapping = Pose::from_quaternion(Eigen::Quaterniond(0.9, 0.1, 0.3, 0.2), {0.6, 0.2, 0.1});
  std::printf("sphere_sphere_distance %.1f\n",
              median_ns(calls, repeats, [&] { return distance(sphere, identity, sphere, moved).distance; }));
  std::printf("box_box_intersect %.1f\n",
              median_ns(calls, repeats, [&] { return intersect(box, identity, box, moved).intersecting ? 1.0 : 0.0; }));
  std::printf("box_box_penetration %.1f\n",
              median_ns(calls, repeats, [&] { return penetration(box, identity, box, overlapping).distance; }));
  std::printf("hull_hull_distance %.1f\n",
              median_ns(calls, repeats, [&] { return distance(hull, identity, hull, moved).distance; }));
  return 0;
}
