#include "robot_agent/controller/wall_follow.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/motion_math.hpp"

namespace swarmform::controller::motion {

bool WallFollower::update(const ObstacleSense& sense, Vec2 desired, Vec2 travel, double theta,
                          const WallFollowParams& params, Vec2& velocity, int side_hint) {
  const bool seen = sense.size != ObstacleSize::None && sense.nearest < kUltrasonicMaxRange;
  const double d_norm = vnorm(desired);
  const Vec2 d_hat = d_norm > 1e-9 ? vscale(desired, 1.0 / d_norm) : vpolar(1.0, theta);
  const Vec2 t_hat = vnorm(travel) > 1e-9 ? vscale(travel, 1.0 / vnorm(travel)) : d_hat;
  double distance = sense.nearest;
  if (seen) {
    last_o_ = vpolar(1.0, theta + sense.nearest_bearing);  // towards the nearest echo, arena frame
    unseen_ = 0;
  }

  if (!active_) {
    // Only what the front sensors see blocks the way (something seen only at +-90 degrees is beside us).
    const bool in_front = std::abs(sense.nearest_bearing) < 1.0;
    const bool ahead = vdot(last_o_, d_hat) > 0.0 && vdot(last_o_, t_hat) > 0.0;
    if (!seen || sense.size != ObstacleSize::Small || sense.nearest >= params.enter_range || !ahead ||
        !in_front) {
      return false;
    }
    active_ = true;
    // The side the desired motion leans to, seen from the obstacle direction (left when exactly behind it).
    const double cross = last_o_.x * d_hat.y - last_o_.y * d_hat.x;
    side_ = side_hint != 0 ? side_hint : (cross >= 0.0 ? 1 : -1);
  } else {
    // Out of sight for a moment (it fell between two cones while turning): keep going round where it was,
    // curving in towards it to find it again.
    if (!seen && ++unseen_ > kLostTicks) active_ = false;
    if (vdot(last_o_, t_hat) < 0.0) active_ = false;  // past it along the direction of travel
    if (!active_) return false;
    if (!seen) distance = params.wall_distance + 0.1;
  }
  const Vec2 tangent = vrotate(last_o_, side_ * std::numbers::pi / 2.0);
  const double speed = std::max(d_norm, params.speed);
  velocity =
      vadd(vscale(tangent, speed), vscale(last_o_, params.radial_gain * (distance - params.wall_distance)));
  return true;
}

}  // namespace swarmform::controller::motion
