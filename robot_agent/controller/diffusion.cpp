#include "robot_agent/controller/diffusion.hpp"

#include <algorithm>
#include <cmath>

#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/robot_state.hpp"

namespace swarmform::controller {

int ir_avoid_turn(const std::array<double, kProximityCount>& proximity, double threshold) {
  // The front half of the ring: sensors at -90..+90 degrees (sin > 0: on the left). A reading weighs by how
  // close the body is.
  double ahead = 0.0;
  double left_minus_right = 0.0;
  for (std::size_t k = 0; k < kProximityCount; ++k) {
    const double a = kProximityAngles[k];
    if (std::cos(a) < -1e-9) continue;  // behind
    ahead = std::max(ahead, proximity[k]);
    left_minus_right += std::sin(a) * proximity[k];
  }
  if (ahead <= threshold) return 0;
  return left_minus_right >= 0.0 ? -1 : 1;
}

int lidar_open_side(const std::vector<LidarRay>& scan) {
  double left_minus_right = 0.0;  // each ray's range, signed by its side
  for (const LidarRay& r : scan) left_minus_right += std::sin(r.angle) * r.range;
  return left_minus_right > 0.0 ? 1 : left_minus_right < 0.0 ? -1 : 0;
}

void Diffusion::init(const Mission& mission, RobotId self) {
  mission_ = mission;
  self_ = self;
}

Command Diffusion::step(const Perception& perception) {
  double v = mission_.max_speed;
  if (perception.ground) {
    double g = 0.0;
    for (double r : *perception.ground) g += r;
    v *= 0.25 + 0.75 * g / static_cast<double>(kGroundCount);
  }
  Command cmd;
  cmd.left_speed = v;
  cmd.right_speed = v;
  if (perception.proximity) {
    if (int turn = ir_avoid_turn(*perception.proximity, kTurnThreshold); turn != 0) {
      if (const int open = lidar_open_side(perception.lidar); open != 0) turn = open;
      cmd.left_speed = -turn * v;
      cmd.right_speed = turn * v;
    }
  }
  cmd.message = encode_idle_beacon(self_, perception.pose);
  cmd.telemetry.state = static_cast<std::int32_t>(RobotState::Idle);
  return cmd;
}

}  // namespace swarmform::controller
