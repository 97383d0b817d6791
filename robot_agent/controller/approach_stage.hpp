// The motion phase's last approach, and a cut-off robot's way (robot_agent/README.md, "the last approach" and
// "a piece that cannot hear its parent"): a place that stands still within fusion_range, or a cut-off robot's
// own target, is reached as a Moving robot reaches its place in the formation phase (place_approach.hpp):
// straight, going round only the unexplained echoes nearer than the place (eq. 1's go-round), with a random
// detour when it makes no progress; no eq. (6), slide, wall- or boundary-following. Those keep an obstacle's
// range (0.6 m) or go round at wall_distance, so a dead robot's body standing beside a place (0.25-0.5 m off
// it) held its robot off for good, circling it, and a robot on its own among posts slid to and fro before
// every gap.
//
// A cut-off robot going round an obstacle's boundary towards a place that stands still keeps going round it
// while its own target is that same place (`same_search`: the same episode, side and Bug2 leave rule) until
// the episode ends: following a wall between it and its place took it out of its parent's radio range, where
// the cut-off robot's way made straight for the place again, back into range, and it was pinned again at the
// same spot, on the border of the radio range, for good (unseen/pocket.yaml --seed 104: a robot outside the
// room's wall, its place inside). An episode about a place that moved with the shape is no such search.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/collision_avoidance.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/place_approach.hpp"

namespace swarmform::controller::motion {

// Whether the approach takes this tick: the place stands still and is near (`near_place`), or the robot is
// cut off and not in the middle of a search round an obstacle for that same place.
inline bool approach_takes_over(bool place_still, bool near_place, bool alone, bool same_search) {
  return place_still && (near_place || (alone && !same_search));
}

// The echo points nearer than the place (`to_place` m from `position`), each seen as a robot standing a body
// radius beyond it (a post the cones swept past while the robot turned is still gone round); points at the
// place's distance or beyond are left out (they may be a body just beyond it).
std::vector<NeighbourPosition> echoes_before_place(const std::vector<Vec2>& points, Vec2 position,
                                                   double to_place);

class ApproachStage {
 public:
  // A new Ready phase; the detours' generator seeded from the run's seed and the id (deterministic per run).
  void reset(std::uint64_t seed, RobotId self);
  // Not approaching this tick (the next approach starts afresh).
  void idle() { approach_.reset(); }
  // One tick of the approach. `echoes`: eq. (6)'s memory, this tick's readings already added; `trace`: the
  // longer memory, for the boundary the approach may follow; `surface_within`: m, how near a remembered
  // surface counts.
  Vec2 step(Vec2 position, Vec2 place, Vec2 desired, Tick tick, EchoMemory& echoes, EchoMemory& trace,
            double surface_within, const PlaceApproachParams& params, std::vector<std::string>& events);

 private:
  PlaceApproach approach_;
  std::mt19937_64 rng_;  // its detours
};

}  // namespace swarmform::controller::motion
