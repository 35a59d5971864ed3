// The families of workloads.hpp: generators and reference-steered placement.
#include "cli/bench/workloads.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>

namespace hedra::tool::bench {

namespace {

using Vec = Eigen::Vector3d;
using Mat = Eigen::Matrix3d;
using collision::Pose;
using collision::Shape;

// ---- randomness ---------------------------------------------------------------

// FNV-1a of the family name: each family draws from its own stream.
std::uint64_t hash_name(const std::string& name) {
  std::uint64_t h = 1469598103934665603ull;
  for (const char c : name) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return h;
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(engine_() >> 11) * 0x1.0p-53); }
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  int integer(int lo, int hi) { return lo + static_cast<int>(engine_() % static_cast<std::uint64_t>(hi - lo + 1)); }
  Vec unit() {
    for (;;) {
      const Vec q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const double n = q.norm();
      if (n <= 1.0 && n > 1e-3) return q / n;
    }
  }
  Mat rotation() {
    const Eigen::Quaterniond q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    return q.normalized().toRotationMatrix();
  }

 private:
  std::mt19937_64 engine_;
};

// ---- bodies -------------------------------------------------------------------

// A shape with its input points (polyhedra) and the radius of a ball about
// its local origin that holds it.
struct Body {
  Shape shape;
  std::vector<Vec> points;
  double radius = 0.0;
  bool ok = true;
};

Body primitive(const Shape& shape) { return Body{shape, {}, collision::bounding_radius(shape), true}; }

Body hull_body(std::vector<Vec> points, double margin = 0.0) {
  Body body;
  auto built = collision::ConvexPolyhedron::build(points);
  body.ok = built.ok();
  if (!body.ok) return body;
  body.shape = collision::Polyhedron{built.polyhedron, margin};
  for (const Vec& p : points) body.radius = std::max(body.radius, p.norm());
  body.radius += margin;
  body.points = std::move(points);
  return body;
}

// n points on the ellipsoid with semi-axes `axes` (every one a vertex).
Body ellipsoid_hull(Rng& rng, int n, const Vec& axes, double margin = 0.0) {
  std::vector<Vec> points;
  for (int i = 0; i < n; ++i) points.push_back(rng.unit().cwiseProduct(axes));
  return hull_body(std::move(points), margin);
}

Body random_poly(Rng& rng) {
  const Vec axes(rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5));
  return ellipsoid_hull(rng, rng.integer(8, 64), axes);
}

Body box(const Vec& half, double margin = 0.0) { return primitive(collision::Box{half, margin}); }
// A capsule whose half length is drawn before its radius (the families'
// seeded draws keep their order, so every pair stays the pair it was).
template <class Draw>
collision::Capsule capsule_drawn(Draw& r, double h_lo, double h_hi, double r_lo, double r_hi) {
  const double half_length = r(h_lo, h_hi);
  const double radius = r(r_lo, r_hi);
  return collision::Capsule{radius, half_length, 0.0};
}

