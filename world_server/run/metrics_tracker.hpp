// Keeps the run's generic Metrics (metrics.hpp) up to date, one recorded tick at a time, from the truth: the
// world's contact onsets and the robots' silence. Events that count into the metrics (deaths, rejoins,
// leader changes, graph splits) come in through count_event, so the events file and the summary can never
// disagree. It knows no behaviour: what a behaviour measures of its own is its experiment's
// (experiment_runner.hpp).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "world_server/run/metrics.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

class MetricsTracker {
 public:
  void observe(Tick tick, const std::vector<RobotTruth>& robots, ContactCounts contacts);
  // An event as written to events.jsonl ({"tick","kind","id",...}); deaths, rejoins, leader, fragment and
  // rejoin_graph are counted, anything else is ignored.
  void count_event(const nlohmann::ordered_json& event);
  // Components of the robots' communication graph this tick (tracked from formation on).
  void note_components(std::size_t components);
  // At the end of the run: silent_robots (from the last observed tick).
  void conclude();

  const Metrics& metrics() const { return metrics_; }

 private:
  Metrics metrics_;
  std::vector<RobotId> silent_ids_;  // this tick's live but silent robots, id order
  bool leader_seen_ = false;
};

}  // namespace swarmform::world
