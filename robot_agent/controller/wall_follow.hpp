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

#include <optional>

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

namespace swarmform::controller::motion {

// Boundary following (Bug-style) for a robot pinned at an obstacle (motion_phase.hpp, "pinned"): a large
// obstacle, a dead robot's body or a corner between them that eq. (6) and the slide cannot get it past (it
// turns on the spot, its cones sweeping on and off the obstacle). It commits to one way round and keeps the
// nearest remembered echo point at `keep` (robot centre to echo), at `speed`, whatever the cones see this
// tick:
//   v = speed t - gain (|p - e| - keep) u,   u = (p - e)/|p - e|,   t = u turned by side * pi/2
// side +1: counter-clockwise about the obstacle (it on the robot's left), -1 clockwise. It leaves once the
// desired motion no longer leads into the obstacle (desired . (e - p) <= 0, after `min_ticks`) and the caller
// allows it (`may_leave`: the leader leaves only nearer its goal than where it began, Bug2's rule; see
// boundary_episode.hpp), or when nothing is remembered near any more. After `max_ticks` on one side it turns
// back the other way (a dead end), and each later turn-back waits twice as long as the one before: a boundary
// of any finite length is searched both ways in the end (a fixed period turned a leader back before it could
// round a long wall). Back within `keep` of where it began (or last turned back) after going more than 2 x
// `keep` from there, it has
// gone all the way round (Bug2's sign that the goal cannot be reached this way round: a post among posts, the
// way past it blocked by the next one): `looped()`, and from then on it leaves as soon as the way is clear,
// whatever the caller allows. The side on entry: the tangent nearer the desired motion; a tie (head-on) goes
// to `tie_break`. In a passage narrower than 2 x `keep` (an echo across the robot from the surface) it keeps
// to the middle, and when the nearest surface changes sides there it follows the other side with the other
// hand (the way along the passage holds). An episode that took a passage and then makes less than `keep` of
// way in 100 ticks (going round on the spot, a cell of posts and bodies): the passages are closed for the
// episode; the second time, `looped()`.
struct BoundaryFollowParams {
  double keep = 0.4;         // m, robot centre to the nearest echo point
  double speed = 0.1;        // m/s
  double radial_gain = 1.0;  // 1/s
  Tick min_ticks = 20;
  Tick max_ticks = 600;
};

class BoundaryFollower {
 public:
  static int choose_side(Vec2 position, Vec2 echo, Vec2 desired, int tie_break);
  // `side_since`: when this side was first taken (a robot pinned again by the same obstacle keeps its way
  // round and its time on it; boundary_episode.hpp); by default now.
  // `turns`: how often it already turned back on this obstacle (its next turn-back waits 2^turns x
  // max_ticks).
  void start(int side, Tick tick, std::optional<Tick> side_since = std::nullopt, int turns = 0) {
    active_ = true;
    side_ = side;
    started_ = tick;
    since_ = side_since.value_or(tick);
    turns_ = turns;
    hit_.reset();
    last_u_.reset();
    stall_from_.reset();
    passages_closed_ = false;
    took_passage_ = false;
    away_ = false;
    looped_ = false;
  }
  // `echo`: the nearest remembered echo point (arena frame), none if nothing is remembered near.
  // `across`: the distance to the nearest echo across the robot from `echo` (EchoMemory::across), if any.
  // In a passage narrower than 2 x `keep` (a dead robot's body in an opening, two posts close together) it
  // keeps to the passage's middle instead of `keep` from one side: a boundary follower that kept `keep`
  // took both sides for one obstacle and went round them, never through a passage it fits through.
  bool update(const std::optional<Vec2>& echo, Vec2 position, Vec2 desired, Tick tick,
              const BoundaryFollowParams& params, Vec2& velocity, bool may_leave = true,
              std::optional<double> across = std::nullopt);
  bool active() const { return active_; }
  int side() const { return side_; }
  Tick since() const { return since_; }  // when it took this side
  int turns() const { return turns_; }
  bool looped() const { return looped_; }
  void reset() { active_ = false; }

 private:
  bool active_ = false;
  int side_ = 1;
  Tick since_ = 0;                  // on this side since
  Tick started_ = 0;                // this episode since
  int turns_ = 0;                   // turn-backs so far
  std::optional<Vec2> hit_;         // where this episode began
  bool away_ = false;               // it has been more than 2 x keep from there
  bool looped_ = false;             // and came back: all the way round
  std::optional<Vec2> last_u_;      // last tick's direction from the surface to the robot
  std::optional<Vec2> stall_from_;  // where the last stall window began, and when
  Tick stall_tick_ = 0;
  bool passages_closed_ = false;  // it circled on the spot in passages: keep from the nearest surface again
  bool took_passage_ = false;     // this episode kept to a passage's middle at least once
};

}  // namespace swarmform::controller::motion
