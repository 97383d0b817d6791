#include "robot_agent/controller/approach_stage.hpp"

#include <cmath>

#include "common/splitmix64.hpp"
#include "robot_agent/controller/boundary_episode.hpp"
#include "robot_agent/controller/obstacle_response.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

std::vector<NeighbourPosition> echoes_before_place(const std::vector<Vec2>& points, Vec2 position,
                                                   double to_place) {
  std::vector<NeighbourPosition> echoes;
  for (const Vec2 e : points) {
    const Vec2 rel = vsub(e, position);
    const double r = vnorm(rel);
    if (r < to_place)
      echoes.push_back({r + kRobotRadius, std::atan2(rel.y, rel.x), RightOfWay::Mutual, true});
  }
  return echoes;
}

void ApproachStage::reset(std::uint64_t seed, RobotId self) {
  approach_.reset();
  rng_.seed(splitmix64(splitmix64(seed) ^ static_cast<std::uint64_t>(self)));
}

Vec2 ApproachStage::step(Vec2 position, Vec2 place, Vec2 desired, Tick tick, EchoMemory& echoes,
                         EchoMemory& trace, double surface_within, const PlaceApproachParams& params,
                         std::vector<std::string>& events) {
  const double to_place = vnorm(vsub(place, position));
  // The echoes of the last kEchoMemoryTicks (Algorithm 2's mask applied when each was heard): this tick's
  // readings alone let a robot graze a post beside it.
  const auto before = echoes_before_place(echoes.points(tick, kEchoMemoryTicks), position, to_place);
  const auto wall = trace.surface(position, tick, surface_within, kTraceTicks);
  const auto across =
      wall ? trace.across(position, *wall, tick, 2.0 * params.bug.keep, kTraceTicks) : std::nullopt;
  return approach_.step(position, place, desired, tick, before, wall, params, rng_, events, across);
}

}  // namespace swarmform::controller::motion
