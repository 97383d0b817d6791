// Small scenarios built in code for the world's unit tests (no YAML, no shape file needed).
#pragma once

#include <vector>

#include "world_server/world/scenario.hpp"

namespace swarmform::world::testing {

// An open arena (no walls, no obstacles) with robots at the given poses; noise and loss off.
inline Scenario open_scenario(std::vector<Pose2D> robots) {
  Scenario s;
  s.walls = false;
  s.robots = std::move(robots);
  s.mission.max_speed = 2.0;
  return s;
}

inline Obstacle box(double cx, double cy, double width, double depth, double yaw = 0.0) {
  Obstacle o;
  o.kind = Obstacle::Kind::Box;
  o.centre = Vec2{cx, cy};
  o.half_extents = Vec2{width / 2.0, depth / 2.0};
  o.yaw = yaw;
  return o;
}

inline Obstacle cylinder(double cx, double cy, double radius) {
  Obstacle o;
  o.kind = Obstacle::Kind::Cylinder;
  o.centre = Vec2{cx, cy};
  o.radius = radius;
  return o;
}

}  // namespace swarmform::world::testing
