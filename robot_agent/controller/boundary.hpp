// Ready phase, part 1 (paper III.C 'Ready'): which robots are on the boundary of the shape.
//
// "The entire shape is analysed by local interactions by exchanging relative azimuth values among neighbors.
// From these interactions the bots on the boundaries are identified and are given roles of 'leftmost' and
// 'rightmost'." Each robot decides for itself from the azimuths of the neighbours it hears: it is on the LEFT
// boundary when no shape neighbour (within `max_range`, i.e. its 3x3 grid) stands within +-`cone_half_angle`
// of its left (heading + pi/2); on the RIGHT boundary likewise around heading - pi/2. With the default cone
// of pi/6, a neighbour straight beside you (pi/2) counts and a diagonal one (pi/4, 3pi/4) does not, so the
// left end of every row of the shape is a left boundary robot: the shape's left perimeter. A robot can be
// both (a row of one, e.g. the apex of a triangle). The result is shared through the stigmergy
// (encode_boundary_entry) so that every robot learns every robot's role and label.
#pragma once

#include <cstdint>
#include <vector>

#include "common/types.hpp"

namespace swarmform::controller::motion {

// A neighbour as the range-and-bearing sensor sees it, with the bearing turned into the arena frame
// (own heading + bearing), so that robots facing different ways compare the same angles.
struct NeighbourAzimuth {
  RobotId id = 0;
  double range = 0.0;    // m
  double azimuth = 0.0;  // rad, arena frame
};

struct BoundaryRole {
  bool left = false;
  bool right = false;
  bool any() const { return left || right; }
  friend bool operator==(const BoundaryRole&, const BoundaryRole&) = default;
};

// `heading`: the formation's common heading in the arena frame (rad).
BoundaryRole classify_boundary(const std::vector<NeighbourAzimuth>& neighbours, double heading,
                               double max_range, double cone_half_angle);

// The stigmergy value of key "boundary/<id>": the robot's label and its role in one integer,
// label * 4 + (left ? 1 : 0) + (right ? 2 : 0). Every robot of the shape writes one at Ready (role none
// included), so the table also maps ids to labels for the leader election and the parent tree.
std::int64_t encode_boundary_entry(int label, BoundaryRole role);
struct BoundaryEntry {
  int label = -1;
  BoundaryRole role;
};
BoundaryEntry decode_boundary_entry(std::int64_t value);

}  // namespace swarmform::controller::motion
