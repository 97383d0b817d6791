// A moved goal: a place beyond a surface turns the shape (extends eq. 3 and its arrival for a goal that
// moves; robot_agent/README.md, "a moved goal"; docs/design-notes/goal-moves.md).
//
// The paper takes the shape to its goal in the orientation it formed in; a scenario's first goal is placed by
// its author where the shape fits, but a goal moved during the run is checked only as a point inside the
// walls (docs/scenario-format.md, "World events"). scenarios/goal_moves.yaml moves it back and aside to 2.5 m
// below a wall, and the V, 8 m wide across its old way, has its arm's last places 0.7 to 2.3 m beyond that
// wall wherever its centroid stands in the goal's radius: those robots stayed pinned at the wall and the
// shape was never formed there, with any radio. The world judges the shape under any rotation, so the shape
// turns, as a body turns that is pushed off-centre:
//   - a follower whose place is still (its parent at rest) and lies beyond a large obstacle's surface it
//     remembers (the echo nearer than its place, on the way to it) puts in the stigmergy (Blocked/<id>) the
//     torque with which the push off that surface turns the shape about its live centroid (push);
//   - the leader sums the live members' torques and, while the sum is on one side, turns the shape at the
//   rate
//     at which the outermost place moves at kRimShare x the speed limit, and puts the sum of its turns in the
//     stigmergy (Leader/1, microradians) (lead);
//   - every member turns its place offsets and its recorded references (eq. 2, kept in the shape's frame) by
//     that one value (turned, unturned). It stops when no place is blocked.
// Only once the goal has moved: runs whose goal never moves are unchanged (a place blocked at a first goal is
// motion-known-limits.md's).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/stigmergy.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

// What a follower's push reads of its motion this tick.
struct PushView {
  Vec2 position;
  Vec2 place;  // where its place stands, as its parent's readings put it
  bool place_still = false;
  Vec2 offset;  // its place's offset from the live centroid, in the shape's frame
  // The nearest remembered surface (EchoMemory::surface), asked only when a new surface is looked for.
  std::function<std::optional<Vec2>()> surface;
  bool large = false;              // the obstacle view sees a large obstacle (or has latched one)
  double arrival_tolerance = 0.0;  // m: at its place within this
};

class ShapeTurn {
 public:
  explicit ShapeTurn(Vec2 first_goal) : first_goal_(first_goal) {}

  // Every tick before the turn is used: the goal as it stands, and the turn the stigmergy agrees on. This
  // tick's push starts at 0.
  void observe(Vec2 goal, const Stigmergy& st);
  bool goal_moved() const { return goal_moved_; }
  Vec2 turned(Vec2 v) const { return turned_ ? vrotate(v, turn_) : v; }     // shape frame -> as it stands
  Vec2 unturned(Vec2 v) const { return turned_ ? vrotate(v, -turn_) : v; }  // as it stands -> shape frame

  // The leader, one tick: `counts` says whose push counts (a live member other than itself); `standing`: it
  // stands at its target (Arrived); `max_speed` (m/s) and `tick_rate` give how far the outermost place may
  // move a tick; `shape_radius`: m, the largest distance of a live place from the live centroid.
  void lead(Stigmergy& st, const std::function<bool(RobotId)>& counts, bool standing, double max_speed,
            double tick_rate, double shape_radius, std::vector<std::string>& events);
  // A follower in Motion, one tick: its push (mm), kept as the surface is; 0 when its place is free.
  void push(const PushView& view);
  // Not a follower with a place this tick (the leader, no live centroid): no push, the surface forgotten.
  void no_push() {
    push_ = 0;
    blocking_.reset();
  }
  // Writes this tick's push to the stigmergy when it changed, once the goal has moved.
  void publish(RobotId self, Stigmergy& st, std::vector<std::string>& events) const;

 private:
  Vec2 first_goal_;  // the mission's goal
  bool goal_moved_ = false;
  int turning_ = 0;        // the leader's last turning side (0: not turning)
  std::int64_t push_ = 0;  // mm: this tick's push (0: none)
  double turn_ = 0.0;
  bool turned_ = false;  // a leader has turned the shape (else every offset and reference as recorded)
  struct Blocking {
    Vec2 at;                 // the surface point found between the robot and its place
    Vec2 normal;             // unit, from the robot towards it then
    std::int64_t torque_mm;  // the push off it about the shape's centroid then
  };
  std::optional<Blocking> blocking_;  // kept while the place lies beyond it
};

}  // namespace swarmform::controller::motion
