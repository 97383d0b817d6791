#include "robot_agent/controller/drive.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller {

namespace {

// rad/s of turn per rad of heading error. At 10 ticks/s a gain of 3 closes ~30% of the error per tick: fast
// but without overshoot at the tick rate.
constexpr double kTurnGain = 3.0;

}  // namespace

WheelSpeeds clamp_wheels(WheelSpeeds w, double max_speed) {
  if (!std::isfinite(w.left) || !std::isfinite(w.right)) return {};
  const double biggest = std::max(std::abs(w.left), std::abs(w.right));
  if (biggest > max_speed && biggest > 0.0) {
    const double k = max_speed / biggest;
    w.left *= k;
    w.right *= k;
  }
  return w;
}

WheelSpeeds drive_velocity(Vec2 velocity, double heading, double max_speed, bool may_reverse) {
  const double speed = std::min(vnorm(velocity), max_speed);
  if (!(speed > 1e-9)) return {};
  double error = wrap_angle(std::atan2(velocity.y, velocity.x) - heading);
  double direction = 1.0;
  if (may_reverse && std::abs(error) > std::numbers::pi / 2.0) {  // behind: drive backwards
    direction = -1.0;
    error = wrap_angle(error + std::numbers::pi);
  }
  // Forward speed falls with the heading error (cos), so the robot turns first when far off course.
  const double forward = direction * speed * std::max(0.0, std::cos(error));
  const double turn = kTurnGain * error;  // rad/s
  const double half_diff = std::clamp(turn * kWheelSpacing / 2.0, -max_speed, max_speed);
  // The turn has priority: the forward part gets what is left of the limit.
  const double room = max_speed - std::abs(half_diff);
  const double fwd = std::clamp(forward, -room, room);
  return clamp_wheels({fwd - half_diff, fwd + half_diff}, max_speed);
}

WheelSpeeds turn_towards(double target_heading, double heading, double max_speed) {
  const double error = wrap_angle(target_heading - heading);
  const double half_diff = std::clamp(kTurnGain * error * kWheelSpacing / 2.0, -max_speed, max_speed);
  return {-half_diff, half_diff};
}

}  // namespace swarmform::controller
