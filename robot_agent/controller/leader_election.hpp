// Ready phase, part 2 (paper III.C 'Ready'): "From the set of boundary bots, a leader bot is elected by
// evaluating the relative azimuths of all the boundary bots."
//
// Our rule, the same on every robot because it reads only shared data (the stigmergy's boundary entries,
// which carry each robot's label and role, and the dead marks of the parents table) and the shape every robot
// was given: among the LIVE robots flagged left or right boundary, the one whose label's place lies furthest
// forward along the common heading; ties (places within 1 mm of each other along the heading) go to the
// smaller id. If no live boundary robot is left, every live robot is a candidate under the same rule. A
// leader that dies is simply no longer a candidate, so the same function elects its successor.
#pragma once

#include <optional>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/boundary.hpp"

namespace swarmform::controller::motion {

struct LeaderCandidate {
  RobotId id = 0;
  int label = -1;  // index into `places`
  BoundaryRole role;
  bool alive = true;
};

// `places`: each label's place in the arena frame (label_places), `heading`: the common heading (rad).
std::optional<RobotId> elect_leader(const std::vector<LeaderCandidate>& candidates,
                                    const std::vector<Vec2>& places, double heading);

}  // namespace swarmform::controller::motion
