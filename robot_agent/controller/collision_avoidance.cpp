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
  bool inside = false;
  Vec2 v = desired;
  Vec2 slide;
  for (const auto& n : neighbours) {
    if (!(n.range < r_o)) continue;
    inside = true;
    const Vec2 towards = unit(n.azimuth);
    const double closing = v.x * towards.x + v.y * towards.y;
    if (closing > 0.0) {
      v = v - closing * towards;  // no more progress into the neighbour
      // Pass it on the right: the slide is as strong as the progress that was removed.
      slide = slide + closing * Vec2{towards.y, -towards.x};
    }
  }
  if (!inside) return desired;
  const Vec2 out = v + slide + collision_force(neighbours, k_collision, r_o);
  return limit(out, max_speed);
}

}  // namespace swarmform::controller
