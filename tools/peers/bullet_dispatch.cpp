// Loads bullet_dispatch.h's entry points from the Bullet modules (as
// bullet_manifold.cpp loads its own) and converts hedra's shapes and poses.
#include "bullet_dispatch.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <vector>

#include "bullet_dispatch.h"

namespace hedra::peers {
namespace {

struct DispatchModule {
  HedraBulletDispatchPrepare prepare = nullptr;
  HedraBulletDispatchQuery query = nullptr;
  HedraBulletDispatchRelease release = nullptr;
};

const DispatchModule* dispatch_module(bool double_precision) {
  static const auto load = [](const char* env_name, const char* built_path) {
    DispatchModule m;
    const char* path = std::getenv(env_name);
    if (!path || !*path) path = built_path;
    if (void* handle = ::dlopen(path, RTLD_NOW | RTLD_LOCAL)) {
      m.prepare = reinterpret_cast<HedraBulletDispatchPrepare>(::dlsym(handle, "hedra_bullet_dispatch_prepare"));
      m.query = reinterpret_cast<HedraBulletDispatchQuery>(::dlsym(handle, "hedra_bullet_dispatch_query"));
      m.release = reinterpret_cast<HedraBulletDispatchRelease>(::dlsym(handle, "hedra_bullet_dispatch_release"));
    }
    return m;
  };
  static const DispatchModule f32 = load("HEDRA_PEER_BULLET_F32_MODULE", HEDRA_PEER_BULLET_F32_MODULE);
  static const DispatchModule f64 = load("HEDRA_PEER_BULLET_F64_MODULE", HEDRA_PEER_BULLET_F64_MODULE);
  const DispatchModule& m = double_precision ? f64 : f32;
  return m.prepare && m.query && m.release ? &m : nullptr;
}

// Any hedra shape; `points` keeps a hull's vertices alive for the call.
HedraBulletShape describe_any(const collision::Shape& shape, std::vector<double>& points) {
  HedraBulletShape s{};
  s.kind = -1;
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
          for (const Eigen::Vector3d& v : x.hull->vertices()) points.insert(points.end(), {v.x(), v.y(), v.z()});
        }
      },
      shape);
  s.points = points.data();
  s.point_count = points.size() / 3;
  return s;
}

// Row-major rotation, then the position of the shape's (hull's) origin.
void pack(const collision::Shape& shape, const collision::Pose& pose, double* out) {
  Eigen::Vector3d origin = pose.translation;
  if (const auto* poly = std::get_if<collision::Polyhedron>(&shape)) origin = pose.apply(poly->hull->offset());
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = pose.rotation(i, j);
  for (int k = 0; k < 3; ++k) out[9 + k] = origin[k];
}

class Dispatched final : public DispatchedPair {
 public:
  Dispatched(const DispatchModule& m, void* handle, const collision::Shape& a, const collision::Shape& b)
      : module_(m), handle_(handle), a_(a), b_(b) {}
  ~Dispatched() override { module_.release(handle_); }
  Dispatched(const Dispatched&) = delete;
  Dispatched& operator=(const Dispatched&) = delete;

  DispatchAnswer query(const collision::Pose& pose_a, const collision::Pose& pose_b, bool warm) override {
    double pa[12], pb[12];
    pack(a_, pose_a, pa);
    pack(b_, pose_b, pb);
    module_.query(handle_, pa, pb, warm ? 1 : 0, &raw_);
    return {raw_.points, raw_.deepest};
  }
  std::string algorithm() const override { return raw_.algorithm; }

 private:
  const DispatchModule& module_;
  void* handle_;
  collision::Shape a_, b_;
  HedraBulletDispatchResult raw_{};
};

}  // namespace

std::unique_ptr<DispatchedPair> prepare_bullet_dispatch(const collision::Shape& a, const collision::Shape& b,
                                                        bool polyhedral, bool double_precision) {
  const DispatchModule* m = dispatch_module(double_precision);
  if (!m) return nullptr;
  std::vector<double> points_a, points_b;
  const HedraBulletShape sa = describe_any(a, points_a);
  const HedraBulletShape sb = describe_any(b, points_b);
  if (sa.kind < 0 || sb.kind < 0) return nullptr;
  return std::make_unique<Dispatched>(*m, m->prepare(&sa, &sb, polyhedral ? 1 : 0), a, b);
}

}  // namespace hedra::peers
