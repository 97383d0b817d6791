#include "robot_agent/controller/place_watch.hpp"

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

void PlaceWatch::add(Tick tick, Vec2 parent_position, Tick window) {
  heard_.emplace_back(tick, parent_position);
  while (!heard_.empty() && heard_.front().first + window <= tick) heard_.pop_front();
}

std::optional<Vec2> PlaceWatch::place(Vec2 reference, std::size_t min_readings) const {
  if (heard_.empty() || heard_.size() < min_readings) return std::nullopt;
  Vec2 sum;
  for (const auto& [tick, p] : heard_) sum = vadd(sum, p);
  return vsub(vscale(sum, 1.0 / static_cast<double>(heard_.size())), reference);
}

}  // namespace swarmform::controller::motion
