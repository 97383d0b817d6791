// The events of scheduled world faults (world/faults.hpp), written the same way by both front ends (the
// in-process harness and the DDS world_server) at the start of each round, before the robots see tick t:
// kind `fault` when one starts acting, `fault_end` when it stops; `id` the robot, or -1 for `all`; `detail`
// the fault's text and what it does (docs/recording-format.md). The scenario's world events likewise.
#pragma once

#include <vector>

#include "world_server/run/run_session.hpp"
#include "world_server/world/faults.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

void record_world_fault_events(RunSession& session, const std::vector<Fault>& faults, Tick t);

// The scenario's world events of tick t (world/world_events.hpp), which World::step executed in producing
// tick t: kind `obstacle_appear`, `obstacle_disappear` or `obstacle_move`, id -1, detail the obstacle's name
// (and where it moved).
void record_world_events(RunSession& session, const Scenario& scenario, Tick t);

// A process fault's event (stall, restart), with what the front end did, e.g. "SIGSTOP pid 123".
void record_process_fault_event(RunSession& session, const Fault& fault, bool start, const std::string& what);

}  // namespace swarmform::world