// Rotation by `angle` about the unit `axis`.
Mat about(const Vec& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

// ---- cases and steering ---------------------------------------------------------

BenchCase make_case(const std::string& family, std::string label, const Body& a, const Pose& pose_a, const Body& b,
                    const Pose& pose_b) {
  BenchCase c;
  c.family = family;
  c.label = std::move(label);
  c.a = a.shape;
  c.b = b.shape;
  c.pose_a = pose_a;
  c.pose_b = pose_b;
  c.points_a = a.points;
  c.points_b = b.points;
  return c;
}

// B placed from A's centre along `direction`, clear of A by `gap` plus the
// radii of both bounding balls.
BenchCase apart(const std::string& family, std::string label, const Body& a, const Mat& rotation_a, const Body& b,
                const Mat& rotation_b, const Vec& direction, double gap = 0.1) {
  return make_case(family, std::move(label), a, Pose{rotation_a, Vec::Zero()}, b,
                   Pose{rotation_b, direction * (a.radius + b.radius + gap)});
}

// Moves B along the reference's normal until the reference's signed distance
// is `target` (within 1e-12 of the size, at most `passes` moves); the case's
// reference is the one at the final pose. False when the reference failed.
bool steer(BenchCase& c, double target, int passes = 4) {
  for (int pass = 0; pass < passes; ++pass) {
    const ReferenceAnswer r = case_reference(c);
    if (!r.exact.ok) {
      c.reference = r;
      return false;
    }
    const double delta = target - r.exact.distance;
    if (std::abs(delta) <= 1e-12 * r.pair_size) {
      c.reference = r;
      return true;
    }
    c.pose_b.translation += delta * r.exact.normal;
  }
  c.reference = case_reference(c);
  return c.reference.exact.ok;
}

// ---- the families ---------------------------------------------------------------

// Each family's generator makes case i (0 <= i < count) from the stream; the
// swept parameter cycles fastest, the kind of pair along a diagonal, so
// that the first few cases (the quick run) already cover both. (Found by the
// first full run: kind (i + i / p) % 2 with p = 7 tied the kind to the
// parameter, every offset of the far family being all apart or all deep.)
struct Plan {
  std::vector<double> parameters;  // empty: none swept
  int kinds = 1;
  int count = 0;
};

std::size_t parameter_index(const Plan& plan, int i) {
  return plan.parameters.empty() ? 0 : static_cast<std::size_t>(i) % plan.parameters.size();
}
// Kind (parameter index + repetition): over the repetitions every parameter
// value meets every kind, and the first repetition already spreads the kinds.
int kind_index(const Plan& plan, int i) {
  const int p = plan.parameters.empty() ? 1 : static_cast<int>(plan.parameters.size());
  return (i % p + i / p) % plan.kinds;
}
// Alternates apart / overlapping over the repetitions of one (parameter, kind).
bool overlapping(const Plan& plan, int i) {
  const int p = plan.parameters.empty() ? 1 : static_cast<int>(plan.parameters.size());
  return ((i / (p * plan.kinds)) + i) % 2 == 1;
}

std::vector<double> decades(int from, int to) {
  std::vector<double> out;
  for (int k = from; k <= to; ++k) out.push_back(std::pow(10.0, k));
  return out;
}

const char* const kSep = "separated";
const char* const kPen = "penetrating";

struct Generator {
  std::string family;
  Rng rng;
  bool quick = false;
  std::map<int, Body> large_hulls;  // large-hull: one hull per vertex count

  BenchCase poly(int i, bool penetrating) {
    const Body a = random_poly(rng), b = random_poly(rng);
    BenchCase c = apart(family,
                        std::string("hulls of ") + std::to_string(a.points.size()) + " and " +
                            std::to_string(b.points.size()) + " vertices, " + (penetrating ? kPen : kSep),
                        a, rng.rotation(), b, rng.rotation(), rng.unit());
    const double target = penetrating ? -rng.log_uniform(1e-3, 0.3) : rng.log_uniform(1e-3, 1.0);
    steer(c, target);
    (void)i;
    return c;
  }

  BenchCase touching(int kind) {
    switch (kind) {
      case 0: {
        const Body a = random_poly(rng), b = random_poly(rng);
        BenchCase c =
            apart(family, "hull on hull (a vertex on a face)", a, rng.rotation(), b, rng.rotation(), rng.unit());
        steer(c, 0.0);
        return c;
      }
      case 1: {  // exact by construction (dyadic sizes)
        const Body a = box(Vec(1, 1, 0.5)), b = box(Vec(0.5, 0.375, 0.25));
        const Vec t(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), 0.75);
        BenchCase c =
            make_case(family, "box face on box face", a, Pose{}, b, Pose{about(Vec::UnitZ(), rng.uniform(0, 1.5)), t});
        c.reference = case_reference(c);
        return c;
      }
      case 2: {
        const Body a = box(Vec(1, 1, 0.5)), b = box(Vec(0.5, 0.25, 0.25));
        BenchCase c = make_case(family, "box edge on box face", a, Pose{}, b,
                                Pose{about(Vec::UnitZ(), rng.uniform(0, 1.5)) * about(Vec::UnitX(), M_PI / 4),
                                     Vec(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 1.0)});
        steer(c, 0.0);
        return c;
      }
      case 3: {
        const Body a = box(Vec(1, 1, 0.5)), b = box(Vec(0.3, 0.25, 0.2));
        BenchCase c = make_case(family, "box corner on box face", a, Pose{}, b,
                                Pose{rng.rotation(), Vec(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 1.2)});
        steer(c, 0.0);
        return c;
      }
      default: {
        const Body a = box(Vec(1, 0.5, 0.5)), b = box(Vec(0.5, 1, 0.5));
        BenchCase c = make_case(family, "crossed box edges", a, Pose{about(Vec::UnitX(), M_PI / 4), Vec::Zero()}, b,
                                Pose{about(Vec::UnitY(), M_PI / 4), Vec(0, 0, 1.6)});
        steer(c, 0.0);
        return c;
      }
    }
  }

  // Two bodies of kind `kind` for the deep family (both about size 1).
  std::pair<Body, Body> deep_pair(int kind, std::string& label) {
    switch (kind) {
      case 0: {
        label = "a hull and itself";
        Body a = random_poly(rng);
        return {a, a};
      }
      case 1:
        label = "a box and itself";
        return {box(Vec(1, 0.6, 0.3)), box(Vec(1, 0.6, 0.3))};
      case 2:
        label = "hull and hull";
        return {random_poly(rng), random_poly(rng)};
      case 3:
        label = "box and hull";
        return {box(Vec(0.8, 0.6, 0.5)), random_poly(rng)};
      case 4:
        label = "sphere and box";
        return {primitive(collision::Sphere{0.7, 0.0}), box(Vec(0.8, 0.6, 0.5))};
      case 5:
        label = "capsule and hull";
        return {primitive(collision::Capsule{0.3, 0.6, 0.0}), random_poly(rng)};
      case 6:
        label = "cylinder and box";
        return {primitive(collision::Cylinder{0.5, 0.7, 0.0}), box(Vec(0.8, 0.6, 0.5))};
      case 7:
        label = "cone and hull";
        return {primitive(collision::Cone{0.6, 0.7, 0.0}), random_poly(rng)};
      case 8:
        label = "rounded box and rounded hull";
        return {box(Vec(0.7, 0.5, 0.4), 0.1), ellipsoid_hull(rng, 24, Vec(0.8, 0.7, 0.6), 0.1)};
      case 9:
        label = "cylinder in a cylinder, axes nearly parallel";
        return {primitive(collision::Cylinder{0.5, 0.7, 0.0}), primitive(collision::Cylinder{0.4, 0.6, 0.0})};
      default:
        label = "cone and cylinder, axes nearly parallel";
        return {primitive(collision::Cone{0.5, 0.7, 0.0}), primitive(collision::Cylinder{0.4, 0.6, 0.0})};
    }
  }

  BenchCase deep(const Plan& plan, int i) {
    const double fraction = plan.parameters[parameter_index(plan, i)];
    std::string label;
    auto [a, b] = deep_pair(kind_index(plan, i), label);
    const Mat rotation_a = rng.rotation();
    // Identical shapes share the pose too: exactly coincident at fraction 0.
    const bool same = label.find("itself") != std::string::npos;
    // Nearly coaxial curved pairs: B's axis turned 1e-10 .. 1e-3 rad off A's
    // (where the depth is almost the same over a circle of directions).
    const bool coaxial = label.find("nearly parallel") != std::string::npos;
    const Mat rotation_b = same      ? rotation_a
                           : coaxial ? Mat(rotation_a * about(rng.unit(), rng.log_uniform(1e-10, 1e-3)))
                                     : rng.rotation();
    const Vec t = rng.unit() * fraction * std::max(a.radius, b.radius);
    BenchCase c = make_case(family, label + (fraction == 0 ? ", coincident" : ", centres apart"), a,
                            Pose{rotation_a, Vec::Zero()}, b, Pose{rotation_b, t});
    c.parameter = fraction;
    c.reference = case_reference(c);
    return c;
  }

  BenchCase parallel(const Plan& plan, int i) {
    const double angle = plan.parameters[parameter_index(plan, i)];
    const int kind = kind_index(plan, i);
    const bool pen = overlapping(plan, i);
    Body a;
    std::string label;
    if (kind == 0) {
      a = box(Vec(1, 1, 0.25));
      label = "box on box";
    } else {
      // A slab hull: a box's corners plus coplanar points on its top face
      // and points inside (merged away by the hull).
      std::vector<Vec> points;
      for (int k = 0; k < 8; ++k) points.emplace_back(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 0.25 : -0.25);
      for (int k = 0; k < 6; ++k) points.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), 0.25);
      for (int k = 0; k < 6; ++k) points.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.25, 0.25));
      a = hull_body(std::move(points));
      label = "box on hull slab";
    }
    const Body b = box(Vec(0.5, 0.4, 0.25));
    const double phi = rng.uniform(0, 2 * M_PI);
    const Vec tilt_axis(std::cos(phi), std::sin(phi), 0.0);
    // The whole pair turned by a random rotation: no face is axis-aligned.
    const Mat frame = rng.rotation();
    const Vec offset(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 0.5);
    BenchCase c = make_case(family, label + ", faces " + (pen ? "overlapping" : "apart"), a, Pose{frame, Vec::Zero()},
                            b, Pose{frame * about(tilt_axis, angle), frame * offset});
    c.parameter = angle;
    steer(c, pen ? -1e-3 : 1e-3);
    return c;
  }

  BenchCase thin(const Plan& plan, int i) {
    const double aspect = plan.parameters[parameter_index(plan, i)];
    const int kind = kind_index(plan, i);
    const bool pen = overlapping(plan, i);
    const double t = 1.0 / aspect;  // half thickness of the thin body
    Body a, b;
    std::string label;
    switch (kind) {
      case 0:
        a = box(Vec(1, 1, t));
        b = box(Vec(0.5, 0.4, 0.3));
        label = "plate box and box";
        break;
      case 1:
        a = box(Vec(t, t, 1));
        b = random_poly(rng);
        label = "needle box and hull";
        break;
      case 2:
        a = ellipsoid_hull(rng, 32, Vec(1, 1, t));
        b = box(Vec(0.5, 0.4, 0.3));
        label = "plate hull and box";
        break;
      default:
        a = ellipsoid_hull(rng, 32, Vec(t, t, 1));
        b = ellipsoid_hull(rng, 32, Vec(t, 1, t));
        label = "needle hull and needle hull";
        break;
    }
    BenchCase c =
        apart(family, label + (pen ? ", overlapping" : ", apart"), a, rng.rotation(), b, rng.rotation(), rng.unit());
    c.parameter = aspect;
    steer(c, (pen ? -0.5 : 0.5) * t);
    return c;
  }

  BenchCase scale(const Plan& plan, int i) {
    const double ratio = plan.parameters[parameter_index(plan, i)];
    const int kind = kind_index(plan, i);
    const bool pen = overlapping(plan, i);
    const double big = 1e3, small = big / ratio;
    const Body a = kind == 0 ? box(Vec(big, big, big)) : ellipsoid_hull(rng, 64, Vec(big, big, big));
    const Body b = ellipsoid_hull(rng, 16, Vec(small, small, small));
    BenchCase c = apart(
        family,
        std::string(kind == 0 ? "box" : "hull") + " 2e3 across and a smaller hull, " + (pen ? "overlapping" : "apart"),
        a, rng.rotation(), b, rng.rotation(), rng.unit(), small);
    c.parameter = ratio;
    steer(c, (pen ? -1.0 : 1.0) * small / 3);
    return c;
  }

  BenchCase far(const Plan& plan, int i) {
    const double offset = plan.parameters[parameter_index(plan, i)];
    const bool pen = kind_index(plan, i) == 1;
    BenchCase c = poly(i, pen);
    const Vec shift = rng.unit() * offset;
    c.pose_a.translation += shift;
    c.pose_b.translation += shift;
    c.label += ", both moved " + std::string(offset >= 1e3 ? "far" : "a little");
    c.parameter = offset;
    c.reference = case_reference(c);
    return c;
  }

  BenchCase large(const Plan& plan, int i) {
    const int n = static_cast<int>(plan.parameters[parameter_index(plan, i)]);
    const bool pen = kind_index(plan, i) == 1;
    auto found = large_hulls.find(n);
    if (found == large_hulls.end()) found = large_hulls.emplace(n, ellipsoid_hull(rng, n, Vec(1, 1, 1))).first;
    const Body& a = found->second;
    const Body b = ellipsoid_hull(rng, 16, Vec(0.3, 0.25, 0.2));
    BenchCase c = apart(family, "hull of " + std::to_string(n) + " vertices and one of 16, " + (pen ? kPen : kSep), a,
                        rng.rotation(), b, rng.rotation(), rng.unit());
    c.parameter = n;
    steer(c, (pen ? -1.0 : 1.0) * rng.log_uniform(1e-3, 0.1));
    return c;
  }

  BenchCase rounded(const Plan& plan, int i) {
    const bool pen = overlapping(plan, i);
    auto r = [&](double lo, double hi) { return rng.uniform(lo, hi); };
    Body a, b;
    std::string label;
    switch (kind_index(plan, i)) {
      case 0:
        a = primitive(collision::Sphere{r(0.3, 1), 0});
        b = primitive(collision::Sphere{r(0.3, 1), 0});
        label = "sphere and sphere";
        break;
      case 1:
        a = primitive(collision::Sphere{r(0.3, 1), 0});
        b = box(Vec(r(0.3, 1), r(0.3, 1), r(0.3, 1)));
        label = "sphere and box";
        break;
      case 2:
        a = primitive(capsule_drawn(r, 0.2, 1, 0.1, 0.5));
        b = primitive(capsule_drawn(r, 0.2, 1, 0.1, 0.5));
        label = "capsule and capsule";
        break;
      case 3:
        a = primitive(capsule_drawn(r, 0.2, 1, 0.1, 0.5));
        b = box(Vec(r(0.3, 1), r(0.3, 1), r(0.3, 1)));
        label = "capsule and box";
        break;
      case 4:
        a = primitive(collision::Sphere{r(0.3, 1), 0});
        b = random_poly(rng);
        label = "sphere and hull";
        break;
      case 5:
        a = primitive(capsule_drawn(r, 0.2, 1, 0.1, 0.5));
        b = ellipsoid_hull(rng, 24, Vec(r(0.4, 1), r(0.4, 1), r(0.4, 1)), r(0.02, 0.2));
        label = "capsule and rounded hull";
        break;
      case 6:
        a = box(Vec(r(0.3, 1), r(0.3, 1), r(0.3, 1)), r(0.02, 0.2));
        b = box(Vec(r(0.3, 1), r(0.3, 1), r(0.3, 1)), r(0.02, 0.2));
        label = "rounded box and rounded box";
        break;
      default:
        a = ellipsoid_hull(rng, 24, Vec(r(0.4, 1), r(0.4, 1), r(0.4, 1)), r(0.02, 0.2));
        b = ellipsoid_hull(rng, 24, Vec(r(0.4, 1), r(0.4, 1), r(0.4, 1)), r(0.02, 0.2));
        label = "rounded hull and rounded hull";
        break;
    }
    BenchCase c =
        apart(family, label + (pen ? ", overlapping" : ", apart"), a, rng.rotation(), b, rng.rotation(), rng.unit());
    steer(c, pen ? -rng.log_uniform(1e-3, 0.3) : rng.log_uniform(1e-3, 1.0));
    return c;
  }

  BenchCase curved(const Plan& plan, int i) {
    const bool pen = overlapping(plan, i);
    auto r = [&](double lo, double hi) { return rng.uniform(lo, hi); };
    auto cylinder = [&] { return primitive(collision::Cylinder{r(0.3, 0.8), r(0.3, 0.8), 0}); };
    auto cone = [&] { return primitive(collision::Cone{r(0.3, 0.8), r(0.3, 0.8), 0}); };
    Body a, b;
    std::string label;
    switch (kind_index(plan, i)) {
      case 0:
        a = cylinder(), b = cylinder(), label = "cylinder and cylinder";
        break;
      case 1:
        a = cylinder(), b = box(Vec(r(0.3, 1), r(0.3, 1), r(0.3, 1))), label = "cylinder and box";
        break;
      case 2:
        a = cone(), b = cone(), label = "cone and cone";
        break;
      case 3:
        a = cone(), b = random_poly(rng), label = "cone and hull";
        break;
      case 4:
        a = cylinder(), b = cone(), label = "cylinder and cone";
        break;
      case 5:
        a = cylinder(), b = primitive(collision::Sphere{r(0.2, 0.8), 0}), label = "cylinder and sphere";
        break;
      case 6:
        a = cone(), b = primitive(capsule_drawn(r, 0.2, 0.8, 0.1, 0.4)), label = "cone and capsule";
        break;
      default:
        a = primitive(collision::Cylinder{r(0.3, 0.8), r(0.3, 0.8), r(0.02, 0.2)});
        b = random_poly(rng);
        label = "rounded cylinder and hull";
        break;
    }
    BenchCase c =
        apart(family, label + (pen ? ", overlapping" : ", apart"), a, rng.rotation(), b, rng.rotation(), rng.unit());
    steer(c, pen ? -rng.log_uniform(1e-3, 0.3) : rng.log_uniform(1e-3, 1.0), 3);
    return c;
  }

  BenchCase degenerate(const Plan& plan, int i) {
    const bool pen = overlapping(plan, i);
    std::vector<Vec> points;
    std::string label;
    Body other = random_poly(rng);
    switch (kind_index(plan, i)) {
      case 0:
        for (int k = 0; k < 12; ++k) {
          const double phi = rng.uniform(0, 2 * M_PI);
          points.emplace_back(std::cos(phi), std::sin(phi), 0.0);
        }
        label = "flat disc hull and hull";
        break;
      case 1:
        for (int k = 0; k < 4; ++k) points.emplace_back(k & 1 ? 0.8 : -0.8, k & 2 ? 0.6 : -0.6, 0.0);
        other = box(Vec(0.5, 0.4, 0.3));
        label = "flat square hull and box";
        break;
      case 2:
        points = {Vec(0, 0, -1), Vec(0, 0, 1)};
        other = box(Vec(0.5, 0.4, 0.3));
        label = "segment hull and box";
        break;
      case 3:
        for (int k = 0; k < 5; ++k) points.push_back(Vec(0.3, -0.2, 1.0) * rng.uniform(-1, 1));
        label = "five collinear points and hull";
        break;
      case 4:
        points = {Vec(0.1, 0.2, 0.3), Vec(0.1, 0.2, 0.3), Vec(0.1, 0.2, 0.3)};
        other = box(Vec(0.5, 0.4, 0.3));
        label = "point hull (a point three times) and box";
        break;
      case 5:
        // A box's corners, each repeated 6 times, some copies nudged by
        // 1e-14: duplicate and near-duplicate support points.
        for (int k = 0; k < 8; ++k) {
          const Vec corner(k & 1 ? 0.7 : -0.7, k & 2 ? 0.5 : -0.5, k & 4 ? 0.4 : -0.4);
          for (int copy = 0; copy < 6; ++copy) points.push_back(corner + (copy % 2) * 1e-14 * rng.unit());
        }
        label = "hull of repeated corners and hull";
        break;
      case 6:
        for (int k = 0; k < 3; ++k) points.push_back(rng.unit());
        other = box(Vec(0.5, 0.4, 0.3));
        label = "triangle hull and box";
        break;
      default:
        for (int k = 0; k < 4; ++k) points.emplace_back(k & 1 ? 0.8 : -0.8, k & 2 ? 0.6 : -0.6, 0.0);
        other = hull_body({Vec(-0.7, -0.5, 0), Vec(0.7, -0.5, 0), Vec(0.7, 0.5, 0), Vec(-0.7, 0.5, 0)});
        label = "flat square hull and flat square hull";
        break;
    }
    const Body a = hull_body(std::move(points));
    BenchCase c = apart(family, label + (pen ? ", overlapping" : ", apart"), a, rng.rotation(), other, rng.rotation(),
                        rng.unit());
    steer(c, pen ? -rng.log_uniform(1e-3, 0.1) : rng.log_uniform(1e-3, 1.0));
    return c;
  }
};

