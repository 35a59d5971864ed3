// FCL 0.7 adapters (solvers GST_LIBCCD and GST_INDEP). Shapes become FCL's
// own primitives (Box, Sphere, Capsule, Cylinder and Cone take full lengths;
// all centred, axis z, the cone's apex at +lz/2 as in hedra) and fcl::Convex
// for hulls, built once in prepare from hedra's recentred vertices and faces
// (the pose absorbs the hull's offset). FCL has no margins and rejects
// point, segment and flat hulls: those are "unsupported".
//
// Queries: `distance` is fcl::distance (unsigned; overlapping pairs answer
// 0); `penetration` is fcl::collide first and its contact (depth, normal
// "from o1 to o2", position) when it reports a collision, else the signed
// fcl::distance. Debian's FCL aborts on signed distance of penetrating pairs
// under GST_INDEP and its GST_INDEP contact can come back with a negative
// depth and a normal not in the world frame (field-notes.md): the values are
// reported as FCL gives them, never repaired, so the errors show.
#include <fcl/fcl.h>

#include <cmath>
#include <stdexcept>

#include "adapters.hpp"

namespace hedra::peers {
namespace {

using Geometry = std::shared_ptr<fcl::CollisionGeometryd>;

struct Converted {
  Geometry geometry;
  fcl::Transform3d transform = fcl::Transform3d::Identity();
  const char* unsupported = nullptr;
};

Converted convert(const collision::Shape& shape, const collision::Pose& pose) {
  Converted c;
  c.transform.linear() = pose.rotation;
  c.transform.translation() = pose.translation;
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if (s.margin != 0.0) {
          c.unsupported = "unsupported: FCL has no margin (rounded) shapes";
          return;
        }
        if constexpr (std::is_same_v<T, collision::Sphere>) {
          c.geometry = std::make_shared<fcl::Sphered>(s.radius);
        } else if constexpr (std::is_same_v<T, collision::Box>) {
          c.geometry = std::make_shared<fcl::Boxd>(2.0 * s.half_extents);
        } else if constexpr (std::is_same_v<T, collision::Capsule>) {
          c.geometry = std::make_shared<fcl::Capsuled>(s.radius, 2.0 * s.half_length);
        } else if constexpr (std::is_same_v<T, collision::Cylinder>) {
          c.geometry = std::make_shared<fcl::Cylinderd>(s.radius, 2.0 * s.half_length);
        } else if constexpr (std::is_same_v<T, collision::Cone>) {
          c.geometry = std::make_shared<fcl::Coned>(s.radius, 2.0 * s.half_length);
        } else {
          const collision::ConvexPolyhedron& hull = *s.hull;
          if (hull.dimension() < 3) {
            c.unsupported = "unsupported: FCL rejects point, segment and flat hulls";
            return;
          }
          auto vertices = std::make_shared<std::vector<Eigen::Vector3d>>(hull.vertices());
          auto faces = std::make_shared<std::vector<int>>();
          const auto polygons = hull.mesh().polygons();
          for (const auto& polygon : polygons) {
            faces->push_back(static_cast<int>(polygon.size()));
            for (auto v : polygon) faces->push_back(static_cast<int>(v));
          }
          c.geometry = std::make_shared<fcl::Convexd>(vertices, static_cast<int>(polygons.size()), faces);
          c.transform.translation() = pose.apply(hull.offset());
        }
      },
      shape);
  return c;
}

class FclPrepared final : public PreparedPair {
 public:
  FclPrepared(const Converted& a, const Converted& b, fcl::GJKSolverType solver)
      : a_(a.geometry, a.transform), b_(b.geometry, b.transform), solver_(solver) {}

  PeerResult query(PeerQuery query) override {
    PeerResult r;
    r.supported = true;
    r.distance = NAN;
    try {
      if (query != PeerQuery::distance) {
        fcl::CollisionRequestd request(1, query == PeerQuery::penetration);
        request.gjk_solver_type = solver_;
        fcl::CollisionResultd result;
        fcl::collide(&a_, &b_, request, result);
        r.intersecting = result.isCollision();
        if (query == PeerQuery::intersect) {
          r.ok = true;
          r.status = "ok";
          return r;
        }
        if (r.intersecting) {
          const fcl::Contactd& contact = result.getContact(0);
          r.has_distance = true;
          r.distance = -contact.penetration_depth;
          r.normal = contact.normal;
          r.point_a = contact.pos;
          r.point_b = contact.pos + r.distance * r.normal;
          r.ok = std::isfinite(r.distance) && r.normal.allFinite();
          r.status = r.ok ? "ok (contact position; witnesses approximate)" : "FCL contact not finite";
          return r;
        }
      }
      fcl::DistanceRequestd request(true, query == PeerQuery::penetration);
      request.gjk_solver_type = solver_;
      fcl::DistanceResultd result;
      const double d = fcl::distance(&a_, &b_, request, result);
      r.has_distance = true;
      r.distance = d;
      r.point_a = result.nearest_points[0];
      r.point_b = result.nearest_points[1];
      if (query == PeerQuery::distance && d <= 0.0) {
        r.intersecting = true;
        r.distance = 0.0;
      } else if (d != 0.0) {
        r.normal = (r.point_b - r.point_a) / d;
      }
      r.intersecting = r.distance <= 0.0;
      r.ok = std::isfinite(r.distance) && r.point_a.allFinite() && r.point_b.allFinite();
      r.status = r.ok ? "ok" : "FCL distance not finite";
    } catch (const std::exception& e) {
      r.ok = false;
      r.status = std::string("FCL threw: ") + e.what();
    }
    return r;
  }

 private:
  fcl::CollisionObjectd a_, b_;
  fcl::GJKSolverType solver_;
};

std::unique_ptr<PreparedPair> prepare(const PeerPair& pair, fcl::GJKSolverType solver) {
  const Converted a = convert(pair.a, pair.pose_a), b = convert(pair.b, pair.pose_b);
  if (a.unsupported) return detail::unsupported(a.unsupported);
  if (b.unsupported) return detail::unsupported(b.unsupported);
  return std::make_unique<FclPrepared>(a, b, solver);
}

}  // namespace

namespace detail {
std::unique_ptr<PreparedPair> prepare_fcl_libccd(const PeerPair& p) { return prepare(p, fcl::GST_LIBCCD); }
std::unique_ptr<PreparedPair> prepare_fcl_indep(const PeerPair& p) { return prepare(p, fcl::GST_INDEP); }
}  // namespace detail

}  // namespace hedra::peers
