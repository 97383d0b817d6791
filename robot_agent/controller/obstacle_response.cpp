#include "robot_agent/controller/obstacle_response.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

int side_away_from_neighbours(const NeighbourTable& table, Vec2 o, double reach) {
  double left = 0.0, right = 0.0;
  const Vec2 t_left = vrotate(o, std::numbers::pi / 2);
  for (const auto& [id, n] : table.all()) {
    if (!table.fresh(n) || n.range > reach) continue;
    const double side = vdot(vpolar(1.0, n.azimuth), t_left) / std::max(n.range, 0.3);
    (side > 0 ? left : right) += std::abs(side);
  }
  constexpr double kAlike = 0.05;
  if (left + kAlike < right) return 1;
  if (right + kAlike < left) return -1;
  return 0;
}

Vec2 respond_to_obstacles(SlideState& state, EchoMemory& echoes, const NeighbourTable& neighbours,
                          const ResponseInputs& in) {
  const Vec2 force = echoes.force(in.position, in.tick, in.m, in.obstacle_range, kEchoMemoryTicks);
  const double f_obs = vnorm(force);
  if (f_obs > 1e-9) {
    state.last_obstacle_tick = in.tick;
  } else if (in.tick > state.last_obstacle_tick + kEchoMemoryTicks) {
    state.side = 0;
  }
  Vec2 desired = in.desired;
  const double d_norm = vnorm(desired);
  if (f_obs > 1e-9 && d_norm > 1e-9) {
    const Vec2 n = vscale(force, 1.0 / f_obs);
    const double into = vdot(desired, n);
    Vec2 slide = vsub(desired, vscale(n, into));
    const bool head_on = vnorm(slide) < 0.5 * d_norm;
    const bool gap_ahead =
        head_on && echoes.gap_ahead(in.position, vscale(desired, 1.0 / d_norm), in.obstacle_range,
                                    2.0 * kRobotRadius, in.tick, kEchoMemoryTicks);
    if (into < 0.0 && !gap_ahead) {
      if (head_on) {
        if (state.side == 0) {
          // Towards the parent's side; the leader, which has none, towards its neighbours.
          const Vec2 to_obstacle = vscale(n, -1.0);
          const double parent_side = to_obstacle.x * in.to_parent.y - to_obstacle.y * in.to_parent.x;
          const int toward = side_away_from_neighbours(neighbours, to_obstacle, in.neighbour_reach);
          if (in.has_parent && std::abs(parent_side) > 0.05) {
            state.side = parent_side > 0 ? 1 : -1;
          } else {
            state.side =
                toward != 0 ? -toward : (vdot(slide, vrotate(n, std::numbers::pi / 2)) >= 0 ? -1 : 1);
          }
        }
        // +1: left of the obstacle direction -n, i.e. n turned by -pi/2.
        slide = vadd(slide, vscale(vrotate(n, -state.side * std::numbers::pi / 2), 0.5 * d_norm));
      }
      desired = slide;
    }
  }
  return vadd(desired, force);
}

}  // namespace swarmform::controller::motion
