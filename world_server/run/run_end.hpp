// When a run ends: at the scenario's max_ticks, or kTicksAfterDone ticks after the behaviour's experiment
// said it was done (the paper's says so 19 ticks after its goal_tick, so the recording shows the formation
// settle at the goal). One rule for both front ends: the DDS world_server and the in-process harness call
// run_complete after every recorded tick. The delay is > 0: world_server decides before it records the tick
// it stepped, the harness after, and either way the run ends at the same tick.
#pragma once

#include <string>

#include "common/types.hpp"
#include "world_server/run/experiment_runner.hpp"
#include "world_server/run/run_session.hpp"

namespace swarmform::world {

inline constexpr Tick kTicksAfterDone = 1;

// `tick` is the tick just recorded (World::tick() after the step).
inline bool run_complete(const RunSession& session, Tick tick, Tick max_ticks) {
  const std::optional<Tick> done = session.experiment_done_at();
  return tick >= max_ticks || (done && tick >= *done + kTicksAfterDone);
}

// The last line a front end prints (after finish) when the run used up max_ticks without its experiment's
// success (its outcome, and its stuck_robots when it gives that key, so a user need not open the summary);
// empty when it succeeded, stopped earlier, or has no experiment (outcome none).
// E.g. "max_ticks 5000 reached without success: outcome formed_not_arrived, stuck robots 1 4".
inline std::string max_ticks_line(const ExperimentVerdict& verdict, Tick tick, Tick max_ticks) {
  if (tick < max_ticks || !verdict.success || *verdict.success) return {};
  // Appends, not operator+ chains: GCC 12 gives a false -Wrestrict on those at -O2.
  std::string line = "max_ticks ";
  line.append(std::to_string(max_ticks));
  line.append(" reached without success: outcome ");
  line.append(verdict.outcome);
  const auto stuck = verdict.fields.find("stuck_robots");
  if (stuck == verdict.fields.end() || !stuck->is_array()) return line;
  line.append(", stuck robots");
  if (stuck->empty()) line.append(" none");
  for (const auto& id : *stuck) {
    line.push_back(' ');
    line.append(id.dump());
  }
  return line;
}

}  // namespace swarmform::world
