// The motion phase's boundary episode: a robot pinned at an obstacle (progress_window.hpp) with an echo
// remembered near follows the obstacle's boundary (BoundaryFollower, wall_follow.hpp) until the way is clear.
// This stage decides when an episode starts, which way round it goes, and when it may leave:
//
//   way round  towards the side of the desired motion the parent stands on, when it clearly stands on one
//              (it is inside the shape, where the way was clear: a corner robot held at a box goes round its
//              inner end, not its outer one), else the tangent nearer the desired motion; a head-on tie goes
//              to a side drawn from the run's seed and the id (two robots pinned face to face do not both
//              pick the same way).
//   Bug's rule pinned again no nearer its place than when it last chose (by less than the distance it keeps
//              from the obstacle, which going round can gain without getting past), the same obstacle or
//              cluster still blocks it: the same way round, its time on that side running on (the dead-end
//              turn-back still comes). Choosing afresh each time made a robot among posts alternate sides
//              every few dozen ticks and stay where it was (posts.yaml, seed 2: for 5,000 ticks).
//   Bug2's leave rule  while its place stands where it stood when the episode began, it leaves only nearer
//              that place than it was then (by arrival_tolerance). Leaving wherever the pull pointed away
//              from the obstacle let it back into a concave obstacle (a U open towards it), where the leader
//              ran between the U's corners for good. A place that moved (a follower's, with the shape) is no
//              fixed point to measure progress against: then it leaves as soon as the way is clear.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/wall_follow.hpp"

namespace swarmform::controller::motion {

inline constexpr Tick kTraceTicks = 60;  // the trace's memory of echoes (boundary episodes, the approach)

// What the episode reads of this tick.
struct EpisodeInputs {
  Vec2 position;
  Vec2 desired;              // the desired motion (desired_motion.hpp)
  Vec2 place;                // where it leads
  bool place_still = false;  // and whether that place stands still
  Vec2 to_parent;            // the vector to the parent (zero: none, or the leader)
  Tick tick = 0;
};

class BoundaryEpisode {
 public:
  // The robot's seeded tie-break side (+1 / -1) for a head-on pin.
  static int tie_break(std::uint64_t seed, RobotId self);

  // A new Ready phase: no episode, no way round remembered.
  void reset() {
    follower_.reset();
    side_ = 0;
    turns_ = 0;
  }
  // The episode ends without a word (arrival, the approach takes over); the way round stays remembered.
  void end() { follower_.reset(); }
  bool active() const { return follower_.active(); }
  // The episode is about a place within `keep` of `place` (the same search).
  bool about(Vec2 place, double keep) const { return vnorm(vsub(place, hit_place_)) < keep; }

  // Begins an episode at the remembered echo `echo` (Bug's rule for the way round); appends
  // "boundary_follow_start SIDE".
  void start(const EpisodeInputs& in, Vec2 echo, int tie, const BoundaryFollowParams& params,
             std::vector<std::string>& events);
  // While active: the velocity round the boundary, or none once it leaves (appends "boundary_follow_end").
  // `echo`: the nearest remembered echo point; `trace` answers the passage's far side.
  std::optional<Vec2> follow(const EpisodeInputs& in, const std::optional<Vec2>& echo, EchoMemory& trace,
                             double arrival_tolerance, const BoundaryFollowParams& params,
                             std::vector<std::string>& events);
  int side() const { return follower_.side(); }

 private:
  BoundaryFollower follower_;
  int side_ = 0;    // the way round last taken (0: none yet), since since_, first chosen
  Tick since_ = 0;  // gap_ m from its place, turned back turns_ times
  double gap_ = 0.0;
  int turns_ = 0;
  Vec2 hit_place_;        // this episode began with its place here,
  double hit_gap_ = 0.0;  // this far from it (Bug2's leave rule)
};

}  // namespace swarmform::controller::motion
