#include "robot_agent/controller/random_walk.hpp"

#include <algorithm>
#include <cmath>

#include "common/splitmix64.hpp"
#include "robot_agent/controller/drive.hpp"
#include "robot_agent/controller/message.hpp"

namespace swarmform::controller {

void RandomWalk::init(const Mission& mission, RobotId self) {
  mission_ = mission;
  self_ = self;
  reset();
}

void RandomWalk::reset() {
  rng_.seed(splitmix64(mission_.seed ^ static_cast<std::uint64_t>(self_)));
  avoid_sign_ = 0;
  leg_ticks_left_ = 0;
  turn_rate_ = 0.0;
}

void RandomWalk::draw_leg() {
  // A leg of 2 to 6 s with a gentle turn: the walk covers ground instead of circling.
  std::uniform_real_distribution<double> turn(-0.5, 0.5);
  std::uniform_int_distribution<int> seconds(2, 6);
  turn_rate_ = turn(rng_);
  leg_ticks_left_ = static_cast<int>(std::lround(seconds(rng_) * mission_.tick_rate));
}

Command RandomWalk::step(const Perception& perception) {
  const double vmax = mission_.max_speed;
  Command cmd;

  // Obstacle: the side with the closer readings decides the turn; a head-on obstacle keeps the side chosen
  // at the start of the avoidance (no dithering between left and right).
  double closest = kUltrasonicMaxRange;
  double side = 0.0;  // > 0: the obstacle is on the left
  for (std::size_t i = 0; i < kUltrasonicCount; ++i) {
    const double r = perception.ultrasonic[i];
    if (!(r < kAvoidDistance)) continue;
    closest = std::min(closest, r);
    side += std::sin(kUltrasonicAngles[i]) * (kAvoidDistance - r);
  }
  if (closest < kAvoidDistance) {
    if (avoid_sign_ == 0) {
      if (side > 1e-9) {
        avoid_sign_ = -1;
      } else if (side < -1e-9) {
        avoid_sign_ = +1;
      } else {
        avoid_sign_ = std::uniform_int_distribution<int>(0, 1)(rng_) == 0 ? -1 : +1;
      }
    }
    // Spin on the spot away from it (no forward motion while something is that close in front).
    cmd.left_speed = -avoid_sign_ * vmax;
    cmd.right_speed = avoid_sign_ * vmax;
  } else {
    avoid_sign_ = 0;
    if (leg_ticks_left_ <= 0) draw_leg();
    --leg_ticks_left_;
    const double half_diff = std::clamp(turn_rate_ * kWheelSpacing / 2.0, -vmax, vmax);
    const double forward = vmax - std::abs(half_diff);
    cmd.left_speed = forward - half_diff;
    cmd.right_speed = forward + half_diff;
  }
  const auto wheels = clamp_wheels({cmd.left_speed, cmd.right_speed}, vmax);
  cmd.left_speed = wheels.left;
  cmd.right_speed = wheels.right;

  cmd.message = encode_idle_beacon(self_, perception.pose);
  cmd.telemetry.state = static_cast<std::int32_t>(RobotState::Idle);
  return cmd;
}

}  // namespace swarmform::controller
