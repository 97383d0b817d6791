#include "robot_agent/controller/desired_motion.hpp"

#include <algorithm>
#include <cmath>

#include "robot_agent/controller/formation_forces.hpp"
#include "robot_agent/controller/goal_force.hpp"
#include "robot_agent/controller/motion_section.hpp"

namespace swarmform::controller::motion {

namespace {

constexpr double kKeepUpStrain = 1.5;  // x the speed limit: the lag of a follower that keeps up
constexpr double kRestingShare = 0.1;  // of the cruise: the smallest eq. (7) |F_goal|
constexpr double kSlowest = 0.3;  // x the cruise: the leader never stops, so the gaps a held robot needs open

// eq. (2)/(4): k_o r^2 (cos a, sin a) for the vector r (cos a, sin a).
Vec2 spring(double k_o, Vec2 to_parent) {
  return attractive_force(k_o, {vnorm(to_parent), std::atan2(to_parent.y, to_parent.x)});
}

}  // namespace

double obstacle_gain(double speed, const MotionParams& p) {
  return std::max(p.m_obstacle * speed, p.m_obstacle * kRestingShare * p.cruise_speed);
}

Desire leader_desire(Vec2 position, Vec2 target, double stop_distance, double children_strain,
                     const MotionParams& p) {
  Desire d;
  if (vnorm(vsub(target, position)) < stop_distance) {
    d.arrival = Arrival::WithShape;
    return d;
  }
  // Pace: cruise while every follower keeps up (a follower at full speed behind its parent has
  // |F_net| ~ the speed limit); slow down linearly as the largest lag towards the goal grows past 1.5x
  // the limit, and wait (stop) at 1.5x + strain_scale: the leader never leaves a follower behind.
  double cruise = p.cruise_speed;
  if (p.strain_scale > 0.0) {
    const double over = std::max(0.0, children_strain - kKeepUpStrain * p.max_speed);
    cruise *= std::clamp(1.0 - over / p.strain_scale, kSlowest, 1.0);
  }
  d.velocity = goal_force(position, target, p.k_goal, cruise, 0.0);  // eq. (3)
  d.place = target;
  d.place_still = true;
  d.m = obstacle_gain(vnorm(d.velocity), p);  // eq. (7)
  return d;
}

// No parent (the tree cannot reach this robot's label: deaths cut it off), or a parent alive (not marked
// dead) but unheard: this robot's piece of the swarm cannot hear the leader's. It takes its own place to
// where the goal puts it (eq. 3 on its own place, as the leader does): every piece goes to the goal and the
// shape is whole again there.
Desire cut_off_desire(Vec2 position, Vec2 target, const MotionParams& p) {
  Desire d;
  if (vnorm(vsub(target, position)) < p.arrival_tolerance) {
    d.arrival = Arrival::Alone;
    return d;
  }
  d.velocity = goal_force(position, target, p.k_goal, p.max_speed, 0.0);
  d.m = obstacle_gain(vnorm(d.velocity), p);
  d.to_parent = Vec2{};
  d.place = target;
  d.place_still = true;
  d.alone = true;
  return d;
}

Desire FollowerDesire::step(const NeighbourTable& neighbours, Vec2 position, Tick tick, double tick_rate,
                            const ParentView& parent, const MotionParams& p) {
  Desire d;
  const Neighbour* n = neighbours.find(parent.id);
  Vec2 to_parent;
  const auto section = n != nullptr ? decode_motion_section(n->message.motion) : std::nullopt;
  const bool parent_resting = section && section->arrived;
  if (!parent_resting || resting_parent_ != parent.id) {
    rest_ = {};
    resting_parent_ = parent_resting ? std::optional<RobotId>(parent.id) : std::nullopt;
  }
  if (n != nullptr && neighbours.fresh(parent.id)) {
    to_parent = vpolar(n->range, n->azimuth);
    if (parent_resting) {
      // A parent at rest stands in one place: the mean of where it was heard since it came to rest.
      rest_.add(vadd(position, to_parent));
      to_parent = vsub(rest_.mean(), position);
    }
  } else if (rest_.count > 0) {
    to_parent = vsub(rest_.mean(), position);
  } else if (parent.last_position) {
    // Not heard this tick (lost copies, or it drifted out of range behind an obstacle): where it was, moved
    // on at the velocity it last said it had.
    const auto heard = neighbours.last_heard(parent.id).value_or(tick);
    const double dt = static_cast<double>(tick - std::min(heard, tick)) / tick_rate;
    to_parent = vsub(vadd(*parent.last_position, vscale(parent.last_velocity, dt)), position);
  }
  d.to_parent = to_parent;
  const Vec2 f_net = net_force(spring(p.k_o, to_parent), spring(p.k_o, parent.reference));  // eq. (5)
  d.net_force = vnorm(f_net);
  // How far behind towards the goal (every robot holds it): what the leader waits for. Not along the
  // parent's velocity, which vanishes when the leader waits.
  if (const Vec2 to_goal = vsub(p.goal, position); vnorm(to_goal) > 1e-6) {
    d.lag = std::max(0.0, vdot(f_net, vscale(to_goal, 1.0 / vnorm(to_goal))));
  }
  // eq. (5) plus the parent's own velocity (it broadcasts it): F_net corrects the follower's place and the
  // feed-forward carries it along, so a follower keeps up with no standing lag, and one held off its place
  // by an obstacle still moves on with its parent while it slides (the paper's F_net alone needs a lag of
  // v / (2 k_o r0) to move at v; beside the paper's box, where the diagonal spring pulls the corner robot
  // backwards as it gives way, that lag was ~0.7 m and the leader waited for it).
  const Vec2 feed = parent.last_velocity;
  d.velocity = vclamp(vadd(f_net, feed), p.max_speed);
  d.m = obstacle_gain(vnorm(feed), p);
  d.place = vsub(vadd(position, to_parent), parent.reference);
  d.place_still = (section && section->arrived) || vnorm(feed) < kRestingShare * p.cruise_speed;
  if (section && section->arrived && d.net_force < p.arrival_net_force) d.arrival = Arrival::WithShape;
  return d;
}

}  // namespace swarmform::controller::motion
