// The motion phase's look at the obstacles, every tick in Motion (paper III.E): Algorithm 2's mask from the
// neighbours heard now, eq. (6)-(7)'s sensing with the desired motion's gain, the size discrimination
// (obstacle_forces.hpp), and the size latch: once a large obstacle is seen, whatever is seen next without a
// break of kLargeLatchTicks is still that obstacle (sliding along a wall, only the side sensor sees it, which
// alone would read as a post).
#pragma once

#include <map>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/motion_params.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"

namespace swarmform::controller::motion {

struct ObstacleView {
  UltrasonicArray readings{};
  SensorMask mask{};
  ObstacleSense sense;
};

// The neighbours whose bodies explain echoes this tick (Algorithm 2's mask): those heard now, at their range
// and bearing; and those in the table not heard now, at the place their last position and broadcast velocity
// give them, uncertain by the speed limit times the time since. A neighbour missed for some ticks (its copies
// lost) is not gone: masked only when heard, its body read as an obstacle on each tick its message was lost,
// remembered as one (eq. 6, the trace of boundary episodes, a post to wall-follow) for up to 60 ticks, and a
// shape under 20 % loss started boundary episodes 2-3 m from any obstacle. The table's own timeout
// (neighbour_timeout) bounds the time since, so the uncertainty stays under the speed limit x that time.
std::vector<NeighbourBearing> neighbours_to_mask(const NeighbourTable& neighbours, const Pose2D& pose,
                                                 double tick_rate, double max_speed,
                                                 const std::map<RobotId, Vec2>& last_position,
                                                 const std::map<RobotId, Vec2>& last_velocity);

// `neighbours`: neighbours_to_mask's; `m`: eq. (7)'s gain (desired_motion.hpp); `theta`: the robot's heading.
ObstacleView look_at_obstacles(const std::vector<NeighbourBearing>& neighbours,
                               const UltrasonicArray& readings, double theta, double m,
                               const MotionParams& p);

class LargeObstacleLatch {
 public:
  static constexpr Tick kLargeLatchTicks = 30;
  // Turns a small obstacle seen within kLargeLatchTicks of a large one into a large one (and keeps the
  // latch).
  void apply(ObstacleSense& sense, Tick tick);
  void reset() { until_ = 0; }

 private:
  Tick until_ = 0;  // a large obstacle was seen lately: no wall-following
};

}  // namespace swarmform::controller::motion
