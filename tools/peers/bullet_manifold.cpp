// Bullet's polyhedral contact path behind hedra's types (bullet_manifold.hpp).
// The Bullet modules are the ones bullet_adapter.cpp loads (dlopen returns
// the same handle); only the manifold entry points are looked up here.
#include "bullet_manifold.hpp"

#include <dlfcn.h>

#include <cstdlib>

#include "bullet_module.h"

namespace hedra::peers {
namespace {

struct ManifoldModule {
  HedraBulletManifoldPrepare prepare = nullptr;
  HedraBulletManifoldQuery query = nullptr;
  HedraBulletManifoldRelease release = nullptr;
  std::string error;
};

ManifoldModule load(const char* env_name, const char* built_path) {
  ManifoldModule m;
  const char* path = std::getenv(env_name);
  if (!path || !*path) path = built_path;
  void* handle = ::dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = ::dlerror();
    m.error = std::string("unsupported: cannot load Bullet module: ") + (e ? e : path);
    return m;
  }
  m.prepare = reinterpret_cast<HedraBulletManifoldPrepare>(::dlsym(handle, "hedra_bullet_manifold_prepare"));
  m.query = reinterpret_cast<HedraBulletManifoldQuery>(::dlsym(handle, "hedra_bullet_manifold_query"));
  m.release = reinterpret_cast<HedraBulletManifoldRelease>(::dlsym(handle, "hedra_bullet_manifold_release"));
  if (!m.prepare || !m.query || !m.release) m.error = std::string("unsupported: no manifold entry points in ") + path;
  return m;
}

const ManifoldModule& module(bool double_precision) {
  static const ManifoldModule f32 = load("HEDRA_PEER_BULLET_F32_MODULE", HEDRA_PEER_BULLET_F32_MODULE);
  static const ManifoldModule f64 = load("HEDRA_PEER_BULLET_F64_MODULE", HEDRA_PEER_BULLET_F64_MODULE);
  return double_precision ? f64 : f32;
}

// Boxes and polyhedra only (kind -1 otherwise); `points` keeps a hull's vertices.
HedraBulletShape describe(const collision::Shape& shape, const collision::Pose& pose, std::vector<double>& points) {
  HedraBulletShape s{};
  s.kind = -1;
  Eigen::Vector3d origin = pose.translation;
  if (const auto* box = std::get_if<collision::Box>(&shape)) {
    s.kind = hedra_bullet_box;
    s.margin = box->margin;
    for (int k = 0; k < 3; ++k) s.half_extents[k] = box->half_extents[k];
  } else if (const auto* poly = std::get_if<collision::Polyhedron>(&shape)) {
    s.kind = hedra_bullet_hull;
    s.margin = poly->margin;
    for (const Eigen::Vector3d& v : poly->hull->vertices()) points.insert(points.end(), {v.x(), v.y(), v.z()});
    origin = pose.apply(poly->hull->offset());
  }
  s.points = points.data();
  s.point_count = points.size() / 3;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s.rotation[3 * i + j] = pose.rotation(i, j);
  for (int k = 0; k < 3; ++k) s.translation[k] = origin[k];
  return s;
}

class Prepared final : public PreparedManifold {
 public:
  Prepared(const ManifoldModule& m, void* handle) : module_(m), handle_(handle) {}
  ~Prepared() override { module_.release(handle_); }
  Prepared(const Prepared&) = delete;
  Prepared& operator=(const Prepared&) = delete;

  void query(double max_distance, PeerManifold& out) override {
    module_.query(handle_, max_distance, &raw_);
    out.supported = raw_.supported != 0;
    out.separated = raw_.separated != 0;
    out.total = raw_.total;
    out.points.resize(static_cast<std::size_t>(raw_.count));
    out.status = out.supported ? "ok" : "unsupported: boxes and polyhedra only";
    for (int k = 0; k < raw_.count; ++k) {
      PeerContactPoint& p = out.points[static_cast<std::size_t>(k)];
      p.point = Eigen::Vector3d(raw_.point[k][0], raw_.point[k][1], raw_.point[k][2]);
      // Bullet's normal "on B" points from B toward A; its depth is a
      // signed distance.
      p.normal = -Eigen::Vector3d(raw_.normal_on_b[k][0], raw_.normal_on_b[k][1], raw_.normal_on_b[k][2]);
      p.depth = -raw_.distance[k];
    }
  }

 private:
  const ManifoldModule& module_;
  void* handle_;
  HedraBulletContacts raw_{};
};

class Unsupported final : public PreparedManifold {
 public:
  explicit Unsupported(std::string why) : why_(std::move(why)) {}
  void query(double, PeerManifold& out) override {
    out = PeerManifold{};
    out.status = why_;
  }

