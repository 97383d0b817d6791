// Rigid-body physics of the arena: the only part of swarmform that includes Bullet (physics.cpp), so no
// Bullet type appears here. Robots are planar differential-drive Khepera IV bodies; walls and obstacles are
// static; a dead robot is a static body that still collides. Contact onsets are counted per tick.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

struct ContactCounts;  // world.hpp

class Physics {
 public:
  // Adds, in this fixed order (Bullet is bit-reproducible only for the same bodies added in the same order):
  // the static bodies of static_obstacles(scenario), then robots 0..N-1 at their initial poses.
  explicit Physics(const Scenario& scenario);
  ~Physics();
  Physics(const Physics&) = delete;
  Physics& operator=(const Physics&) = delete;

  // Wheel rim speeds (m/s) used for every substep of the next tick_forward().
  void set_wheels(RobotId id, double left, double right);
  // A failed wheel (faults.hpp): the stored speed of the left (side 0) or right (1) wheel becomes 0.
  void stop_wheel(RobotId id, int side);

  // One tick: `substeps` Bullet steps of 1/(tick_rate*substeps) s, the velocities re-set from the wheel
  // speeds before each (v = (l+r)/2 along the heading, w = (r-l)/wheel_spacing), contacts collected.
  void tick_forward();

  // Writes the robots' poses (arena frame, theta in (-pi, pi]) into `out` (resized to N).
  void read_poses(std::vector<Pose2D>& out) const;
  Pose2D pose(RobotId id) const;

  // Obstacle `index` of static_obstacles(scenario) as it now stands (world_events.hpp): moved to its centre
  // and yaw, and out of the dynamics world while it is not present (its body is kept, in its place in order).
  void set_obstacle(std::size_t index, const Obstacle& obstacle);

  // Dead: a static body where it stands (wheels zeroed). Alive again: a dynamic body, wheels zero.
  void set_dead(RobotId id, bool dead);

  // Contact onsets of the last tick_forward(): pairs touching (within 0.5 mm) at some substep of this tick
  // that touched at no substep of the previous tick. A pair with a dead robot counts as robot-obstacle.
  std::uint32_t onsets_robot_robot() const;
  std::uint32_t onsets_robot_obstacle() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::world
