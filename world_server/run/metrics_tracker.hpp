// Keeps the run's Metrics (metrics.hpp) up to date, one recorded tick at a time, from the truth alone: the
// robots' true poses, their alive flags and what their controllers report (Telemetry), plus the world's
// contact onsets. Events that count into the metrics (deaths, rejoins, leader changes, graph splits) come in
// through count_event, so the events file and the summary can never disagree.
//
// Definitions (world_server/run/README.md has the reasons):
// - a "shape robot" is a live robot whose telemetry label is >= 0;
// - formation_tick: the first tick with at least one shape robot and every shape robot in state >= Ready;
// - motion ticks: from motion_start_tick (first tick any live robot is in Motion) to goal_tick inclusive;
// - the goal region: the disc around the goal of radius goal_radius + the shape's own radius (the largest
//   distance of a label's place from the label grid's centre). The leader is pulled to the goal, so the
//   formation can never fit in the goal radius alone; a formation whose centre is within goal_radius of the
//   goal has every robot in the region when it is in shape.
// - goal_tick: the first tick, at or after formation, with every shape robot in the goal region, or every
//   shape robot reporting Arrived (the controller's own judgement of arrival);
// - arrived: the live shape robots in the goal region (at the last tick);
// - path_length: the distance travelled by the shape robots' centroid over the motion ticks; a step in which
//   the set of shape robots changed (a death, a label lost) is not counted, so a death is not a jump.
#pragma once

#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/mission.hpp"
#include "world_server/run/metrics.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

class MetricsTracker {
 public:
  explicit MetricsTracker(const Mission& mission);

  void observe(Tick tick, const std::vector<RobotTruth>& robots, ContactCounts contacts);
  // An event as written to events.jsonl ({"tick","kind","id",...}); deaths, rejoins, leader, fragment and
  // rejoin_graph are counted, anything else is ignored.
  void count_event(const nlohmann::ordered_json& event);
  // Components of the shape robots' communication graph this tick (tracked from formation on).
  void note_components(std::size_t components);

  const Metrics& metrics() const { return metrics_; }
  double goal_region_radius() const { return goal_region_radius_; }

 private:
  bool in_motion_window(Tick tick) const;

  ShapeMatrix shape_;
  double grid_spacing_;
  Vec2 goal_;
  double goal_region_radius_;  // m: goal_radius + the shape's radius

  Metrics metrics_;
  double distortion_sum_ = 0.0;
  std::size_t distortion_count_ = 0;
  std::vector<RobotId> previous_shape_ids_;  // shape robots of the previous observed tick (for path_length)
  std::optional<Vec2> previous_centroid_;
  bool leader_seen_ = false;
};

}  // namespace swarmform::world
