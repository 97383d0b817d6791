// The motion phase's first stage, the desired motion (paper III.D): where a robot in Motion wants to go
// before any obstacle is considered, and eq. (7)'s obstacle gain that goes with it.
//
//   leader    eq. (3): F_goal from its own place to its target (the goal plus its place's offset from the
//   live
//             shape's centroid), at the cruise speed scaled down by the shape's strain ("Pace").
//   cut off   (no parent, or one alive but unheard): eq. (3) on its own place, at the speed limit.
//   follower  eq. (5)'s F_net towards where its parent puts its place, plus the parent's broadcast velocity
//             (the feed-forward); the parent's vector from this tick's reading, from the mean of where it was
//             heard since it came to rest, or, unheard, dead-reckoned from where and how fast it last was.
//
// Each also says where its motion leads (`place`) and whether that place stands still (a target does; a
// follower's while its parent is at rest or crawls), which the later stages read, and whether the robot has
// arrived (the stage never moves an arrived robot).
#pragma once

#include <optional>

#include "common/types.hpp"
#include "robot_agent/controller/motion_params.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

// A running sum of points, for their mean.
struct PointSum {
  Vec2 total;
  int count = 0;
  void add(Vec2 p) {
    total = vadd(total, p);
    ++count;
  }
  Vec2 mean() const { return vscale(total, 1.0 / count); }
};

enum class Arrival { None, WithShape, Alone };

struct Desire {
  Vec2 velocity;                  // the desired velocity, arena frame
  Vec2 place;                     // where it leads
  bool place_still = false;       // that place stands still
  bool alone = false;             // cut off from its parent: it makes for its own target
  double m = 0.0;                 // eq. (7)'s obstacle gain
  double net_force = 0.0;         // |F_net| (followers)
  double lag = 0.0;               // F_net's part towards the goal (>= 0): the robot's strain (followers)
  std::optional<Vec2> to_parent;  // the vector to the parent this tick (followers; a cut-off robot: zero)
  Arrival arrival = Arrival::None;
};

// eq. (7)'s m for a pull of `speed`, never below its floor (a tenth of the cruise: the slide needs a
// direction even as the shape comes to rest).
double obstacle_gain(double speed, const MotionParams& p);

// The leader: eq. (3) to `target`, arrived within `stop_distance`; the cruise scaled by the strain its
// children report.
Desire leader_desire(Vec2 position, Vec2 target, double stop_distance, double children_strain,
                     const MotionParams& p);

// A robot cut off from its parent: eq. (3) to its own target at the speed limit, arrived within
// arrival_tolerance.
Desire cut_off_desire(Vec2 position, Vec2 target, const MotionParams& p);

// What a follower knows of its parent this tick.
struct ParentView {
  RobotId id = 0;
  Vec2 reference;                     // eq. (2)'s r0 to the parent
  std::optional<Vec2> last_position;  // where it was when last heard (arena frame)
  Vec2 last_velocity;                 // the velocity it said it had then
};

// A follower's eq. (5) with the feed-forward. Its state: the parent's position averaged since it came to
// rest (noise in range and bearing averaged away; one noisy reading let a follower arrive off its place).
class FollowerDesire {
 public:
  void reset() {
    rest_ = {};
    resting_parent_.reset();
  }
  Desire step(const NeighbourTable& neighbours, Vec2 position, Tick tick, double tick_rate,
              const ParentView& parent, const MotionParams& p);

 private:
  PointSum rest_;                          // where the parent was heard since it came to rest (arena frame)
  std::optional<RobotId> resting_parent_;  // the parent rest_ is about
};

}  // namespace swarmform::controller::motion
