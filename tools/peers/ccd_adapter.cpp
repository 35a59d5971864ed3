// libccd 2.1 adapters. libccd sees each shape only through callbacks: the
// support point in the world frame (hedra's local support mapping, rotated
// in and out: R s(R^T d) + t) and a centre for MPR. Margins therefore come
// for free (they are part of hedra's support), so every shape is supported.
//
// libccd's conventions: ccdGJKPenetration / ccdMPRPenetration return 0 when
// the objects intersect, with `dir` the unit direction along which obj2 must
// move by `depth` to separate (= hedra's normal from A toward B) and `pos` a
// point midway between the two surfaces; -1 when separated (and no
// distance); -2 when memory ran out. Tolerances are absolute (libccd's
// defaults); max_iterations is unbounded by default, capped here.
#include <ccd/ccd.h>

#include <cmath>
#include <hedra/collision/detail/support.hpp>

#include "adapters.hpp"

namespace hedra::peers {
namespace {

constexpr unsigned long kMaxIterations = 1000;

struct CcdObject {
  const collision::Shape* shape;
  const collision::Pose* pose;
};

void ccd_support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const auto* o = static_cast<const CcdObject*>(obj);
  const Eigen::Vector3d d(dir->v[0], dir->v[1], dir->v[2]);
  const Eigen::Vector3d s = o->pose->apply(collision::support(*o->shape, o->pose->rotation.transpose() * d));
  ccdVec3Set(out, s.x(), s.y(), s.z());
}

void ccd_center(const void* obj, ccd_vec3_t* out) {
  const auto* o = static_cast<const CcdObject*>(obj);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  if (const auto* p = std::get_if<collision::Polyhedron>(o->shape)) c = p->hull->offset();
  c = o->pose->apply(c);
  ccdVec3Set(out, c.x(), c.y(), c.z());
}

ccd_t make_ccd() {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = ccd_support;
  ccd.support2 = ccd_support;
  ccd.center1 = ccd_center;
  ccd.center2 = ccd_center;
  ccd.max_iterations = kMaxIterations;
  return ccd;
}

enum class Algorithm { gjk, gjk_epa, mpr };

PeerResult run(const PeerPair& pair, PeerQuery query, Algorithm algorithm) {
  PeerResult r;
  r.supported = true;
  r.distance = NAN;
  const CcdObject a{&pair.a, &pair.pose_a}, b{&pair.b, &pair.pose_b};
  const ccd_t ccd = make_ccd();
  if (algorithm == Algorithm::gjk || query == PeerQuery::intersect) {
    const int hit = algorithm == Algorithm::mpr ? ccdMPRIntersect(&a, &b, &ccd) : ccdGJKIntersect(&a, &b, &ccd);
    r.ok = true;
    r.intersecting = hit != 0;
    r.status = query == PeerQuery::intersect ? "ok" : "ok (intersect only: libccd GJK has no distance)";
    return r;
  }
  ccd_real_t depth = 0;
  ccd_vec3_t dir, pos;
  ccdVec3Set(&dir, 0, 0, 0);
  ccdVec3Set(&pos, 0, 0, 0);
  const int code = algorithm == Algorithm::mpr ? ccdMPRPenetration(&a, &b, &ccd, &depth, &dir, &pos)
                                               : ccdGJKPenetration(&a, &b, &ccd, &depth, &dir, &pos);
  if (code == -1) {
    r.ok = true;
    r.intersecting = false;
    r.status = "ok (separated: libccd reports no distance)";
    return r;
  }
  if (code != 0) {
    r.status = "libccd error " + std::to_string(code);
    return r;
  }
  r.intersecting = true;
  const Eigen::Vector3d n(dir.v[0], dir.v[1], dir.v[2]), p(pos.v[0], pos.v[1], pos.v[2]);
  if (query == PeerQuery::distance) {  // overlapping: distance 0, no normal
    r.ok = true;
    r.has_distance = true;
    r.distance = 0.0;
    r.status = "ok";
    return r;
  }
  r.has_distance = true;
  r.distance = -depth;
  r.normal = n;
  r.point_a = p + 0.5 * depth * n;
  r.point_b = p - 0.5 * depth * n;
  r.ok = std::isfinite(r.distance) && r.normal.allFinite() && r.point_a.allFinite();
  r.status = r.ok ? "ok" : "libccd returned a non-finite depth, direction or position";
  return r;
}

class CcdPrepared final : public PreparedPair {
 public:
  CcdPrepared(const PeerPair& pair, Algorithm algorithm) : pair_(pair), algorithm_(algorithm) {}
  PeerResult query(PeerQuery query) override { return run(pair_, query, algorithm_); }

 private:
  PeerPair pair_;
  Algorithm algorithm_;
};

}  // namespace

namespace detail {
std::unique_ptr<PreparedPair> prepare_ccd_gjk(const PeerPair& p) {
  return std::make_unique<CcdPrepared>(p, Algorithm::gjk);
}
std::unique_ptr<PreparedPair> prepare_ccd_gjk_epa(const PeerPair& p) {
  return std::make_unique<CcdPrepared>(p, Algorithm::gjk_epa);
}
std::unique_ptr<PreparedPair> prepare_ccd_mpr(const PeerPair& p) {
  return std::make_unique<CcdPrepared>(p, Algorithm::mpr);
}
}  // namespace detail

}  // namespace hedra::peers
