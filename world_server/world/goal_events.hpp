// Goal moves, the world events that move the run's goal (the scenario's `events:` items with `goal:`,
// docs/scenario-format.md "World events"): from tick t on, the goal is another disc. Like the obstacles'
// events they act in the step that produces tick t, so tick t's perceptions (Perception::goal), recording
// and judging see the goal moved; every robot is told in its perception, in-process and over DDS alike.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/yaml_fields.hpp"

namespace swarmform::world {

struct Scenario;

struct GoalEvent {
  Tick tick = 0;              // >= 1
  Goal goal;                  // the goal from `tick` on
  bool radius_given = false;  // false: the radius it had (filled in by check_goal_events)
  int line = 0;               // the item's line, for the checks that need the whole scenario
};

// One `events:` item that has `goal:` ({tick, goal: [x, y], radius}), checked at file:line: tick in
// 1..max_ticks, coordinates as any of the scenario's, radius > 0 when given; no other key.
GoalEvent parse_goal_event(const yaml::Source& src, yaml::MapReader& item, Tick max_ticks);

// Once the run's goal and walls are known: a run without a goal has no goal to move, one move a tick, each
// inside the walls; the radius not given is the one the goal had. `origin`: the scenario file, for messages.
// Sorts the moves by tick (stable).
void check_goal_events(const std::string& origin, Scenario& s);

// The run's goal as it stands at tick t: the mission's, moved by every goal event at or before t (nullopt:
// the run has none).
std::optional<Goal> goal_at(const Scenario& s, Tick t);

// events.jsonl's detail of a `goal_move`: "to (4, 6) radius 0.5".
std::string describe_goal_event(const GoalEvent& e);

}  // namespace swarmform::world
