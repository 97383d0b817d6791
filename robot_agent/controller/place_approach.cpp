#include "robot_agent/controller/place_approach.hpp"

#include <cmath>
#include <numbers>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

namespace {
constexpr double kProgress = 0.05;  // m
constexpr Tick kStuckTicks = 50;
constexpr Tick kSideTicks = 200;
constexpr double kDetourDistance = 1.0;  // m
constexpr Tick kDetourTicks = 150;
constexpr double kDetourReached = 0.15;  // m
}  // namespace

void PlaceApproach::reset() {
  started_ = false;
  side_ = 0;
  detour_.reset();
  bug_.reset();
  bug_next_ = true;
}

Vec2 PlaceApproach::step(Vec2 position, Vec2 place, Vec2 desired, Tick tick,
                         const std::vector<NeighbourPosition>& echoes, const std::optional<Vec2>& wall,
                         const PlaceApproachParams& params, std::mt19937_64& rng,
                         std::vector<std::string>& events, std::optional<double> across) {
  const double distance = vnorm(vsub(place, position));
  if (!started_) {
    started_ = true;
    best_ = distance;
    progress_tick_ = tick;
  }
  if (bug_.active()) {
    Vec2 v;
    if (bug_.update(wall, position, desired, tick, params.bug, v, distance < bug_gap_ - params.there, across))
      return v;
    events.push_back("boundary_follow_end");
    bug_next_ = !bug_.looped();  // all the way round: the next time it is stuck, a random detour
    side_ = 0;
    best_ = distance;
    progress_tick_ = tick;
  }
  if (distance < best_ - kProgress) {
    best_ = distance;
    progress_tick_ = tick;
  } else if (distance < params.there) {
    progress_tick_ = tick;
  } else if (!detour_ && tick >= progress_tick_ + (side_ == 0 ? kStuckTicks : kSideTicks)) {
    if (side_ != 0 && wall && distance > params.bug_from && bug_next_) {
      bug_.start(BoundaryFollower::choose_side(position, *wall, desired, side_), tick);
      bug_gap_ = distance;
      events.push_back("boundary_follow_start " + std::to_string(bug_.side()));
      side_ = 0;
      Vec2 v;  // never leaves on its first tick (min_ticks), and `wall` is known: it follows
      bug_.update(wall, position, desired, tick, params.bug, v, false, across);
      return v;
    }
    if (side_ != 0) {
      bug_next_ = true;
      const double a = std::uniform_real_distribution<double>(-std::numbers::pi, std::numbers::pi)(rng);
      detour_ = vadd(position, vpolar(kDetourDistance, a));
      detour_until_ = tick + kDetourTicks;
      events.push_back("detour");
    }
    side_ = side_ < 0 ? 1 : -1;
    best_ = distance;
    progress_tick_ = tick;
  }
  Vec2 v = desired;
  if (detour_) {
    const Vec2 to_detour = vsub(*detour_, position);
    if (tick >= detour_until_ || vnorm(to_detour) < kDetourReached) {
      detour_.reset();
      best_ = distance;
      progress_tick_ = tick;
    } else {
      v = vscale(to_detour, params.max_speed / std::max(vnorm(to_detour), 1e-9));
    }
  }
  if (side_ == 0 || echoes.empty())
    return avoid_collisions(v, echoes, params.k_collision, params.r_o, params.max_speed);
  // The committed side holds for the nearest echo only, the obstacle it goes round (Bug); the others are
  // gone round on the place's side, so it still passes between two obstacles.
  std::size_t nearest = 0;
  for (std::size_t i = 1; i < echoes.size(); ++i) {
    if (echoes[i].range < echoes[nearest].range) nearest = i;
  }
  std::vector<NeighbourPosition> rest;
  for (std::size_t i = 0; i < echoes.size(); ++i) {
    if (i != nearest) rest.push_back(echoes[i]);
  }
  v = avoid_collisions(v, {echoes[nearest]}, params.k_collision, params.r_o, params.max_speed, side_);
  return avoid_collisions(v, rest, params.k_collision, params.r_o, params.max_speed);
}

}  // namespace swarmform::controller::motion