Plan plan_for(const std::string& family, bool quick) {
  if (family == "poly-separated" || family == "poly-penetrating") return {{}, 1, quick ? 8 : 256};
  if (family == "touching") return {{}, 5, quick ? 5 : 100};
  if (family == "deep") {
    std::vector<double> f = {0.0, 1e-4, 1e-3, 1e-2, 1e-1, 0.3};
    return {f, 11, quick ? 6 : 264};
  }
  if (family == "parallel") return {decades(-9, -4), 2, quick ? 6 : 192};
  if (family == "thin") return {decades(2, 4), 4, quick ? 6 : 144};
  if (family == "scale") return {decades(0, 6), 2, quick ? 7 : 168};
  if (family == "far") return {decades(0, 6), 2, quick ? 7 : 168};
  if (family == "large-hull") {
    if (quick) return {{1000, 2000}, 2, 4};
    return {{1000, 2000, 5000, 10000, 20000}, 2, 60};
  }
  if (family == "rounded") return {{}, 8, quick ? 8 : 192};
  if (family == "curved") return {{}, 8, quick ? 8 : 128};
  if (family == "degenerate") return {{}, 8, quick ? 8 : 128};
  return {};
}

}  // namespace

const std::vector<FamilyInfo>& families() {
  static const std::vector<FamilyInfo> list = {
      {"poly-separated", "", "hulls of 8-64 vertices, apart by 1e-3 .. 1 of their size"},
      {"poly-penetrating", "", "hulls of 8-64 vertices, overlapping by 1e-3 .. 0.3 of their size"},
      {"touching", "", "signed distance 0: vertex on face, face on face, edge on face, corner on face, crossed edges"},
      {"deep", "centre offset / size",
       "coincident and deep pairs of every kind of shape, nearly coaxial cylinders and cones among them"},
      {"parallel", "angle (rad)", "faces 1e-9 .. 1e-4 rad from parallel, 1e-3 apart or overlapping"},
      {"thin", "aspect ratio", "plates and needles of aspect 1e2 .. 1e4"},
      {"scale", "size ratio", "a hull 1e-3 .. 1e3 across against one 2e3 across"},
      {"far", "offset", "pairs translated together by 1 .. 1e6"},
      {"large-hull", "vertices", "a 1 000 .. 20 000-vertex hull against a 16-vertex hull"},
      {"rounded", "", "spheres, capsules, boxes and hulls with margins"},
      {"curved", "", "cylinders and cones against each other and polytopes"},
      {"degenerate", "", "flat, segment and point hulls; repeated points"},
  };
  return list;
}

