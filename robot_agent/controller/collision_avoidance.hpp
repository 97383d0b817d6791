// Collision avoidance among robots while the shape forms (paper III.C 'Moving', eq. 1):
//
//   F_collision = sum over neighbours j with r_ij < r_o of  -k_collision / (r_ij - r_o)^2 (cos a_ij x + sin
//   a_ij y)
//
// a_ij the azimuth of j seen from i (arena frame here, so the force is in the arena frame), r_ij its range.
// As printed, the magnitude is infinite at r_ij = r_o; we floor |r_ij - r_o| at kSingularityFloor (so the
// push at the threshold is k/floor^2, 0.8 m/s with the defaults, i.e. the speed limit) and write it down in
// robot_agent/README.md. The paper: "the task changes from reaching the desired position to avoiding
// collision as a combined force could lead to an equilibrium point" -- so while any neighbour is within r_o
// (plus kAwarenessMargin, so that a robot does not chatter in and out of the threshold) the desired velocity
// loses its component towards that neighbour and goes round it at the desired speed, on the side of the goal
// (on the right when the goal is right behind it, so two robots meeting head-on do not mirror each other
// forever); inside r_o the repulsion, capped at the speed limit, is added.
#pragma once

#include <vector>

#include "common/types.hpp"

namespace swarmform::controller {

// |r_ij - r_o| is floored at this, m.
inline constexpr double kSingularityFloor = 0.05;
// The slide starts this much beyond r_o, m.
inline constexpr double kAwarenessMargin = 0.15;
// ...blended in over this much more, m.
inline constexpr double kBlendWidth = 0.15;

struct NeighbourPosition {
  double range = 0.0;    // m
  double azimuth = 0.0;  // rad, arena frame
};

// eq. (1), summed over the neighbours closer than r_o.
Vec2 collision_force(const std::vector<NeighbourPosition>& neighbours, double k_collision, double r_o);

// The desired velocity after the task switch described above (unchanged when nobody is inside r_o).
Vec2 avoid_collisions(Vec2 desired, const std::vector<NeighbourPosition>& neighbours, double k_collision,
                      double r_o, double max_speed);

}  // namespace swarmform::controller
