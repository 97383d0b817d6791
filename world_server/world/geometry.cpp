#include "world_server/world/geometry.hpp"

namespace swarmform::world {

namespace {

void add_walls(const Scenario& s, std::vector<Obstacle>& out) {
  if (!s.walls) return;
  const double hw = s.arena_width / 2.0;
  const double hh = s.arena_height / 2.0;
  const double t = s.wall_thickness / 2.0;
  auto wall = [&](const char* name, double cx, double cy, double hx, double hy) {
    Obstacle o;
    o.kind = Obstacle::Kind::Box;
    o.name = name;
    o.centre = Vec2{s.arena_centre.x + cx, s.arena_centre.y + cy};
    o.half_extents = Vec2{hx, hy};
    out.push_back(o);
  };
  // Inner faces on the arena's edges; the east and west walls span the corners.
  wall("wall north", 0.0, hh + t, hw, t);
  wall("wall south", 0.0, -hh - t, hw, t);
  wall("wall east", hw + t, 0.0, t, hh + 2.0 * t);
  wall("wall west", -hw - t, 0.0, t, hh + 2.0 * t);
}

}  // namespace

std::vector<Obstacle> static_obstacles(const Scenario& s) {
  std::vector<Obstacle> out = s.obstacles;
  add_walls(s, out);
  return out;
}

std::vector<Obstacle> present_statics(const Scenario& s, const std::vector<Obstacle>& obstacles) {
  std::vector<Obstacle> out;
  for (const Obstacle& o : obstacles) {
    if (o.present) out.push_back(o);
  }
  add_walls(s, out);
  return out;
}

}  // namespace swarmform::world
