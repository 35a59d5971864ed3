// Entry points of query.cpp for callers inside the library that have
// validated their inputs already (World: shapes at add(), poses at add() and
// set_pose(), the pair's extent from the bodies' radii), so that a hot loop
// does not check every shape again on every pair.
#pragma once

#include <hedra/collision/query.hpp>

namespace hedra::collision::detail {

// separated_beyond() without its input checks. Requires is_valid(a),
// is_valid(b), pose_a.valid(), pose_b.valid(), pair_in_range(a, pose_a, b,
// pose_b) and gap >= 0 (asserted in debug builds).
bool separated_beyond_unchecked(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, double gap,
                                const GjkSettings& settings);

// penetration() on shapes of known types without its input checks (the
// contact code checks once, in contact()): the same answer, bit for bit.
// Requires what penetration() checks (asserted in debug builds). Point and
// segment hulls take the sphere's and the capsule's paths, as in
// penetration(). Instantiated in query.cpp for every pair of shape types.
template <class SA, class SB>
PenetrationResult penetration_unchecked(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b,
                                        GjkCache* cache, const PenetrationSettings& settings);

}  // namespace hedra::collision::detail
