#include "robot_agent/controller/goal_force.hpp"

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

Vec2 goal_force(Vec2 position, Vec2 goal, double k_goal, double max_norm, double goal_radius) {
  const Vec2 to_goal = vsub(goal, position);
  if (vnorm(to_goal) <= goal_radius) return {};
  return vclamp(vscale(to_goal, k_goal), max_norm);  // eq. (3), saturated
}

}  // namespace swarmform::controller::motion
