#include "robot_agent/controller/formation_forces.hpp"

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

Vec2 reference_force(double k_o, ParentMeasure at_ready) {
  // eq. (2)
  return vpolar(k_o * at_ready.range * at_ready.range, at_ready.azimuth);
}

Vec2 attractive_force(double k_o, ParentMeasure now) {
  // eq. (4)
  return vpolar(k_o * now.range * now.range, now.azimuth);
}

Vec2 net_force(Vec2 attractive, Vec2 reference) {
  // eq. (5): F_ref "shifted by pi" is -F_ref.
  return vsub(attractive, reference);
}

}  // namespace swarmform::controller::motion
