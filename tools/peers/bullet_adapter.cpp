// Bullet adapters: hedra shapes to the plain-C description of
// bullet_module.h, handed to the module of the requested precision. The
// modules are found at the paths CMake bakes in (HEDRA_PEER_BULLET_F32_MODULE,
// HEDRA_PEER_BULLET_F64_MODULE), overridable with the environment variables
// of the same names, and loaded once, lazily, with RTLD_LOCAL so that the
// single- and double-precision Bullet libraries never resolve each other's
// symbols.
#include <dlfcn.h>

#include <cstdlib>
#include <mutex>
#include <vector>

#include "adapters.hpp"
#include "bullet_module.h"

namespace hedra::peers {
namespace {

struct Module {
  HedraBulletPrepare prepare = nullptr;
  HedraBulletQuery query = nullptr;
  HedraBulletRelease release = nullptr;
  HedraBulletToiPrepare toi_prepare = nullptr;
  HedraBulletToiQuery toi_query = nullptr;
  HedraBulletToiRelease toi_release = nullptr;
  std::string error;
};

Module load(const char* env_name, const char* built_path) {
  Module m;
  const char* path = std::getenv(env_name);
  if (!path || !*path) path = built_path;
  void* handle = ::dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = ::dlerror();
    m.error = std::string("unsupported: cannot load Bullet module: ") + (e ? e : path);
    return m;
  }
  m.prepare = reinterpret_cast<HedraBulletPrepare>(::dlsym(handle, "hedra_bullet_prepare"));
  m.query = reinterpret_cast<HedraBulletQuery>(::dlsym(handle, "hedra_bullet_query"));
  m.release = reinterpret_cast<HedraBulletRelease>(::dlsym(handle, "hedra_bullet_release"));
  m.toi_prepare = reinterpret_cast<HedraBulletToiPrepare>(::dlsym(handle, "hedra_bullet_toi_prepare"));
  m.toi_query = reinterpret_cast<HedraBulletToiQuery>(::dlsym(handle, "hedra_bullet_toi_query"));
  m.toi_release = reinterpret_cast<HedraBulletToiRelease>(::dlsym(handle, "hedra_bullet_toi_release"));
  if (!m.prepare || !m.query || !m.release || !m.toi_prepare || !m.toi_query || !m.toi_release)
    m.error = std::string("unsupported: incomplete Bullet module ") + path;
  return m;  // the handle stays open for the life of the process
}

const Module& module(bool double_precision) {
  static const Module f32 = load("HEDRA_PEER_BULLET_F32_MODULE", HEDRA_PEER_BULLET_F32_MODULE);
  static const Module f64 = load("HEDRA_PEER_BULLET_F64_MODULE", HEDRA_PEER_BULLET_F64_MODULE);
  return double_precision ? f64 : f32;
}

// The description of one shape; `points` keeps a hull's vertices alive.
// With `about_origin`, a hull's vertices are given relative to the shape's
// origin (not its centroid), so that a sweep rotates it about that origin.
HedraBulletShape describe(const collision::Shape& shape, const collision::Pose& pose, std::vector<double>& points,
                          bool about_origin = false) {
  HedraBulletShape s{};
  Eigen::Vector3d origin = pose.translation;
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        s.margin = x.margin;
        if constexpr (std::is_same_v<T, collision::Sphere>) {
          s.kind = hedra_bullet_sphere;
          s.radius = x.radius;
        } else if constexpr (std::is_same_v<T, collision::Box>) {
          s.kind = hedra_bullet_box;
          for (int k = 0; k < 3; ++k) s.half_extents[k] = x.half_extents[k];
        } else if constexpr (std::is_same_v<T, collision::Capsule>) {
          s.kind = hedra_bullet_capsule;
          s.radius = x.radius;
          s.half_length = x.half_length;
        } else if constexpr (std::is_same_v<T, collision::Cylinder>) {
          s.kind = hedra_bullet_cylinder;
          s.radius = x.radius;
          s.half_length = x.half_length;
        } else if constexpr (std::is_same_v<T, collision::Cone>) {
          s.kind = hedra_bullet_cone;
          s.radius = x.radius;
          s.half_length = x.half_length;
        } else {
          s.kind = hedra_bullet_hull;
          const Eigen::Vector3d shift = about_origin ? x.hull->offset() : Eigen::Vector3d::Zero();
          for (const Eigen::Vector3d& v : x.hull->vertices()) {
            const Eigen::Vector3d p = v + shift;
            points.insert(points.end(), {p.x(), p.y(), p.z()});
          }
          if (!about_origin) origin = pose.apply(x.hull->offset());
        }
      },
      shape);
  s.points = points.data();
  s.point_count = points.size() / 3;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s.rotation[3 * i + j] = pose.rotation(i, j);
  for (int k = 0; k < 3; ++k) s.translation[k] = origin[k];
  return s;
}

