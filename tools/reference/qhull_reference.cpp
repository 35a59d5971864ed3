// qhull (libqhull_r) behind hedra's reference interface; see
// qhull_reference.hpp. The pattern is qhull's documented one (user_r.c):
// qh_zero, qh_new_qhull (which sets its own setjmp and returns an exit code
// instead of exiting), read the facet list, then qh_freeqhull(!qh_ALL) +
// qh_memfreeshort. The one extra qhull call made afterwards, qh_getarea, runs
// under our own setjmp with qh->NOerrexit cleared, exactly as qh_new_qhull
// does, so an error in it longjmps back here instead of calling exit(). No C++
// object is created between a setjmp and a possible longjmp.
#include "qhull_reference.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace hedra::reference {
namespace {

// qhull's error FILE, backed by memory; text() closes it and returns what
// qhull wrote.
class ErrorStream {
 public:
  ErrorStream() : file_(open_memstream(&buffer_, &size_)) {}
  ~ErrorStream() {
    close();
    std::free(buffer_);
  }
  ErrorStream(const ErrorStream&) = delete;
  ErrorStream& operator=(const ErrorStream&) = delete;

  FILE* file() const { return file_; }
  std::string text() {
    close();
    return buffer_ ? std::string(buffer_, size_) : std::string();
  }

 private:
  void close() {
    if (file_) std::fclose(file_);
    file_ = nullptr;
  }
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  FILE* file_ = nullptr;
};

std::vector<char> qhull_command(const char* options) {
  std::string command = "qhull";
  if (options && *options) {
    command += ' ';
    command += options;
  }
  return std::vector<char>(command.c_str(), command.c_str() + command.size() + 1);
}

// Frees everything qhull allocated; returns the long memory it could not free.
int free_qhull(qhT* qh) {
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0;
  int totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  return totlong;
}

// qh_getarea under a setjmp of our own (see the note at the top).
int compute_area_and_volume(qhT* qh) {
  int code = setjmp(qh->errexit);
  if (code == 0) {
    qh->NOerrexit = False;
    qh_getarea(qh, qh->facet_list);
  }
  qh->NOerrexit = True;
  return code;
}

// Sorts a facet's vertices counter-clockwise around its outward normal.
void sort_around_normal(std::vector<int>& polygon, const std::vector<Eigen::Vector3d>& points,
                        const Eigen::Vector3d& normal) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int i : polygon) centre += points[static_cast<std::size_t>(i)];
  centre /= static_cast<double>(polygon.size());
  // Any unit vector perpendicular to the normal, then its right-handed partner.
  Eigen::Vector3d u = std::abs(normal.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  u = (u - normal * normal.dot(u)).normalized();
  const Eigen::Vector3d v = normal.cross(u);
  std::vector<std::pair<double, int>> keyed;
  keyed.reserve(polygon.size());
  for (int i : polygon) {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(i)] - centre;
    keyed.emplace_back(std::atan2(d.dot(v), d.dot(u)), i);
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t k = 0; k < keyed.size(); ++k) polygon[k] = keyed[k].second;
}

// Reads the finished hull out of qh into `out` (no qhull call that can fail).
void read_hull(qhT* qh, const std::vector<Eigen::Vector3d>& points, QhullHull& out) {
  facetT* facet = nullptr;
  vertexT* vertex = nullptr;
  vertexT** vertexp = nullptr;

  FORALLvertices { out.vertices.push_back(qh_pointid(qh, vertex->point)); }
  std::sort(out.vertices.begin(), out.vertices.end());

  FORALLfacets {
    std::vector<int> polygon;
    FOREACHvertex_(facet->vertices) { polygon.push_back(qh_pointid(qh, vertex->point)); }
    const Eigen::Vector3d normal(facet->normal[0], facet->normal[1], facet->normal[2]);
    sort_around_normal(polygon, points, normal);
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      out.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
      out.triangle_planes.emplace_back(normal.x(), normal.y(), normal.z(), facet->offset);
    }
    out.facets.push_back(std::move(polygon));
    if (facet->coplanarset) out.coplanar_points += static_cast<std::size_t>(qh_setsize(qh, facet->coplanarset));
    if (facet->tricoplanar) ++out.tricoplanar_facets;
    if (!facet->simplicial) ++out.merged_facets;
  }
  out.facet_count = out.facets.size();
  out.max_outside = qh->max_outside;
}

bool all_finite(const std::vector<Eigen::Vector3d>& points, std::string& message) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      message = "hedra reference: point " + std::to_string(i) + " is not finite; not passed to qhull";
      return false;
    }
  }
  return true;
}

}  // namespace

QhullHull qhull_hull(const std::vector<Eigen::Vector3d>& points, const char* options) {
  QhullHull out;
  out.options = options ? options : "";
  if (points.empty()) {
    // qh_new_qhull treats (0 points, null array) as "initialise only".
    out.exit_code = -1;
    out.messages = "hedra reference: no points";
    return out;
  }
  if (!all_finite(points, out.messages)) {
    out.exit_code = -1;
    return out;
  }

  std::vector<coordT> coords(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) coords[3 * i + static_cast<std::size_t>(k)] = points[i][k];
  }
  std::vector<char> command = qhull_command(options);
  ErrorStream errors;
  auto qh = std::make_unique<qhT>();
  qh_zero(qh.get(), errors.file());
  int code = qh_new_qhull(qh.get(), 3, static_cast<int>(points.size()), coords.data(), False, command.data(), nullptr,
                          errors.file());
  if (code == 0) code = compute_area_and_volume(qh.get());
  if (code == 0) {
    read_hull(qh.get(), points, out);
    out.volume = qh->totvol;
    out.area = qh->totarea;
  }
  out.leaked_bytes = free_qhull(qh.get());
  out.messages = errors.text();
  out.exit_code = code;
  out.ok = code == 0;
  if (!out.ok) {
    out.vertices.clear();
    out.triangles.clear();
    out.triangle_planes.clear();
    out.facets.clear();
  }
  return out;
}

long qhull_build_only(const Eigen::Vector3d* points, std::size_t count, const char* options) {
  if (count == 0) return -1;
  thread_local std::vector<coordT> coords;
  coords.resize(3 * count);
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(coordT), "Vector3d must be three packed doubles");
  std::memcpy(coords.data(), points[0].data(), 3 * count * sizeof(coordT));
  std::vector<char> command = qhull_command(options);
  ErrorStream errors;
  auto qh = std::make_unique<qhT>();
  qh_zero(qh.get(), errors.file());
  const int code =
      qh_new_qhull(qh.get(), 3, static_cast<int>(count), coords.data(), False, command.data(), nullptr, errors.file());
  const long vertex_count = code == 0 ? static_cast<long>(qh->num_vertices) : -1;
  free_qhull(qh.get());
  return vertex_count;
}

}  // namespace hedra::reference
