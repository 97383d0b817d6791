// When a run ends: at the scenario's max_ticks, or kTicksAfterGoal ticks after goal_tick (so the recording
// shows the formation settle at the goal). One rule for both front ends: the DDS world_server and the
// in-process harness call run_complete after every recorded tick.
#pragma once

#include "common/types.hpp"
#include "world_server/run/metrics.hpp"

namespace swarmform::world {

inline constexpr Tick kTicksAfterGoal = 20;

// `tick` is the tick just recorded (World::tick() after the step).
inline bool run_complete(const Metrics& metrics, Tick tick, Tick max_ticks) {
  return tick >= max_ticks || (metrics.goal_tick && tick >= *metrics.goal_tick + kTicksAfterGoal);
}

}  // namespace swarmform::world
