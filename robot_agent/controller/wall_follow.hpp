// Small obstacles (paper III.E): "Upon encountering a smaller obstacle, wall-following behaviour is done only
// for the affected bot and the rest of the swarm is undisturbed."
//
// The affected robot leaves the formation forces for a while and goes round the obstacle, then F_net pulls
// it back to its place: the shape fragments and rejoins.
//   enter: a SMALL obstacle (obstacle_forces.hpp) nearer than `enter_range`, seen by a front sensor (0 or
//          +-45 degrees), ahead of both the desired motion and the formation's direction of travel (the
//          parent's broadcast velocity).
//   go:    round a circle about the obstacle's centre as estimated on entry (the echo point pushed
//          `obstacle_radius` further along the echo direction), of radius obstacle_radius + robot radius +
//          `wall_distance`: v = speed t - gain (|p - c| - R) u, u the unit vector from the centre to the
//          robot and t = u turned by +-pi/2. The way round is chosen once, on entry: `side_hint` if not 0
//          (the motion phase passes the side away from its neighbours, so the robot leaves the shape on the
//          outside), else the side the desired motion leans to. The circle is followed from the positioning
//          sensor, not from the echoes: a differential-drive robot turning round a post sweeps its cones over
//          it, and echoes that come and go would make it dither on the spot.
//   leave: past the centre along the direction of travel, (p - c) . travel > 0; or at once when three
//          adjacent cones see it (no post is that wide: it was a wall's corner, which the motion phase then
//          treats as a large obstacle).
#pragma once

#include "common/types.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"

namespace swarmform::controller::motion {

struct WallFollowParams {
  double enter_range = 0.6;       // m
  double wall_distance = 0.4;     // m, kept from the obstacle's surface
  double radial_gain = 0.5;       // 1/s
  double speed = 0.07;            // m/s, at least this fast around the obstacle
  double obstacle_radius = 0.25;  // m, assumed radius of a small obstacle (half the small-obstacle width)
};

class WallFollower {
 public:
  // Returns true while going round; `velocity` is then the desired velocity (arena frame).
  // `desired`: what the robot would do without the obstacle; `travel`: the formation's direction of travel
  // (both arena frame; a zero `travel` means `desired`).
  // `side_hint`: +1 the obstacle on the robot's right (round it counter-clockwise), -1 on its left, 0 none.
  bool update(const ObstacleSense& sense, Vec2 desired, Vec2 travel, const Pose2D& pose,
              const WallFollowParams& params, Vec2& velocity, int side_hint = 0);
  bool active() const { return active_; }
  void reset() { active_ = false; }
  Vec2 centre() const { return centre_; }

 private:
  bool active_ = false;
  int side_ = 1;
  Vec2 centre_;        // estimated centre of the obstacle, arena frame
  Vec2 travel_{1, 0};  // unit direction of travel at entry (used when no travel is known)
};

}  // namespace swarmform::controller::motion