 private:
  std::string why_;
};

// The moving-pair entry points of the same modules.
struct MovingModule {
  HedraBulletMovingPrepare prepare = nullptr;
  HedraBulletMovingQuery query = nullptr;
  HedraBulletMovingRelease release = nullptr;
};

const MovingModule* moving_module(bool double_precision) {
  static const auto load_moving = [](const char* env_name, const char* built_path) {
    MovingModule m;
    const char* path = std::getenv(env_name);
    if (!path || !*path) path = built_path;
    if (void* handle = ::dlopen(path, RTLD_NOW | RTLD_LOCAL)) {
      m.prepare = reinterpret_cast<HedraBulletMovingPrepare>(::dlsym(handle, "hedra_bullet_moving_prepare"));
      m.query = reinterpret_cast<HedraBulletMovingQuery>(::dlsym(handle, "hedra_bullet_moving_query"));
      m.release = reinterpret_cast<HedraBulletMovingRelease>(::dlsym(handle, "hedra_bullet_moving_release"));
    }
    return m;
  };
  static const MovingModule f32 = load_moving("HEDRA_PEER_BULLET_F32_MODULE", HEDRA_PEER_BULLET_F32_MODULE);
  static const MovingModule f64 = load_moving("HEDRA_PEER_BULLET_F64_MODULE", HEDRA_PEER_BULLET_F64_MODULE);
  const MovingModule& m = double_precision ? f64 : f32;
  return m.prepare && m.query && m.release ? &m : nullptr;
}

class Moving final : public MovingPair {
 public:
  Moving(const MovingModule& m, void* handle, const collision::Shape& a, const collision::Shape& b)
      : module_(m), handle_(handle), a_(a), b_(b) {}
  ~Moving() override { module_.release(handle_); }
  Moving(const Moving&) = delete;
  Moving& operator=(const Moving&) = delete;

  PeerResult query(const collision::Pose& pose_a, const collision::Pose& pose_b, bool warm) override {
    double pa[12], pb[12];
    pack(a_, pose_a, pa);
    pack(b_, pose_b, pb);
    HedraBulletResult raw{};
    module_.query(handle_, pa, pb, warm ? 1 : 0, &raw);
    PeerResult r;
    r.supported = true;
    r.ok = raw.ok != 0;
    r.intersecting = raw.intersecting != 0;
    r.has_distance = raw.has_distance != 0;
    r.distance = raw.distance;
    r.normal = Eigen::Vector3d(raw.normal[0], raw.normal[1], raw.normal[2]);
    r.point_a = Eigen::Vector3d(raw.point_a[0], raw.point_a[1], raw.point_a[2]);
    r.point_b = Eigen::Vector3d(raw.point_b[0], raw.point_b[1], raw.point_b[2]);
    r.status = raw.status;
    return r;
  }

 private:
  // Row-major rotation, then the position of the shape's (hull's) origin.
  static void pack(const collision::Shape& shape, const collision::Pose& pose, double* out) {
    Eigen::Vector3d origin = pose.translation;
    if (const auto* poly = std::get_if<collision::Polyhedron>(&shape)) origin = pose.apply(poly->hull->offset());
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out[3 * i + j] = pose.rotation(i, j);
    for (int k = 0; k < 3; ++k) out[9 + k] = origin[k];
  }
  const MovingModule& module_;
  void* handle_;
  collision::Shape a_, b_;
};

}  // namespace

std::unique_ptr<MovingPair> prepare_bullet_moving(const collision::Shape& a, const collision::Shape& b,
                                                  bool double_precision) {
  const MovingModule* m = moving_module(double_precision);
  if (!m) return nullptr;
  std::vector<double> points_a, points_b;
  const HedraBulletShape sa = describe(a, collision::Pose::identity(), points_a);
  const HedraBulletShape sb = describe(b, collision::Pose::identity(), points_b);
  if (sa.kind < 0 || sb.kind < 0) return nullptr;
  return std::make_unique<Moving>(*m, m->prepare(&sa, &sb), a, b);
}

std::unique_ptr<PreparedManifold> prepare_bullet_manifold(const PeerPair& pair, bool double_precision) {
  const ManifoldModule& m = module(double_precision);
  if (!m.error.empty()) return std::make_unique<Unsupported>(m.error);
  std::vector<double> points_a, points_b;
  const HedraBulletShape a = describe(pair.a, pair.pose_a, points_a);
  const HedraBulletShape b = describe(pair.b, pair.pose_b, points_b);
  if (a.kind < 0 || b.kind < 0) return std::make_unique<Unsupported>("unsupported: boxes and polyhedra only");
  return std::make_unique<Prepared>(m, m.prepare(&a, &b));
}

}  // namespace hedra::peers
