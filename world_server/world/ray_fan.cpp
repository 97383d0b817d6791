#include "world_server/world/ray_fan.hpp"

#include <algorithm>
#include <cmath>

namespace swarmform::world {

void cast_ring_rays(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
                    const std::vector<StaticShape>& statics, double range, std::span<const double> dx,
                    std::span<const double> dy, std::span<double> nearest) {
  const Pose2D& me = poses[self];
  const std::size_t n = nearest.size();
  // A robot whose centre is farther than this from the reading robot's centre cannot be hit by any ray.
  const double robot_reach = kRobotRadius + range + kRobotRadius;
  grid.for_each_near(me.x, me.y, robot_reach, [&](std::uint32_t j) {
    if (j == self) return;
    for (std::size_t k = 0; k < n; ++k) {
      const double t = ray_circle(me.x + kRobotRadius * dx[k], me.y + kRobotRadius * dy[k], dx[k], dy[k],
                                  poses[j].x, poses[j].y, kRobotRadius);
      nearest[k] = std::min(nearest[k], t);
    }
  });
  for (const StaticShape& st : statics) {
    const double cx = me.x - st.cx, cy = me.y - st.cy, far = kRobotRadius + range + st.bound + 1e-6;
    if (cx * cx + cy * cy > far * far) continue;
    for (std::size_t k = 0; k < n; ++k) {
      nearest[k] = std::min(
          nearest[k], ray_static(me.x + kRobotRadius * dx[k], me.y + kRobotRadius * dy[k], dx[k], dy[k], st));
    }
  }
}

}  // namespace swarmform::world
