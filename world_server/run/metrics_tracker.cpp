// The generic metrics (metrics_tracker.hpp).
#include "world_server/run/metrics_tracker.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

namespace swarmform::world {

void MetricsTracker::observe(Tick tick, const std::vector<RobotTruth>& robots, ContactCounts contacts) {
  metrics_.collisions_robot_robot += contacts.robot_robot;
  metrics_.collisions_robot_obstacle += contacts.robot_obstacle;
  silent_ids_.clear();
  for (const auto& r : robots) {
    if (is_silent(r, tick)) silent_ids_.push_back(r.id);
  }
}

void MetricsTracker::conclude() {
  metrics_.silent_robots = silent_ids_;
}

void MetricsTracker::count_event(const nlohmann::ordered_json& event) {
  const std::string kind = event.value("kind", "");
  const Tick tick = event.value("tick", Tick{0});
  const auto id = event.value("id", std::int64_t{-1});
  if (kind == "death") {
    metrics_.deaths.push_back({static_cast<RobotId>(id), tick});
  } else if (kind == "rejoin") {
    metrics_.rejoins.push_back({static_cast<RobotId>(id), tick});
  } else if (kind == "leader") {
    if (leader_seen_) ++metrics_.leader_changes;
    leader_seen_ = true;
  } else if (kind == "fragment") {
    ++metrics_.fragmentations;
  } else if (kind == "rejoin_graph") {
    ++metrics_.graph_rejoins;
  }
}

void MetricsTracker::note_components(std::size_t components) {
  metrics_.max_components = std::max(metrics_.max_components, static_cast<std::uint32_t>(components));
}

}  // namespace swarmform::world
