#include "robot_agent/controller/obstacle_view.hpp"

#include <vector>

namespace swarmform::controller::motion {

ObstacleView look_at_obstacles(const NeighbourTable& neighbours, const UltrasonicArray& readings,
                               double theta, double m, const MotionParams& p) {
  std::vector<NeighbourBearing> bearings;
  for (const auto& [id, n] : neighbours.all()) {
    if (neighbours.fresh(n)) bearings.push_back({n.range, n.bearing});
  }
  ObstacleView view;
  view.readings = readings;
  view.mask = mask_neighbour_directions(view.readings, bearings, p.mask_angle, p.mask_slack);
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
