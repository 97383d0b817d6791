// Small obstacles (paper III.E): "Upon encountering a smaller obstacle, wall-following behaviour is done only
// for the affected bot and the rest of the swarm is undisturbed."
//
// The affected robot leaves the formation forces for a while and circles the obstacle at `wall_distance`
// until it is past it along the formation's direction of travel (its parent's velocity, which the parent
// broadcasts); then F_net pulls it back to its place: the shape fragments and rejoins.
//   enter: a SMALL obstacle (obstacle_forces.hpp) nearer than `enter_range`, seen by a front sensor (0 or
//          +-45 degrees), ahead of both the desired motion and the direction of travel;
//   go:    v = speed * t + gain (r - wall_distance) o,  o the unit vector to the echo, t = o turned by
//   +-pi/2.
//          The side is chosen once, on entry, so the robot never dithers: `side_hint` if not 0 (the motion
//          phase passes the side away from its neighbours: the robot leaves the shape on the outside),
//          else the side its desired motion leans to;
//   leave: the echo has been gone for kLostTicks (a post between two cones is followed where it was last
//          seen meanwhile), or it no longer lies ahead along the direction of travel (o . travel < 0).
//          Not the desired motion: while the robot's place crosses the obstacle, the place lies behind it
//          and the robot would circle it for ever. The size is not judged again on the way round: seen from
//          close by, a post fills two cones unequally and would read as large.
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
  // `desired`: what the robot would do without the obstacle; `travel`: the formation's direction of travel
  // (both arena frame; a zero `travel` means `desired`). `theta`: own heading.
  // `side_hint`: +1 turn left of the obstacle direction, -1 right, 0 no preference.
  bool update(const ObstacleSense& sense, Vec2 desired, Vec2 travel, double theta,
              const WallFollowParams& params, Vec2& velocity, int side_hint = 0);
  bool active() const { return active_; }
  void reset() {
    active_ = false;
    unseen_ = 0;
  }
  static constexpr int kLostTicks = 20;  // ticks out of sight before giving up the obstacle

 private:
  bool active_ = false;
  int side_ = 1;           // +1: turn left of the obstacle direction (go round it clockwise), -1: right
  Vec2 last_o_{1.0, 0.0};  // unit vector to the obstacle when last seen, arena frame
  int unseen_ = 0;         // ticks since it was last seen
};

}  // namespace swarmform::controller::motion
