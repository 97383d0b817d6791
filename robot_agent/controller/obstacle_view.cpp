#include "robot_agent/controller/obstacle_view.hpp"

#include <cmath>
#include <vector>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

std::vector<NeighbourBearing> neighbours_to_mask(const NeighbourTable& neighbours, const Pose2D& pose,
                                                 double tick_rate, double max_speed,
                                                 const std::map<RobotId, Vec2>& last_position,
                                                 const std::map<RobotId, Vec2>& last_velocity) {
  std::vector<NeighbourBearing> bearings;
  const Vec2 own{pose.x, pose.y};
  for (const auto& [id, n] : neighbours.all()) {
    if (neighbours.fresh(n)) {
      bearings.push_back({n.range, n.bearing});
      continue;
    }
    const auto at = last_position.find(id);
    if (at == last_position.end() || n.last_heard > neighbours.now()) continue;
    const double dt = static_cast<double>(neighbours.now() - n.last_heard) / tick_rate;
    const auto v = last_velocity.find(id);
    const Vec2 there = vadd(at->second, vscale(v != last_velocity.end() ? v->second : Vec2{}, dt));
    const Vec2 rel = vsub(there, own);
    bearings.push_back({vnorm(rel), wrap_angle(std::atan2(rel.y, rel.x) - pose.theta), max_speed * dt});
  }
  return bearings;
}

ObstacleView look_at_obstacles(const std::vector<NeighbourBearing>& neighbours,
                               const UltrasonicArray& readings, double theta, double m,
                               const MotionParams& p) {
  ObstacleView view;
  view.readings = readings;
  view.mask = mask_neighbour_directions(view.readings, neighbours, p.mask_angle, p.mask_slack);
  view.sense = sense_obstacles(view.readings, view.mask, theta,
                               {m, p.obstacle_range, p.fusion_range, p.small_obstacle_width});
  return view;
}

void LargeObstacleLatch::apply(ObstacleSense& sense, Tick tick) {
  if (sense.size == ObstacleSize::Large) until_ = tick + kLargeLatchTicks;
  if (sense.size == ObstacleSize::Small && tick < until_) {
    sense.size = ObstacleSize::Large;
    until_ = tick + kLargeLatchTicks;
  }
}

}  // namespace swarmform::controller::motion
