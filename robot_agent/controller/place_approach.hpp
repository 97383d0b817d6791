// A robot's way to a place that stands still, among obstacles only its ultrasonic sensors see
// (robot_agent/README.md, "the last approach" and "a piece that cannot hear its parent"): the desired
// velocity goes round each unexplained echo nearer than the place with eq. (1)'s go-round
// (collision_avoidance.hpp), on the place's side, as a Moving robot does in the formation phase. A robot that
// has not come kProgress nearer its place in kStuckTicks backs off in space: it drives to a point
// kDetourDistance away in a random direction (its own seeded generator: deterministic per run) for at most
// kDetourTicks, then makes for its place again (never within `there` of it: what is left is settling).
// Further than `bug_from` from its place it follows the obstacle's boundary instead of a random detour (Bug2:
// it leaves only nearer the place than where it began, by `there`), since random detours of 1 m never leave a
// concave obstacle (a U open towards the robot) far across; a boundary followed all the way round (a post
// whose far side is blocked) makes the next escape a random detour again. No
// committed side: between two obstacles (a gap between
// posts) "always right of an echo" is forwards past one and backwards past the other, and the robot stood.
#pragma once

#include <optional>
#include <random>
#include <string>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/collision_avoidance.hpp"
#include "robot_agent/controller/wall_follow.hpp"

namespace swarmform::controller::motion {

struct PlaceApproachParams {
  double k_collision = 0.002;
  double r_o = 0.35;
  double max_speed = 0.1;
  double there = 0.1;     // m from the place: not stuck, settling (arrival_tolerance)
  double bug_from = 1e9;  // m from the place: beyond it, stuck means boundary following, not a detour
  BoundaryFollowParams bug;
};

class PlaceApproach {
 public:
  void reset();
  // `desired`: the velocity towards `place` without obstacles; `echoes`: the unexplained echoes nearer than
  // the place, each as a robot standing there; `wall`: the nearest remembered echo point, for boundary
  // following, and `across` the far side of a passage there (BoundaryFollower::update). Appends "detour" to
  // `events` when it backs off, "boundary_follow_start SIDE" / "_end".
  Vec2 step(Vec2 position, Vec2 place, Vec2 desired, Tick tick, const std::vector<NeighbourPosition>& echoes,
            const std::optional<Vec2>& wall, const PlaceApproachParams& params, std::mt19937_64& rng,
            std::vector<std::string>& events, std::optional<double> across = std::nullopt);
  bool detouring() const { return detour_.has_value() || bug_.active(); }

 private:
  bool started_ = false;
  double best_ = 0.0;  // m, nearest to the place since the last progress
  Tick progress_tick_ = 0;
  int side_ = 0;  // 0: the place's side; -1 / +1: committed for the nearest echo
  std::optional<Vec2> detour_;
  Tick detour_until_ = 0;
  BoundaryFollower bug_;
  double bug_gap_ = 0.0;  // m from the place when the boundary following began
  bool bug_next_ = true;  // stuck next, follow the boundary (false after a loop: a random detour)
};

}  // namespace swarmform::controller::motion
