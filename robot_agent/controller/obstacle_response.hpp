// The motion phase's response to a large obstacle (paper III.E): eq. (6) repulsion over the echoes remembered
// for a moment (obstacle_forces.hpp: EchoMemory), and the slide. The part of the desired motion that pushes
// into the obstacle is dropped, so the robot slides along it instead of stalling against it. Head-on it also
// slides sideways: towards its parent's side (inside the shape, where the way is clear); the leader, or a
// robot whose parent stands straight behind it, towards its neighbours (the perimeter gives way inwards and
// the shape shrinks on that side); with no neighbour near, the way the slide already leans. The side is
// judged against the remembered obstacle and kept until the obstacle has been gone for the echo memory's
// span, so a robot never swings from one side to the other.
//
// Head-on is a wall ahead only if something remembered lies on the way: between two obstacles on either side
// (a gap between posts, 0.8-1 m) the summed repulsion also points straight back, and dropping the desired
// motion along it turned every such gap into a dead end (posts.yaml: lone robots and leaders slid to and fro
// before a gap for thousands of ticks). There eq. (6) alone, against the full desired motion, takes the robot
// through.
#pragma once

#include "common/types.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"

namespace swarmform::controller::motion {

inline constexpr Tick kEchoMemoryTicks = 15;  // eq. (6)'s memory of echoes (obstacle_forces.hpp: EchoMemory)

// Which way round an obstacle in direction `o` (unit, arena frame) leads away from the neighbours: +1 turning
// left of `o`, -1 right, 0 when both sides are alike. Each neighbour heard this tick within `reach` weighs by
// how much it stands on that side, nearer ones more.
int side_away_from_neighbours(const NeighbourTable& table, Vec2 o, double reach);

// The slide's state: the head-on side (0: none yet), kept while the obstacle is near.
struct SlideState {
  int side = 0;
  Tick last_obstacle_tick = 0;
};

struct ResponseInputs {
  Vec2 position;
  Vec2 desired;    // the desired motion (desired_motion.hpp)
  double m = 0.0;  // eq. (7)'s gain
  bool has_parent = false;
  Vec2 to_parent;  // zero when unknown
  Tick tick = 0;
  double obstacle_range = 0.6;   // m, eq. (6)'s R
  double neighbour_reach = 1.5;  // m: the neighbours that count for the head-on side
};

// eq. (6) over `echoes` (this tick's already added) and the slide: the velocity to drive.
Vec2 respond_to_obstacles(SlideState& slide, EchoMemory& echoes, const NeighbourTable& neighbours,
                          const ResponseInputs& in);

}  // namespace swarmform::controller::motion
