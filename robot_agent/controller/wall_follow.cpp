#include "robot_agent/controller/wall_follow.hpp"

#include <algorithm>
#include <numbers>

#include "robot_agent/controller/motion_math.hpp"

namespace swarmform::controller::motion {

bool WallFollower::update(const ObstacleSense& sense, Vec2 desired, double theta,
                          const WallFollowParams& params, Vec2& velocity) {
  const bool seen = sense.size != ObstacleSize::None && sense.nearest < kUltrasonicMaxRange;
  const Vec2 o = vpolar(1.0, theta + sense.nearest_bearing);  // towards the nearest echo, arena frame
  const double d_norm = vnorm(desired);
  const Vec2 d_hat = d_norm > 1e-9 ? vscale(desired, 1.0 / d_norm) : vpolar(1.0, theta);
  const bool ahead = vdot(o, d_hat) > 0.0;

  if (!active_) {
    if (!seen || sense.size != ObstacleSize::Small || sense.nearest >= params.enter_range || !ahead) {
      return false;
    }
    active_ = true;
    // The side the desired motion leans to, seen from the obstacle direction (left when exactly behind it).
    const double cross = o.x * d_hat.y - o.y * d_hat.x;
    side_ = cross >= 0.0 ? 1 : -1;
  } else if (!seen || !ahead) {
    active_ = false;
    return false;
  }
  const Vec2 tangent = vrotate(o, side_ * std::numbers::pi / 2.0);
  const double speed = std::max(d_norm, params.speed);
  velocity =
      vadd(vscale(tangent, speed), vscale(o, params.radial_gain * (sense.nearest - params.wall_distance)));
  return true;
}

}  // namespace swarmform::controller::motion
