// The exact first contact of two moving shapes, for judging continuous
// queries (shape casts, times of impact, the peers' casts) independently of
// hedra's code: exact_signed_distance (exact_reference.hpp) evaluated along
// the motion and traced with a Lipschitz bound.
//
// Motion: each body's origin moves linearly from p0 to p1 and its
// orientation turns from q0 to q1 by Eigen's slerp (constant angular velocity
// along the shorter arc), over t in [0, 1]. The pair's distance then changes
// at most as fast as
//   L = |v_b - v_a| + theta_a r_a + theta_b r_b,
// v the origins' velocities, theta the turned angles, r each shape's largest
// distance from its origin (margin included). Tracing from t = 0 by steps
// (lower bound of the distance - target) / L never passes the first contact
// (early); probing forward by doubling steps until the certified upper bound
// is within the target gives a time never before it (late). A pass that only
// touches has late = infinity; one that starts within the target has
// early = late = 0. Every distance is the reference's certified bracket.
#pragma once

#include <Eigen/Geometry>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/shapes.hpp>
#include <limits>
#include <string>

#include "exact_reference.hpp"

namespace hedra::reference {

struct Motion {
  Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity(), q1 = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), p1 = Eigen::Vector3d::Zero();
  collision::Pose at(double t) const;
  double angle() const { return q0.angularDistance(q1); }
};

// The largest distance of the shape (margin included) from its origin.
double reach(const collision::Shape& shape);

// L above: how fast the pair's distance can change per unit t.
double distance_rate_bound(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb);

// The reference's certified bracket [lower, upper] of the distance at t
// (ok == false: the reference failed, with its reason).
struct DistanceBracket {
  bool ok = false;
  std::string reason;
  double lower = 0.0, upper = 0.0;
};
DistanceBracket distance_at(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb,
                            double t);

struct FirstContactSettings {
  double target = 0.0;   // contact when the distance is <= target
  double size = 0.0;     // the pair's scale (0: the larger reach)
  double stop = 1e-12;   // the trace stops this close to the target (times size)
  int max_steps = 3000;  // trace steps (a tangential touch converges slowly: early stays a lower bound)
};

struct FirstContact {
  bool ok = true;  // false: the reference failed (reason)
  std::string reason;
  bool initially = false;  // within the target at t = 0
  bool contact = false;    // the trace came within the stop distance of the target in [0, 1]
  double early = 1.0;      // never after the first contact
  double late = std::numeric_limits<double>::infinity();     // never before it (inf: a touch at most)
  double min_gap = std::numeric_limits<double>::infinity();  // smallest lower bound - target seen
  double rate = 0.0;                                         // distance_rate_bound
  int steps = 0;                                             // reference evaluations
  bool exhausted = false;  // the trace ran out of max_steps short of the target: early is a lower bound only
};

FirstContact exact_first_contact(const collision::Shape& a, const Motion& ma, const collision::Shape& b,
                                 const Motion& mb, const FirstContactSettings& settings = {});

// One continuous answer (hit, and the fraction in [0, 1] of the motion)
// against the bracket, by one rule for every caller (`hedra bench
// --continuous`, `hedra compare`). Distances along the motion are fraction
// differences times contact.rate; `tolerance` is absolute, on distance:
//   started within the target   tunnelled unless a hit at fraction * rate <= tolerance;
//   a miss                      tunnelled when the pair certainly gets deeper than
//                               the tolerance after the late end (a touch at most is
//                               missed either way);
//   a hit after late            tunnelled by (fraction - late) * rate > tolerance;
//   a hit before early          early by error = (early - fraction) * rate / size;
//   a hit after a touch's early bound, or without a contact: a false hit when the
//   certified distance there is above target + tolerance.
// through: tunnelled by a miss, or later than 1e-3 of the size.
struct ContactVerdict {
  bool tunnelled = false, false_hit = false, through = false;
  double error = 0.0;  // distance along the motion / size (early answers and tunnelling)
};
// The default tolerance: 1e-9 of the size plus the coordinates' rounding
// (64 eps times `far`, the largest coordinate of the motion).
double contact_tolerance(double size, double far);
ContactVerdict judge_contact(const collision::Shape& a, const Motion& ma, const collision::Shape& b, const Motion& mb,
                             const FirstContact& contact, double target, double size, double tolerance, bool hit,
                             double fraction);

}  // namespace hedra::reference
