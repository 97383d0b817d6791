#include "robot_agent/controller/phototaxis.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/diffusion.hpp"
#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/robot_state.hpp"

namespace swarmform::controller {

void Phototaxis::init(const Mission& mission, RobotId self) {
  mission_ = mission;
  self_ = self;
}

Command Phototaxis::step(const Perception& perception) {
  const double v = mission_.max_speed;
  Command cmd;
  const bool spent = perception.battery && *perception.battery < kReserve;
  int avoid = 0;
  if (perception.proximity) avoid = ir_avoid_turn(*perception.proximity, kTurnThreshold);
  if (spent) {
    // Keep still: the rest of the charge is for being found.
  } else if (avoid != 0) {
    cmd.left_speed = -avoid * v;
    cmd.right_speed = avoid * v;
  } else if (perception.light) {
    // The light's direction in the robot frame: the sensors' directions weighted by their readings.
    double x = 0.0, y = 0.0;
    for (std::size_t k = 0; k < kLightCount; ++k) {
      x += std::cos(kProximityAngles[k]) * (*perception.light)[k];
      y += std::sin(kProximityAngles[k]) * (*perception.light)[k];
    }
    if (x * x + y * y < 1e-12) {
      cmd.left_speed = -0.3 * v;  // nothing seen: turn on the spot, counter-clockwise, to look for it
      cmd.right_speed = 0.3 * v;
    } else {
      // Turn rate proportional to the bearing; forward speed falls off as the light gets to the side.
      const double bearing = std::atan2(y, x);
      const double forward = v * std::max(0.0, std::cos(bearing));
      const double turn = std::clamp(bearing / (std::numbers::pi / 2.0), -1.0, 1.0) * v;
      cmd.left_speed = std::clamp(forward - turn, -v, v);
      cmd.right_speed = std::clamp(forward + turn, -v, v);
    }
  }
  cmd.message = encode_idle_beacon(self_, perception.pose);
  cmd.telemetry.state = static_cast<std::int32_t>(RobotState::Idle);
  return cmd;
}

}  // namespace swarmform::controller
