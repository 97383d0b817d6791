#include "robot_agent/controller/shape_turn.hpp"

#include <cmath>

namespace swarmform::controller::motion {
namespace {

// The shape's turn since it formed, in microradians: every robot applies the one value the stigmergy agrees
// on, so the turned shape is the same shape on every robot.
std::uint32_t turn_key() {
  return stig::key(stig::Ns::Leader, 1);
}
constexpr double kTurnUnit = 1e-6;  // rad per unit of the turn entry
// Stigmergy namespace 6 (stigmergy.hpp: reserved for the motion phases): index = robot id, value = the torque
// (mm) with which the push off the surface its place lies beyond turns the shape (0 free). Written only once
// the goal has moved.
constexpr std::uint32_t kBlockedNs = 6;
std::uint32_t blocked_key(RobotId id) {
  return stig::key(kBlockedNs, id);
}

}  // namespace

void ShapeTurn::observe(Vec2 goal, const Stigmergy& st) {
  push_ = 0;
  if (goal.x != first_goal_.x || goal.y != first_goal_.y) goal_moved_ = true;
  if (const auto turn = st.get(turn_key())) {
    turn_ = static_cast<double>(*turn) * kTurnUnit;
    turned_ = true;
  }
}

// The leader sums the torques, not their signs, as a body pushed off-centre turns by the pushes' net torque:
// with signs, the V's arm end (a long lever) and the place next to it (a push nearly straight out, its normal
// taken from an echo up and aside) stood blocked with opposite signs, the sum 0, the shape never turned
// (goal_moves.yaml, the V, seed 4, a clean radio, once turns waited for the leader's arrival).
void ShapeTurn::lead(Stigmergy& st, const std::function<bool(RobotId)>& counts, bool standing,
                     double max_speed, double tick_rate, double shape_radius,
                     std::vector<std::string>& events) {
  if (!goal_moved_ || shape_radius <= 0.0) return;
  std::int64_t torque = 0;  // mm
  for (const auto& [key, e] : st.in_namespace(kBlockedNs)) {
    if (counts(static_cast<RobotId>(stig::index_of(key)))) torque += e.value;
  }
  if (torque == 0) {
    turning_ = 0;
    return;
  }
  // Only at the goal: a turn starts while the leader stands at its target (Arrived), as the shape stands at a
  // goal it does not fit; it goes on while places stay blocked, through the short walks by which the leader
  // follows its own turned place. On the way, a place beyond a surface is the boundary follower's: the goal
  // moved while the hexagon was still before the doorway's wall (the untuned doorway layout, clean, seed
  // 1102,
  // --kill 24@1666 --kill 2@2233), its front robots pinned at that wall turned it back and forth for
  // thousands of ticks, robots touching at the wall.
  if (turning_ == 0 && !standing) return;
  constexpr double kRimShare = 0.5;  // x the speed limit: the outermost place's speed while the shape turns
  const double rate = kRimShare * max_speed / tick_rate / shape_radius;  // rad a tick
  const double turn = wrap_angle((turned_ ? turn_ : 0.0) + (torque > 0 ? rate : -rate));
  const auto entry = static_cast<std::int64_t>(std::llround(turn / kTurnUnit));
  st.put(turn_key(), entry);
  turn_ = static_cast<double>(entry) * kTurnUnit;
  turned_ = true;
  const int side = torque > 0 ? 1 : -1;
  if (turning_ != side) events.push_back("shape_turning " + std::to_string(side));
  turning_ = side;
}

// The surface is kept: the sonars see only ahead, and a robot at rest beside a wall, turned away from it, no
// longer sees it; the wall is still there. Kept as a plane (the surface point, the normal towards it from the
// robot); the place is reachable again once it lies a body radius on this side of the plane, or the robot
// stands at it. The torque is the one found then, kept while the surface is (as boundary following commits a
// side): a push nearly straight out from the centroid has a torque near zero whose sign flips from tick to
// tick as the shape turns, and the leader turned back and forth (goal_moves_twice.yaml, the V, seed 4, kills
// 0@592 7@1307). Either way brings such a place in.
void ShapeTurn::push(const PushView& view) {
  if (!goal_moved_) {
    no_push();
    return;
  }
  const Vec2 to_place = vsub(view.place, view.position);
  const double distance = vnorm(to_place);
  if (distance <= view.arrival_tolerance) blocking_.reset();
  // Only a large obstacle (seen by three sensors or more, or latched: obstacle_view.hpp) blocks: a robot's
  // body is small and is gone round by the approach (goal_moves.yaml, the square, 20 % loss + noise, seed 1,
  // --kill 11@2010 --kill 4@2537: members beside the two dead robots' bodies inside the square took them for
  // walls and turned the shape over and over; it never stood formed).
  const Vec2 offset = turned(view.offset);
  if (!blocking_ && view.large && view.place_still && distance > view.arrival_tolerance) {
    if (const auto surface = view.surface()) {
      const Vec2 to_surface = vsub(*surface, view.position);
      const double near = vnorm(to_surface);
      if (near > 1e-6 && vdot(to_surface, to_place) > 0.0 && near < distance) {
        const Vec2 normal = vscale(to_surface, 1.0 / near);
        const double torque = -(offset.x * normal.y - offset.y * normal.x);  // offset x push, push = -normal
        blocking_ = Blocking{*surface, normal, static_cast<std::int64_t>(std::llround(torque * 1000.0))};
      }
    }
  }
  if (blocking_ && vdot(vsub(view.place, blocking_->at), blocking_->normal) <= -kRobotRadius)
    blocking_.reset();
  // A turn about the live centroid moves the place on a circle of the place's offset about it: it can bring
  // the place a body radius to this side of the surface only if the centroid stands no further beyond the
  // surface than that. A place behind a wall that the shape's centroid stands beyond is to be gone round, not
  // turned in (the same doorway run: the leader at the moved goal past the wall, robots left before it).
  if (blocking_) {
    const Vec2 centroid = vsub(view.place, offset);
    const double centroid_this_side = -vdot(vsub(centroid, blocking_->at), blocking_->normal);
    if (centroid_this_side + vnorm(offset) < kRobotRadius) blocking_.reset();
  }
  push_ = blocking_ ? blocking_->torque_mm : 0;
}

void ShapeTurn::publish(RobotId self, Stigmergy& st, std::vector<std::string>& events) const {
  if (!goal_moved_ || st.get(blocked_key(self)).value_or(0) == push_) return;
  st.put(blocked_key(self), push_);
  events.push_back("place_blocked " + std::to_string(push_));
}

}  // namespace swarmform::controller::motion
