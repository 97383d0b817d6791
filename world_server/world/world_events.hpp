// Scheduled world events (the scenario's `events:`, docs/scenario-format.md "World events"): at a tick, an
// obstacle appears, disappears or moves. An obstacle listed with `present: false` starts absent.
//
// World::step executes the events of tick t in the step that produces tick t, after the physics and before
// the sensors: tick t's poses were integrated with the obstacles as they stood, and tick t's perceptions,
// recording and judging see them as they stand after the events. The physics keeps every obstacle's body (in
// the scenario's order, whatever is present: Bullet is reproducible only for the same bodies in the same
// order) and takes an absent one out of its dynamics world; the sensors and the medium see the present ones.
// One World runs both front ends, so an in-process and a multi-process run stay bit-identical. An obstacle
// that appears on a robot pushes it aside, as a real one dropped there would.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/yaml_fields.hpp"

namespace swarmform::world {

struct Obstacle;
struct Scenario;

struct WorldEvent {
  enum class Action { Appear, Disappear, Move };
  Tick tick = 0;             // >= 1 (tick 0 is the scenario's own `present`)
  std::size_t obstacle = 0;  // index into Scenario::obstacles
  Action action = Action::Move;
  Vec2 centre;                // Move: where the obstacle's centre goes (m)
  std::optional<double> yaw;  // Move: a box's new yaw (rad); none keeps it
};

// "appear", "disappear", "move": the scenario's words, and the events.jsonl kinds' endings
// (obstacle_appear, obstacle_disappear, obstacle_move).
std::string_view action_word(WorldEvent::Action action);

// `events:` of the scenario's top map, after its obstacles and max_ticks: each checked at file:line (a known
// obstacle by name, one event per obstacle and tick, appear only what is absent, disappear only what is
// present, a tick within 1..max_ticks), then sorted by tick (stable: the file's order within a tick).
void parse_world_events(const yaml::Source& src, yaml::MapReader& top, Scenario& s);

// Applies to `obstacles` (the scenario's, as they stand) every event of exactly tick t, in order; returns how
// many there were.
std::size_t apply_world_events(std::vector<Obstacle>& obstacles, const std::vector<WorldEvent>& events,
                               Tick t);

// What the event did, for events.jsonl's detail: "gate" / "crate to (3, -2) yaw 0.3".
std::string describe_world_event(const WorldEvent& e, const std::vector<Obstacle>& obstacles);

}  // namespace swarmform::world
