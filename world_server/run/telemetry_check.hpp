// Telemetry is what an agent says about itself: untrusted input. Before a command's telemetry reaches the
// world (and so robots.csv, events.jsonl and the metrics' first guesses), every field is range-checked and
// every event string size-capped; a field out of range is dropped (the robot keeps the value the world last
// accepted from it) and counted, so a lying or broken agent can never put a label of 2e9, a NaN force or a
// 20 KB string into the recording as a fact. In-range values are recorded as what the robot reported; the
// run's metrics and its end come from the world's own poses (metrics_tracker.hpp).
#pragma once

#include <cstdint>
#include <string>

#include "behaviour/known_columns.hpp"
#include "common/types.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

// The bounds of one run's telemetry (from the scenario).
struct TelemetryLimits {
  // The known columns (behaviour/known_columns.hpp) of the behaviour, where it declares them: a label is
  // -1 (none) or 0..labels-1, a parent -1 (none) or 0..robots-1, a leader 0 or 1, a net force in
  // 0..max_net_force.
  behaviour::KnownColumns known;
  std::int32_t labels = 0;
  std::uint32_t robots = 0;
  double max_net_force = 1e6;
  std::size_t max_events = 16;        // event strings in one command; more are dropped
  std::size_t max_event_bytes = 256;  // a longer event string is dropped
  std::int32_t min_state = 0;         // a state is one of the behaviour's (its descriptor's `states`)
  std::int32_t max_state = 6;
  std::size_t extra = 0;  // telemetry columns of the behaviour: `extra` holds 0 or exactly this many
};

// The limits of a run of `scenario`: its shape's labels, its robots, its behaviour's states and columns (with
// robot groups, group `group`'s behaviour's: a robot is held to its own group's).
TelemetryLimits telemetry_limits(const Scenario& scenario, std::size_t group = 0);

// What one check dropped (0 everywhere for an honest controller).
struct TelemetryDrops {
  std::uint32_t fields =
      0;  // the state, the columns (as a whole), a known column's value: each one out of range
  std::uint32_t events = 0;  // event strings dropped (too many, too long, or not printable ASCII)
  std::string first;         // the first problem, e.g. "label 2000000000 outside -1..2" (for the log)
  bool any() const { return fields > 0 || events > 0; }
};

// Checks `incoming` in place: a field out of range takes the value of `accepted` (what the world holds for
// the robot now); bad event strings are removed.
TelemetryDrops check_telemetry(Telemetry& incoming, const Telemetry& accepted, const TelemetryLimits& limits);

}  // namespace swarmform::world
