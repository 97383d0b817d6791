// Formation motion, the leader's pull (paper III.C, eq. 3): F_goal ∝ r_goal - r_position.
//
// The elected leader applies it to its own place (every robot holds the mission's goal, so that a newly
// elected leader can take over at once); so does a follower cut off from its parent (motion_phase.hpp).
// F_goal = k_goal (r_goal - r_position), saturated at `max_norm` (the leader's cruise: by default the speed
// limit, slowed while the shape lags; followers keep up with their parent's velocity fed forward). Within
// `goal_radius` of the goal it is zero.
#pragma once

#include "common/types.hpp"

namespace swarmform::controller::motion {

Vec2 goal_force(Vec2 position, Vec2 goal, double k_goal, double max_norm, double goal_radius);

}  // namespace swarmform::controller::motion
