#include "robot_agent/controller/collision_avoidance.hpp"

#include <algorithm>
#include <cmath>

#include "robot_agent/controller/drive.hpp"

namespace swarmform::controller {

Vec2 collision_force(const std::vector<NeighbourPosition>& neighbours, double k_collision, double r_o) {
  Vec2 f;
  for (const auto& n : neighbours) {
    if (!(n.range < r_o)) continue;
    const double gap = std::max(std::abs(n.range - r_o), kSingularityFloor);
    f = f + (-k_collision / (gap * gap)) * unit(n.azimuth);  // eq. (1)
  }
  return f;
}

Vec2 avoid_collisions(Vec2 desired, const std::vector<NeighbourPosition>& neighbours, double k_collision,
                      double r_o, double max_speed) {
  bool near = false;
  Vec2 v = desired;
  const double speed = norm(desired);
  const double inner = r_o + kAwarenessMargin;
  const double outer = inner + kBlendWidth;
  for (const auto& n : neighbours) {
    if (!(n.range < outer)) continue;
    near = true;
    // Full go-round inside `inner`, none beyond `outer`, a linear blend between: the velocity is continuous
    // across the band, so a differential-drive robot does not flip 90 degrees each tick at its edge.
    const double w = std::clamp((outer - n.range) / kBlendWidth, 0.0, 1.0);
    const Vec2 towards = unit(n.azimuth);
    const double closing = v.x * towards.x + v.y * towards.y;
    if (closing <= 0.0) continue;
    // No more progress into the neighbour: go round it, at the desired speed, on the side the goal is on
    // (on the right when the goal is straight behind it, so two robots meeting head-on do not mirror each
    // other).
    const Vec2 right{towards.y, -towards.x};
    const double side = v.x * right.x + v.y * right.y;
    const Vec2 tangent = side >= -0.2 * closing ? right : Vec2{-right.x, -right.y};
    Vec2 g = v - closing * towards;
    g = g - (g.x * tangent.x + g.y * tangent.y) * tangent + speed * tangent;
    v = (1.0 - w) * v + w * g;
  }
  if (!near) return desired;
  // eq. (1), capped at the speed limit so that going round still has a say (the sum is limited below).
  const Vec2 repulsion = limit(collision_force(neighbours, k_collision, r_o), max_speed);
  return limit(v + repulsion, max_speed);
}

}  // namespace swarmform::controller
