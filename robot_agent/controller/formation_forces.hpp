// Formation control (paper III.C 'Ready' and III.D): each follower keeps its place relative to its parent.
//
//   eq. (2)  F_ref = k_o r0^2 (cos a0 x + sin a0 y)   recorded once, at Ready, to the parent
//   eq. (4)  F_a   = k_o rt^2 (cos at x + sin at y)   the same, now, while the formation moves
//   eq. (5)  F_net = F_a - F_ref
//
// r is the distance to the parent and a its azimuth, both from the range-and-bearing sensor. We take the
// azimuth in the ARENA frame (own heading from the positioning sensor + bearing), not in the body frame: a
// differential-drive robot turns while it moves, and a body-frame azimuth would then read as the parent
// having moved. The paper's "shifted by pi" is the minus sign of eq. (5): F_ref turned by pi is -F_ref, a
// constant counter-force added to F_a. So F_net is exactly zero at the reference geometry, and when the
// parent moves by d, F_net ~ k_o r0 (d + (u.d) u) (u the unit vector to the parent): a spring pulling the
// follower after it, stiffer along the link than across it. The follower's desired velocity is F_net itself
// (k_o in 1/(m s)).
#pragma once

#include "common/types.hpp"

namespace swarmform::controller::motion {

// A parent as measured: distance (m) and azimuth in the arena frame (rad).
struct ParentMeasure {
  double range = 0.0;
  double azimuth = 0.0;
};

// eq. (2): the reference force, recorded at Ready (or when re-parenting).
Vec2 reference_force(double k_o, ParentMeasure at_ready);
// eq. (4): the attractive force now.
Vec2 attractive_force(double k_o, ParentMeasure now);
// eq. (5): the net formation force.
Vec2 net_force(Vec2 attractive, Vec2 reference);

}  // namespace swarmform::controller::motion
