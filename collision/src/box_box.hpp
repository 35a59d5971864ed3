// The box-box contact path (box_box.cpp): contact() for two boxes without
// the general polytope machinery, the same answers.
#pragma once

#include <hedra/collision/manifold.hpp>

namespace hedra::collision::detail {

// contact() for two boxes (inputs already checked). True: `out` is the
// answer and the cache (if any) is updated as the general polytope path
// updates it. False: this path does not answer the pair (rounded cores that
// touch or overlap, a clipped-away deepest vertex, the exact-normal axis
// search asked for, ...); the general path must, and the cache is untouched
// but for its box memory, which is cleared.
bool box_box_contact(const Box& a, const Pose& pose_a, const Box& b, const Pose& pose_b, ContactCache* cache,
                     const ContactSettings& settings, ContactResult& out);

}  // namespace hedra::collision::detail
