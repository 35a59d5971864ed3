// Pieces of contact() shared by the general polytope path (contact_polytopes.cpp)
// and the box-box path (box_box.cpp, box_face.cpp), so that both give the
// same answers from one definition:
//   choose_axis   which SAT axis becomes the manifold's: faces before edges,
//                 A's face the incumbent, a challenger winning only by the
//                 face bias, B's face kept while the cache names it.
//   segment_exit  how far a ray runs inside a capsule about a segment (the
//                 rounded depths of margins).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <hedra/collision/detail/sat.hpp>
#include <hedra/collision/manifold.hpp>
#include <limits>

namespace hedra::collision::detail {

// Face axes first, then the edge axis, each challenger beating the
// incumbent by the bias; A's face is the incumbent. B's face is kept
// instead when the pair's cache says it was the reference last frame and
// it still holds with B's face as the incumbent: without that memory a
// slide that carries the two faces' separations across the bias swaps the
// reference face although the same faces touch, and renames every point.
// (Only a choice of A's face is ever replaced so: were B's face not to
// hold, the choice is the one without the cache.) Candidates: any struct
// with SatAxis members face_a, face_b and edge.
template <class Candidates>
SatAxis choose_axis(const Candidates& c, const ContactCache* cache, const ContactSettings& settings, double scale) {
  const auto bias = [&](double sep) { return settings.relative_bias * std::abs(sep) + settings.absolute_bias * scale; };
  const auto pick = [&](const SatAxis& incumbent, const SatAxis& challenger) {
    const SatAxis* best = &incumbent;
    if (challenger.separation > incumbent.separation + bias(incumbent.separation)) best = &challenger;
    if (c.edge.kind == SatAxisKind::edge && c.edge.separation > best->separation + bias(best->separation))
      best = &c.edge;
    return best;
  };
  const bool keep_b = cache && cache->axis == SatAxisKind::face_b && cache->feature == c.face_b.feature_b;
  if (keep_b && pick(c.face_b, c.face_a) == &c.face_b) return c.face_b;
  return *pick(c.face_a, c.face_b);
}

// How far the ray p + t d (d unit, p within r of the segment a-b) runs
// inside the capsule of radius r around a-b: the later exit of the ball at
// a and of the cylinder around a-b (where its exit lies between a and b).
// The ball at b is the ball at a of the neighbouring edge (a capsule: call
// it with the ends swapped too).
inline double segment_exit(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b, double r) {
  double t = -std::numeric_limits<double>::infinity();
  const Eigen::Vector3d w = p - a;
  const double bq = d.dot(w), disc = bq * bq - (w.squaredNorm() - r * r);
  if (disc >= 0.0) t = -bq + std::sqrt(disc);
  const Eigen::Vector3d ab = b - a;
  const double len = ab.norm();
  if (!(len > 0.0)) return t;
  const Eigen::Vector3d u = ab / len;
  const Eigen::Vector3d dp = d - d.dot(u) * u, wp = w - w.dot(u) * u;
  const double qa = dp.squaredNorm(), qb = dp.dot(wp), qd = qb * qb - qa * (wp.squaredNorm() - r * r);
  if (qa > 0.0 && qd >= 0.0) {
    const double tc = (-qb + std::sqrt(qd)) / qa;
    const double along = (w + tc * d).dot(u);
    if (along >= 0.0 && along <= len) t = std::max(t, tc);
  }
  return t;
}

}  // namespace hedra::collision::detail
