#include "world_server/run/fault_events.hpp"

namespace swarmform::world {
namespace {

std::int64_t id_of(const Fault& f) {
  return f.robot ? static_cast<std::int64_t>(*f.robot) : -1;
}

}  // namespace

void record_world_fault_events(RunSession& session, const std::vector<Fault>& faults, Tick t) {
  for (const FaultEdge& e : world_fault_edges(faults, t)) {
    session.record_event(id_of(*e.fault), e.start ? "fault" : "fault_end",
                         describe_world_fault(*e.fault, e.start));
  }
}

void record_world_events(RunSession& session, const Scenario& scenario, Tick t) {
  for (const WorldEvent& e : scenario.world_events) {
    if (e.tick != t) continue;
    session.record_event(-1, "obstacle_" + std::string(action_word(e.action)),
                         describe_world_event(e, scenario.obstacles));
  }
  for (const GoalEvent& e : scenario.goal_events) {
    if (e.tick == t) session.record_event(-1, "goal_move", describe_goal_event(e));
  }
}

void record_process_fault_event(RunSession& session, const Fault& fault, bool start,
                                const std::string& what) {
  session.record_event(id_of(fault), start ? "fault" : "fault_end", fault.text + ": " + what);
}

}  // namespace swarmform::world
