// When a run ends: at the scenario's max_ticks, kTicksAfterGoal ticks after goal_tick (so the recording
// shows the formation settle at the goal), or kTicksAfterDone ticks after the behaviour's experiment said it
// was done. One rule for both front ends: the DDS world_server and the in-process harness call run_complete
// after every recorded tick. Both delays are > 0: world_server decides before it records the tick it stepped,
// the harness after, and either way the run ends at the same tick.
#pragma once

#include <string>

#include "common/types.hpp"
#include "world_server/run/metrics.hpp"
#include "world_server/run/run_session.hpp"

namespace swarmform::world {

inline constexpr Tick kTicksAfterGoal = 20;
inline constexpr Tick kTicksAfterDone = 1;

// `tick` is the tick just recorded (World::tick() after the step). Only an arrival at or after the goal's
// last move (`last_goal_move`, 0 when it never moves) ends the run: one before it was at a goal that then
// moved (world_server asks before it records the move's tick, when goal_tick still holds that arrival).
inline bool run_complete(const Metrics& metrics, Tick tick, Tick max_ticks, Tick last_goal_move = 0) {
  return tick >= max_ticks || (metrics.goal_tick && *metrics.goal_tick >= last_goal_move &&
                               tick >= *metrics.goal_tick + kTicksAfterGoal);
}
inline bool run_complete(const RunSession& session, Tick tick, Tick max_ticks) {
  const std::optional<Tick> done = session.experiment_done_at();
  return run_complete(session.metrics(), tick, max_ticks, session.last_goal_move()) ||
         (done && tick >= *done + kTicksAfterDone);
}

// The last line a front end prints when the run used up max_ticks without arriving (outcome and stuck
// robots from the summary, so a user need not open it); empty when the run arrived or stopped earlier, or
// has no goal (outcome none).
// E.g. "max_ticks 5000 reached without arriving: outcome formed_not_arrived, stuck robots 1 4".
inline std::string max_ticks_line(const Metrics& metrics, Tick tick, Tick max_ticks) {
  if (tick < max_ticks || metrics.goal_tick || metrics.outcome == "none") return {};
  // Appends, not operator+ chains: GCC 12 gives a false -Wrestrict on those at -O2.
  std::string line = "max_ticks ";
  line.append(std::to_string(max_ticks));
  line.append(" reached without arriving: outcome ");
  line.append(metrics.outcome);
  line.append(", stuck robots");
  if (metrics.stuck_robots.empty()) line.append(" none");
  for (const RobotId id : metrics.stuck_robots) {
    line.push_back(' ');
    line.append(std::to_string(id));
  }
  return line;
}

}  // namespace swarmform::world
