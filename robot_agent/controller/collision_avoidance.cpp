#include "robot_agent/controller/collision_avoidance.hpp"

#include <algorithm>
#include <cmath>

#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/paper_params.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller {

Vec2 collision_force(const std::vector<NeighbourPosition>& neighbours, double k_collision, double r_o) {
  Vec2 f;
  for (const auto& n : neighbours) {
    if (!(n.range < r_o)) continue;
    const double gap = std::max(std::abs(n.range - r_o), kSingularityFloor);
    f = vadd(f, vpolar(-k_collision / (gap * gap), n.azimuth));  // eq. (1)
  }
  return f;
}

Vec2 avoid_collisions(Vec2 desired, const std::vector<NeighbourPosition>& neighbours, double k_collision,
                      double r_o, double max_speed, int side_choice) {
  const double inner = r_o + kAwarenessMargin;
  const double outer = inner + kBlendWidth;
  // Full go-round inside `inner`, none beyond `outer`, a linear blend between: the velocity is continuous
  // across the band, so a differential-drive robot does not flip 90 degrees each tick at its edge.
  auto weight = [&](double range) { return std::clamp((outer - range) / kBlendWidth, 0.0, 1.0); };
  bool near = false;
  // Giving way first: no more progress towards a robot with the right of way, and back away from it, as much
  // as it is near (the full speed limit inside `inner`); the go-round below keeps that retreat off the rest.
  Vec2 v = desired;
  Vec2 retreat;
  for (const auto& n : neighbours) {
    if (!(n.range < outer)) continue;
    near = true;
    if (n.way != RightOfWay::Theirs) continue;
    const double w = weight(n.range);
    const Vec2 towards = vpolar(1.0, n.azimuth);
    v = vsub(v, vscale(towards, w * std::max(0.0, vdot(v, towards))));
    retreat = vadd(retreat, vscale(towards, -w * max_speed));
  }
  if (!near) return desired;
  if (retreat.x != 0.0 || retreat.y != 0.0)
    v = vclamp(vadd(v, retreat), max_speed);  // else as before (motion)
  const double speed = vnorm(v);
  for (const auto& n : neighbours) {
    if (!(n.range < outer)) continue;
    if (n.way == RightOfWay::Ours) continue;  // it gives way; eq. (1) below keeps us apart
    const double w = weight(n.range);
    const Vec2 towards = vpolar(1.0, n.azimuth);
    const double closing = vdot(v, towards);
    if (closing <= 0.0) continue;
    // No more progress into the neighbour: go round it, at the desired speed, on the side the goal is on
    // (on the right when the goal is straight behind it, so two robots meeting head-on do not mirror each
    // other).
    const Vec2 right{towards.y, -towards.x};
    const double side = vdot(v, right);
    // A committed side: always that side of an echo; for a robot heard, that side when the goal is (nearly)
    // straight behind it, instead of the right.
    bool go_right = side >= -0.2 * closing;
    if (side_choice != 0 && n.echo) go_right = side_choice > 0;
    if (side_choice < 0 && !n.echo) go_right = side > 0.2 * closing;
    const Vec2 tangent = go_right ? right : Vec2{-right.x, -right.y};
    Vec2 g = vsub(v, vscale(towards, closing));
    g = vadd(vsub(g, vscale(tangent, vdot(g, tangent))), vscale(tangent, speed));
    v = vadd(vscale(v, 1.0 - w), vscale(g, w));
  }
  // eq. (1), capped at the speed limit so that going round still has a say (the sum is limited below).
  const Vec2 repulsion = vclamp(collision_force(neighbours, k_collision, r_o), max_speed);
  return vclamp(vadd(v, repulsion), max_speed);
}

std::vector<NeighbourPosition> unexplained_echoes(const std::array<double, kUltrasonicCount>& readings,
                                                  double theta, const std::vector<NeighbourPosition>& heard,
                                                  double max_echo) {
  // Algorithm 2's test (obstacle_forces.hpp), with the defaults of its parameters: the formation phases
  // have no parameters of their own for it.
  static const double kMaskAngle = param_value({}, "neighbour_mask_angle");
  static const double kSlack = param_value({}, "mask_slack");
  std::vector<NeighbourPosition> out;
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    const double r = readings[s];
    if (!(r < max_echo)) continue;
    const double azimuth = wrap_angle(theta + kUltrasonicAngles[s]);
    bool explained = false;
    for (const auto& n : heard) {
      if (motion::neighbour_explains_echo(n.azimuth, azimuth, r, n.range, kMaskAngle, kSlack)) {
        explained = true;
        break;
      }
    }
    if (!explained) out.push_back({r + 2.0 * kRobotRadius, azimuth, RightOfWay::Mutual, true});
  }
  return out;
}

}  // namespace swarmform::controller
