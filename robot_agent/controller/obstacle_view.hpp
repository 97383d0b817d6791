// The motion phase's look at the obstacles, every tick in Motion (paper III.E): Algorithm 2's mask from the
// neighbours heard now, eq. (6)-(7)'s sensing with the desired motion's gain, the size discrimination
// (obstacle_forces.hpp), and the size latch: once a large obstacle is seen, whatever is seen next without a
// break of kLargeLatchTicks is still that obstacle (sliding along a wall, only the side sensor sees it, which
// alone would read as a post).
#pragma once

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

// `m`: eq. (7)'s gain (desired_motion.hpp); `theta`: the robot's heading.
ObstacleView look_at_obstacles(const NeighbourTable& neighbours, const UltrasonicArray& readings,
                               double theta, double m, const MotionParams& p);

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