const FamilyInfo* find_family(const std::string& name) {
  for (const FamilyInfo& f : families())
    if (name == f.name) return &f;
  return nullptr;
}

ReferenceAnswer case_reference(const BenchCase& c) {
  reference::ExactSettings settings;
  if (!c.points_a.empty()) settings.override_a = &c.points_a;
  if (!c.points_b.empty()) settings.override_b = &c.points_b;
  ReferenceAnswer r;
  r.exact = reference::exact_signed_distance(c.a, c.pose_a, c.b, c.pose_b, settings);
  r.pair_size = pair_size(c.a, c.pose_a, c.b, c.pose_b);
  return r;
}

FamilyCases make_family(const std::string& family, const WorkloadOptions& options) {
  FamilyCases out;
  const Plan plan = plan_for(family, options.quick);
  Generator g{family, Rng(options.seed ^ hash_name(family)), options.quick, {}};
  for (int i = 0; i < plan.count; ++i) {
    BenchCase c;
    if (family == "poly-separated") c = g.poly(i, false);
    if (family == "poly-penetrating") c = g.poly(i, true);
    if (family == "touching") c = g.touching(kind_index(plan, i));
    if (family == "deep") c = g.deep(plan, i);
    if (family == "parallel") c = g.parallel(plan, i);
    if (family == "thin") c = g.thin(plan, i);
    if (family == "scale") c = g.scale(plan, i);
    if (family == "far") c = g.far(plan, i);
    if (family == "large-hull") c = g.large(plan, i);
    if (family == "rounded") c = g.rounded(plan, i);
    if (family == "curved") c = g.curved(plan, i);
    if (family == "degenerate") c = g.degenerate(plan, i);
    if (!c.reference.exact.ok) {
      ++out.dropped;
      out.notes.push_back(family + " case " + std::to_string(i) + " (" + c.label +
                          "): no reference: " + c.reference.exact.reason);
      continue;
    }
    out.cases.push_back(std::move(c));
  }
  return out;
}

}  // namespace hedra::tool::bench
