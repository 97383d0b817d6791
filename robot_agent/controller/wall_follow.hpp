// Small obstacles (paper III.E): "Upon encountering a smaller obstacle, wall-following behaviour is done only
// for the affected bot and the rest of the swarm is undisturbed."
//
// The affected robot leaves the formation forces for a while and circles the obstacle at `wall_distance`,
// on the side its desired motion (F_net, or F_goal for the leader) leans to, until the obstacle no longer
// lies ahead of that desired motion; then F_net pulls it back to its place: the shape fragments and rejoins.
//   enter: a SMALL obstacle (obstacle_forces.hpp) nearer than `enter_range` and ahead of the desired motion;
//   go:    v = speed * t + gain (r - wall_distance) o,  o the unit vector to the echo, t = o turned by +-pi/2
//          (the side is chosen once, on entry, so the robot never dithers between the two sides);
//   leave: the echo is gone, or it no longer lies ahead of the desired motion (o . d < 0).
#pragma once

#include "common/types.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"

namespace swarmform::controller::motion {

struct WallFollowParams {
  double enter_range = 0.6;    // m
  double wall_distance = 0.4;  // m, kept from the obstacle's surface
  double radial_gain = 0.5;    // 1/s
  double speed = 0.07;         // m/s, at least this fast around the obstacle
};

class WallFollower {
 public:
  // Returns true while wall-following; `velocity` is then the desired velocity (arena frame).
  // `desired`: what the robot would do without the obstacle (arena frame). `theta`: own heading.
  bool update(const ObstacleSense& sense, Vec2 desired, double theta, const WallFollowParams& params,
              Vec2& velocity);
  bool active() const { return active_; }
  void reset() { active_ = false; }

 private:
  bool active_ = false;
  int side_ = 1;  // +1: turn left of the obstacle direction (go round it clockwise), -1: right
};

}  // namespace swarmform::controller::motion