class BulletPrepared final : public PreparedPair {
 public:
  BulletPrepared(const Module& m, void* handle) : module_(m), handle_(handle) {}
  ~BulletPrepared() override { module_.release(handle_); }
  BulletPrepared(const BulletPrepared&) = delete;
  BulletPrepared& operator=(const BulletPrepared&) = delete;

  PeerResult query(PeerQuery query) override {
    HedraBulletResult out{};
    module_.query(handle_, static_cast<int>(query), &out);
    PeerResult r;
    r.supported = true;
    r.ok = out.ok != 0;
    r.intersecting = out.intersecting != 0;
    r.has_distance = out.has_distance != 0;
    r.distance = out.distance;
    r.normal = Eigen::Vector3d(out.normal[0], out.normal[1], out.normal[2]);
    r.point_a = Eigen::Vector3d(out.point_a[0], out.point_a[1], out.point_a[2]);
    r.point_b = Eigen::Vector3d(out.point_b[0], out.point_b[1], out.point_b[2]);
    r.status.assign(out.status);
    return r;
  }

 private:
  const Module& module_;
  void* handle_;
};

std::unique_ptr<PreparedPair> prepare(const PeerPair& pair, bool double_precision, int method) {
  const Module& m = module(double_precision);
  if (!m.error.empty()) return detail::unsupported(m.error.c_str());
  std::vector<double> points_a, points_b;
  const HedraBulletShape a = describe(pair.a, pair.pose_a, points_a);
  const HedraBulletShape b = describe(pair.b, pair.pose_b, points_b);
  return std::make_unique<BulletPrepared>(m, m.prepare(&a, &b, method));
}

// Time of impact (continuous.hpp).
class BulletToiPrepared final : public PreparedSweep {
 public:
  BulletToiPrepared(const Module& m, void* handle) : module_(m), handle_(handle) {}
  ~BulletToiPrepared() override { module_.toi_release(handle_); }
  BulletToiPrepared(const BulletToiPrepared&) = delete;
  BulletToiPrepared& operator=(const BulletToiPrepared&) = delete;

  ToiPeerResult query() override {
    HedraBulletToiResult out{};
    module_.toi_query(handle_, &out);
    ToiPeerResult r;
    r.supported = true;
    r.ok = out.ok != 0;
    r.hit = out.hit != 0;
    r.fraction = out.fraction;
    r.status.assign(out.status);
    return r;
  }

 private:
  const Module& module_;
  void* handle_;
};

bool rotates(const collision::Sweep& s) { return !s.start.rotation.isApprox(s.end.rotation, 0.0); }

std::unique_ptr<PreparedSweep> prepare_toi(const SweepPair& pair, bool double_precision, int method) {
  const Module& m = module(double_precision);
  if (!m.error.empty()) return detail::unsupported_sweep(m.error.c_str());
  if (method < 2 && (rotates(pair.sweep_a) || rotates(pair.sweep_b)))
    return detail::unsupported_sweep("unsupported: a linear cast ignores rotation");
  std::vector<double> pa, pb, pa1, pb1;
  const HedraBulletShape a = describe(pair.a, pair.sweep_a.start, pa, true);
  const HedraBulletShape a1 = describe(pair.a, pair.sweep_a.end, pa1, true);
  const HedraBulletShape b = describe(pair.b, pair.sweep_b.start, pb, true);
  const HedraBulletShape b1 = describe(pair.b, pair.sweep_b.end, pb1, true);
  return std::make_unique<BulletToiPrepared>(m, m.toi_prepare(&a, &a1, &b, &b1, method));
}

}  // namespace

namespace detail {
std::unique_ptr<PreparedSweep> prepare_bullet_f64_gjk_cast(const SweepPair& p) { return prepare_toi(p, true, 0); }
std::unique_ptr<PreparedSweep> prepare_bullet_f64_subsimplex(const SweepPair& p) { return prepare_toi(p, true, 1); }
std::unique_ptr<PreparedSweep> prepare_bullet_f64_continuous(const SweepPair& p) { return prepare_toi(p, true, 2); }
std::unique_ptr<PreparedSweep> prepare_bullet_f32_continuous(const SweepPair& p) { return prepare_toi(p, false, 2); }
std::unique_ptr<PreparedPair> prepare_bullet_f32_gjk_epa(const PeerPair& p) { return prepare(p, false, 0); }
std::unique_ptr<PreparedPair> prepare_bullet_f64_gjk_epa(const PeerPair& p) { return prepare(p, true, 0); }
std::unique_ptr<PreparedPair> prepare_bullet_f32_signed(const PeerPair& p) { return prepare(p, false, 1); }
std::unique_ptr<PreparedPair> prepare_bullet_f64_signed(const PeerPair& p) { return prepare(p, true, 1); }
}  // namespace detail

}  // namespace hedra::peers
