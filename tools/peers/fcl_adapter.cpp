// FCL 0.7 adapters (solvers GST_LIBCCD and GST_INDEP). Shapes become FCL's
// own primitives (Box, Sphere, Capsule, Cylinder and Cone take full lengths;
// all centred, axis z, the cone's apex at +lz/2 as in hedra) and fcl::Convex
// for hulls, built once in prepare from hedra's recentred vertices and faces
// (the pose absorbs the hull's offset). FCL has no margins and rejects
// point, segment and flat hulls: those are "unsupported".
//
// Times of impact: fcl::continuousCollide (continuous.hpp).
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

// With `about_origin`, a hull's vertices are given relative to the shape's
// origin (not its centroid), so that a motion rotates it about that origin.
Converted convert(const collision::Shape& shape, const collision::Pose& pose, bool about_origin = false) {
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
          if (about_origin)
            for (Eigen::Vector3d& v : *vertices) v += hull.offset();
          auto faces = std::make_shared<std::vector<int>>();
          const auto polygons = hull.mesh().polygons();
          for (const auto& polygon : polygons) {
            faces->push_back(static_cast<int>(polygon.size()));
            for (auto v : polygon) faces->push_back(static_cast<int>(v));
          }
          c.geometry = std::make_shared<fcl::Convexd>(vertices, static_cast<int>(polygons.size()), faces);
          if (!about_origin) c.transform.translation() = pose.apply(hull.offset());
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

// Time of impact (continuous.hpp): fcl::continuousCollide on the geometries
// and the four transforms.
class FclToiPrepared final : public PreparedSweep {
 public:
  FclToiPrepared(const Converted& a0, const Converted& a1, const Converted& b0, const Converted& b1,
                 const fcl::ContinuousCollisionRequestd& request)
      : a_(a0.geometry), b_(b0.geometry), request_(request) {
    a_->computeLocalAABB();
    b_->computeLocalAABB();
    ta0_ = a0.transform, ta1_ = a1.transform, tb0_ = b0.transform, tb1_ = b1.transform;
  }

  ToiPeerResult query() override {
    ToiPeerResult r;
    r.supported = true;
    try {
      fcl::ContinuousCollisionResultd result;
      fcl::continuousCollide(a_.get(), ta0_, ta1_, b_.get(), tb0_, tb1_, request_, result);
      r.hit = result.is_collide;
      r.fraction = r.hit ? result.time_of_contact : 1.0;
      r.ok = std::isfinite(r.fraction) && r.fraction >= 0.0;
      r.status = r.ok ? "ok" : "FCL returned no time of contact";
    } catch (const std::exception& e) {
      r.status = std::string("FCL threw: ") + e.what();
    }
    return r;
  }

 private:
  Geometry a_, b_;
  fcl::Transform3d ta0_, ta1_, tb0_, tb1_;
  fcl::ContinuousCollisionRequestd request_;
};

bool rotates(const collision::Sweep& s) { return !s.start.rotation.isApprox(s.end.rotation, 0.0); }

std::unique_ptr<PreparedSweep> prepare_toi(const SweepPair& pair, fcl::CCDMotionType motion,
                                           fcl::CCDSolverType solver) {
  if (motion == fcl::CCDM_TRANS && (rotates(pair.sweep_a) || rotates(pair.sweep_b)))
    return detail::unsupported_sweep("unsupported: a translation motion ignores rotation");
  const Converted a0 = convert(pair.a, pair.sweep_a.start, true), a1 = convert(pair.a, pair.sweep_a.end, true);
  const Converted b0 = convert(pair.b, pair.sweep_b.start, true), b1 = convert(pair.b, pair.sweep_b.end, true);
  if (a0.unsupported) return detail::unsupported_sweep(a0.unsupported);
  if (b0.unsupported) return detail::unsupported_sweep(b0.unsupported);
  // FCL's default request (10 iterations, toc_err 1e-4, GST_LIBCCD) with the motion and solver asked.
  fcl::ContinuousCollisionRequestd request;
  request.ccd_motion_type = motion;
  request.ccd_solver_type = solver;
  return std::make_unique<FclToiPrepared>(a0, a1, b0, b1, request);
}

}  // namespace

namespace detail {
std::unique_ptr<PreparedSweep> prepare_fcl_naive_trans(const SweepPair& p) {
  return prepare_toi(p, fcl::CCDM_TRANS, fcl::CCDC_NAIVE);
}
std::unique_ptr<PreparedSweep> prepare_fcl_ca_trans(const SweepPair& p) {
  return prepare_toi(p, fcl::CCDM_TRANS, fcl::CCDC_CONSERVATIVE_ADVANCEMENT);
}
std::unique_ptr<PreparedSweep> prepare_fcl_ca_linear(const SweepPair& p) {
  return prepare_toi(p, fcl::CCDM_LINEAR, fcl::CCDC_CONSERVATIVE_ADVANCEMENT);
}
std::unique_ptr<PreparedPair> prepare_fcl_libccd(const PeerPair& p) { return prepare(p, fcl::GST_LIBCCD); }
std::unique_ptr<PreparedPair> prepare_fcl_indep(const PeerPair& p) { return prepare(p, fcl::GST_INDEP); }
}  // namespace detail

}  // namespace hedra::peers
