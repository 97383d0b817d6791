#include "robot_agent/controller/wall_follow.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

bool WallFollower::update(const ObstacleSense& sense, Vec2 desired, Vec2 travel, const Pose2D& pose,
                          const WallFollowParams& params, Vec2& velocity, int side_hint) {
  const Vec2 position{pose.x, pose.y};
  const double d_norm = vnorm(desired);
  const Vec2 d_hat = d_norm > 1e-9 ? vscale(desired, 1.0 / d_norm) : vpolar(1.0, pose.theta);
  const Vec2 t_hat = vnorm(travel) > 1e-9 ? vscale(travel, 1.0 / vnorm(travel)) : (active_ ? travel_ : d_hat);

  if (!active_) {
    const bool seen = sense.size != ObstacleSize::None && sense.nearest < kUltrasonicMaxRange;
    if (!seen) return false;
    const Vec2 o = vpolar(1.0, pose.theta + sense.nearest_bearing);  // towards the echo, arena frame
    const bool in_front = std::abs(sense.nearest_bearing) < 1.0;     // 0 or +-45 degrees
    const bool ahead = vdot(o, d_hat) > 0.0 && vdot(o, t_hat) > 0.0;
    if (sense.size != ObstacleSize::Small || sense.nearest >= params.enter_range || !ahead || !in_front) {
      return false;
    }
    active_ = true;
    centre_ = vadd(position, vscale(o, sense.nearest + kRobotRadius + params.obstacle_radius));
    travel_ = t_hat;
    // Left of the obstacle direction is where the desired motion leans (when no hint).
    const double cross = o.x * d_hat.y - o.y * d_hat.x;
    const int pass_left = side_hint != 0 ? side_hint : (cross >= 0.0 ? 1 : -1);
    side_ = pass_left;
  }
  // Three adjacent cones at once: no post is that wide (a wall's corner was taken for one); give it up.
  if (sense.run_length >= 3) {
    active_ = false;
    return false;
  }
  const Vec2 rel = vsub(position, centre_);
  if (vdot(rel, t_hat) > 0.0) {  // past the obstacle along the direction of travel
    active_ = false;
    return false;
  }
  const double dist = std::max(vnorm(rel), 1e-6);
  const Vec2 u = vscale(rel, 1.0 / dist);
  const double radius = params.obstacle_radius + kRobotRadius + params.wall_distance;
  // Passing on the left of the obstacle (seen from the robot, side +1) is going round it clockwise: the
  // tangent is u turned by -pi/2.
  const Vec2 tangent = vrotate(u, -side_ * std::numbers::pi / 2.0);
  const double speed = std::max(d_norm, params.speed);
  velocity = vsub(vscale(tangent, speed), vscale(u, params.radial_gain * (dist - radius)));
  return true;
}

}  // namespace swarmform::controller::motion

namespace swarmform::controller::motion {

int BoundaryFollower::choose_side(Vec2 position, Vec2 echo, Vec2 desired, int tie_break) {
  const Vec2 rel = vsub(position, echo);
  const double dist = vnorm(rel);
  if (dist < 1e-9) return tie_break >= 0 ? 1 : -1;
  const Vec2 u = vscale(rel, 1.0 / dist);
  const double ccw = vdot(vrotate(u, std::numbers::pi / 2), desired);
  constexpr double kTie = 0.1;  // of |desired|
  if (std::abs(ccw) <= kTie * vnorm(desired)) return tie_break >= 0 ? 1 : -1;
  return ccw > 0 ? 1 : -1;
}

bool BoundaryFollower::update(const std::optional<Vec2>& echo, Vec2 position, Vec2 desired, Tick tick,
                              const BoundaryFollowParams& params, Vec2& velocity, bool may_leave,
                              std::optional<double> across) {
  if (!active_) return false;
  if (!echo) {
    active_ = false;
    return false;
  }
  const Vec2 rel = vsub(position, *echo);
  const double dist = std::max(vnorm(rel), 1e-6);
  const Vec2 u = vscale(rel, 1.0 / dist);
  if (!hit_) hit_ = position;
  const double from_hit = vnorm(vsub(position, *hit_));
  if (from_hit > 2.0 * params.keep) {
    away_ = true;
  } else if (away_ && from_hit < params.keep) {
    looped_ = true;
  }
  if ((may_leave || looped_) && tick >= started_ + params.min_ticks && vdot(desired, u) >= 0.0) {
    active_ = false;  // the desired motion leads away from the obstacle: the way is clear
    return false;
  }
  constexpr int kMaxDoublings = 6;  // 64 x max_ticks: longer than any run's budget
  if (tick >= since_ + (params.max_ticks << std::min(turns_, kMaxDoublings))) {
    side_ = -side_;  // a dead end that way: back the other way, searching twice as far
    since_ = tick;
    ++turns_;
    hit_ = position;  // a loop is judged from here: going back passes the old start
    away_ = false;
  }
  // A passage narrower than two keeps: its middle (the robot fits where the follower's keep does not). In
  // the middle the nearest surface changes sides; the way along the passage must not: the other side is
  // followed with the other hand (without it the tangent reversed with each change and the robot stood in
  // the passage).
  const bool passage = !passages_closed_ && across && dist + *across < 2.0 * params.keep;
  // Going round on the spot after taking a passage: among posts and bodies the middles of the gaps round one
  // cell made a loop smaller than a keep, and the robot circled there for good (posts.yaml --seed 70 --kill
  // 0@1956 --kill 8@2362). Less than a keep of way made in kStallTicks (a metre at the speed limit): the
  // passages are closed for the rest of this episode (the cell's sides are one obstacle again); the next
  // time, it has gone all the way round what it can go round (looped: it leaves as soon as the way is
  // clear). An episode that never took a passage is left as it was (a follower held by its neighbours).
  constexpr Tick kStallTicks = 100;
  took_passage_ = took_passage_ || passage;
  if (!stall_from_ || tick < stall_tick_) {
    stall_from_ = position;
    stall_tick_ = tick;
  } else if (tick >= stall_tick_ + kStallTicks) {
    if (took_passage_ && vnorm(vsub(position, *stall_from_)) < params.keep) {
      if (passages_closed_) looped_ = true;
      passages_closed_ = true;
    }
    stall_from_ = position;
    stall_tick_ = tick;
  }
  const double keep = passage ? (dist + *across) / 2.0 : params.keep;
  if (passage && last_u_ && vdot(u, *last_u_) < 0.0) side_ = -side_;
  last_u_ = u;
  const Vec2 tangent = vrotate(u, side_ * std::numbers::pi / 2.0);
  velocity = vclamp(vsub(vscale(tangent, params.speed), vscale(u, params.radial_gain * (dist - keep))),
                    params.speed);
  return true;
}

}  // namespace swarmform::controller::motion
