// exact_first_contact: see first_contact.hpp.
#include "first_contact.hpp"

#include <algorithm>
#include <cmath>

namespace hedra::reference {

collision::Pose Motion::at(double t) const {
  return collision::Pose::from_quaternion(q0.slerp(t, q1), p0 + t * (p1 - p0));
}

double reach(const collision::Shape& shape) {
  struct Visitor {
    double operator()(const collision::Sphere& s) const { return s.radius + s.margin; }
    double operator()(const collision::Box& s) const { return s.half_extents.norm() + s.margin; }
    double operator()(const collision::Capsule& s) const { return s.half_length + s.radius + s.margin; }
    double operator()(const collision::Cylinder& s) const { return std::hypot(s.radius, s.half_length) + s.margin; }
    double operator()(const collision::Cone& s) const { return std::hypot(s.radius, s.half_length) + s.margin; }
    double operator()(const collision::Polyhedron& s) const {
      double r = 0.0;
      for (const Eigen::Vector3d& v : s.hull->vertices()) r = std::max(r, (v + s.hull->offset()).norm());
      return r + s.margin;
    }
  };
  return std::visit(Visitor{}, shape);
}

double distance_rate_bound(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb) {
  return ((mb.p1 - mb.p0) - (ma.p1 - ma.p0)).norm() + ma.angle() * reach(a) + mb.angle() * reach(b);
}

DistanceBracket distance_at(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb,
                            double t) {
  const ExactResult r = exact_signed_distance(a, ma.at(t), b, mb.at(t));
  DistanceBracket out;
  out.ok = r.ok;
  out.reason = r.reason;
  out.lower = r.distance - r.error_bound;
  out.upper = r.distance + r.error_bound;
  return out;
}

namespace {

// The trace from below: the first t whose lower bound is within the stop
// distance of the target (never after the first contact).
void trace_early(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb,
                 const FirstContactSettings& s, double size, FirstContact& out) {
  double t = 0.0;
  for (int k = 0;; ++k) {
    const DistanceBracket d = distance_at(a, ma, b, mb, t);
    ++out.steps;
    if (!d.ok) {
      out.ok = false;
      out.reason = d.reason;
      return;
    }
    out.min_gap = std::min(out.min_gap, d.lower - s.target);
    if (t == 0.0 && d.upper <= s.target) {
      out.initially = out.contact = true;
      out.early = out.late = 0.0;
      return;
    }
    if (d.lower - s.target <= s.stop * size) break;
    if (k == s.max_steps) {
      out.exhausted = true;
      break;
    }
    t += (d.lower - s.target) / out.rate;
    if (t > 1.0) return;  // separated all the way
  }
  out.contact = true;
  out.early = t;
}

// Doubling probes after `early` until the pair is certainly within the target.
void probe_late(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb,
                const FirstContactSettings& s, double size, FirstContact& out) {
  for (double step = 1e-14 * size / out.rate; out.early + step <= 1.0; step *= 2.0) {
    const DistanceBracket d = distance_at(a, ma, b, mb, out.early + step);
    ++out.steps;
    if (d.ok && d.upper <= s.target) {
      out.late = out.early + step;
      return;
    }
  }
}

}  // namespace

FirstContact exact_first_contact(const collision::Shape& a, const Motion& ma, const collision::Shape& b,
                                 const Motion& mb, const FirstContactSettings& settings) {
  FirstContact out;
  out.rate = distance_rate_bound(a, ma, b, mb);
  const double size = settings.size > 0.0 ? settings.size : std::max(reach(a), reach(b));
  trace_early(a, ma, b, mb, settings, size, out);
  if (out.ok && out.contact && !out.initially && out.rate > 0.0) probe_late(a, ma, b, mb, settings, size, out);
  return out;
}

double contact_tolerance(double size, double far) {
  return 1e-9 * size + 64.0 * std::numeric_limits<double>::epsilon() * far;
}

namespace {

// Whether the pair, within the target from `late` on, gets deeper than the
// tolerance (probes at late + doubling steps).
bool deeper_than(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb,
                 const FirstContact& contact, double target, double size, double tolerance) {
  for (double step = std::max(tolerance, 1e-14 * size) / contact.rate; contact.late + step <= 1.0; step *= 2.0) {
    const DistanceBracket d = distance_at(a, ma, b, mb, contact.late + step);
    if (d.ok && d.upper < target - tolerance) return true;
  }
  return false;
}

}  // namespace

ContactVerdict judge_contact(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb,
                             const FirstContact& contact, double target, double size, double tolerance, bool hit,
                             double fraction) {
  ContactVerdict v;
  const double L = contact.rate;
  if (contact.initially) {
    v.tunnelled = !hit || fraction * L > tolerance;
    v.error = hit ? fraction * L / size : 0.0;
    v.through = !hit || v.error > 1e-3;
    return v;
  }
  const bool certain = contact.contact && std::isfinite(contact.late);
  if (!hit) {
    v.tunnelled = v.through = certain && deeper_than(a, ma, b, mb, contact, target, size, tolerance);
    return v;
  }
  if (certain && (fraction - contact.late) * L > tolerance) {
    v.tunnelled = true;
    v.error = (fraction - contact.late) * L / size;
    v.through = v.error > 1e-3;
    return v;
  }
  if (contact.contact && fraction <= contact.early) {
    v.error = (contact.early - fraction) * L / size;
    return v;
  }
  if (certain) return v;  // within [early, late]
  // After a touch's early bound, or no contact at all: the pair must be within the tolerance there.
  const DistanceBracket d = distance_at(a, ma, b, mb, fraction);
  v.false_hit = d.ok && d.lower > target + tolerance;
  return v;
}

}  // namespace hedra::reference
