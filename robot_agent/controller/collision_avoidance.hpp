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

#include <array>
#include <vector>

#include "common/types.hpp"

namespace swarmform::controller {

// |r_ij - r_o| is floored at this, m.
inline constexpr double kSingularityFloor = 0.05;
// The slide starts this much beyond r_o, m.
inline constexpr double kAwarenessMargin = 0.15;
// ...blended in over this much more, m.
inline constexpr double kBlendWidth = 0.15;

// Who gives way (the yield rule that breaks symmetric deadlocks; robot_agent/README.md). Two robots that
// avoid each other by the same rule mirror each other: two movers heading for one gap swapped sides every
// other tick for ever. So between two robots on the move one has the right of way: a Moving robot over a
// Searching one, and between two Moving robots the higher id (the paper's conflict rule: the higher id keeps
// the label).
enum class RightOfWay {
  Mutual,  // both go round each other (a standing robot, an obstacle's echo, two searchers)
  Theirs,  // it has the right of way: go round it and back away from it
  Ours,    // we have it: no go-round (it backs away); eq. (1) still acts inside r_o
};

struct NeighbourPosition {
  double range = 0.0;  // m, centre to centre (an echo: its reading + 2 body radii, as if a robot stood there)
  double azimuth = 0.0;  // rad, arena frame
  RightOfWay way = RightOfWay::Mutual;
  bool echo = false;  // an unexplained ultrasonic echo, not a robot heard
};

// The echoes of the ultrasonic sensors that no neighbour heard this tick explains (a dead robot's body, a
// wall, an obstacle; Algorithm 2's mask, as in the motion phases), as positions to keep clear of: the echo
// point seen as a robot standing there (range = reading + 2 body radii), right of way Mutual. Readings at
// or beyond `max_echo` are left out.
std::vector<NeighbourPosition> unexplained_echoes(const std::array<double, kUltrasonicCount>& readings,
                                                  double theta, const std::vector<NeighbourPosition>& heard,
                                                  double max_echo);

// eq. (1), summed over the neighbours closer than r_o.
Vec2 collision_force(const std::vector<NeighbourPosition>& neighbours, double k_collision, double r_o);

// The desired velocity after the task switch described above (unchanged when nobody is inside r_o).
// `side`: 0 goes round each neighbour on the goal's side (above); +1 always on an echo's right, -1 on its
// left, and with -1 a robot heard with the goal (nearly) straight behind it is passed on its left instead of
// its right. A robot that makes no progress commits to a side (bug-style boundary following), so it leaves a
// pocket between a body and a robot that the goal's side alternates between, or that the right-hand tie
// leads into. Robots heard are otherwise passed on the goal's side (a committed side for every robot made
// movers circle in the gaps between two reached robots).
Vec2 avoid_collisions(Vec2 desired, const std::vector<NeighbourPosition>& neighbours, double k_collision,
                      double r_o, double max_speed, int side = 0);

}  // namespace swarmform::controller
