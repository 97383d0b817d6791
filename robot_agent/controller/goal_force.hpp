// Formation motion, the leader's pull (paper III.C, eq. 3): F_goal ∝ r_goal - r_position.
//
// Only the elected leader applies it (every robot holds the mission's goal, so that a newly elected leader
// can take over at once, but followers never use it). F_goal = k_goal (r_goal - r_position), saturated at
// `max_norm` (the leader's cruise speed, below the robots' speed limit so that followers, which also have to
// correct their place, can keep up). Within `goal_radius` of the goal it is zero (arrival, SPEC 5.8).
#pragma once

#include "common/types.hpp"

namespace swarmform::controller::motion {

Vec2 goal_force(Vec2 position, Vec2 goal, double k_goal, double max_norm, double goal_radius);

}  // namespace swarmform::controller::motion
