#include "world_server/run/fault_schedule.hpp"

#include "world_server/run/fault_events.hpp"

namespace swarmform::world {

FaultSchedule::FaultSchedule(const Scenario& scenario)
    : scenario_(scenario), held_(scenario.robots.size(), 0), stopped_(scenario.faults.size(), 0) {
  for (const Kill& k : scenario.kills) kills_.emplace(k.tick, k.id);
}

void FaultSchedule::add_kill(Tick t, RobotId id) {
  kills_.emplace(t, id);
}

void FaultSchedule::at_round(Tick t, RunSession& session, FaultActions& actions) {
  while (!kills_.empty() && kills_.begin()->first <= t) {
    const RobotId id = kills_.begin()->second;
    kills_.erase(kills_.begin());
    actions.kill(id);
  }
  for (std::size_t i = 0; i < scenario_.faults.size(); ++i) {
    const Fault& f = scenario_.faults[i];
    if (f.kind == FaultKind::Stall) {
      // The scenario allows one stall of a robot at a time (faults.cpp), so a robot's flag is one stall's.
      const RobotId id = *f.robot;
      if (f.tick == t) {
        FaultActions::Stall s = actions.start_stall(f);
        stopped_[i] = s.stopped ? 1 : 0;
        if (!s.stopped) held_[id] = 1;
        record_process_fault_event(session, f, true, s.what);
      } else if (f.end_tick() == t) {
        const bool stopped = stopped_[i] != 0;
        stopped_[i] = 0;
        if (!stopped) held_[id] = 0;
        record_process_fault_event(session, f, false, actions.end_stall(f, stopped));
      }
    } else if (f.kind == FaultKind::Restart && f.tick == t) {
      pending_restarts_.push_back(&f);
    }
  }
  for (auto it = pending_restarts_.begin(); it != pending_restarts_.end();) {
    const std::optional<std::string> what = actions.restart(**it, t);
    if (!what) {
      ++it;
      continue;
    }
    record_process_fault_event(session, **it, true, *what);
    it = pending_restarts_.erase(it);
  }
  record_world_fault_events(session, scenario_.faults, t);
  record_world_events(session, scenario_, t);
}

bool FaultSchedule::quiet_at(Tick t) const {
  if (!pending_restarts_.empty()) return false;
  if (!kills_.empty() && kills_.begin()->first <= t) return false;
  for (const Fault& f : scenario_.faults) {
    if (f.tick == t || f.end_tick() == t) return false;
  }
  for (const WorldEvent& e : scenario_.world_events) {
    if (e.tick == t) return false;
  }
  for (const GoalEvent& e : scenario_.goal_events) {
    if (e.tick == t) return false;
  }
  return true;
}

void FaultSchedule::finish(RunSession& session) {
  for (const Fault* f : pending_restarts_) {
    record_process_fault_event(
        session, *f, true,
        "not done: robot " + std::to_string(*f->robot) + "'s death was not seen before the end of the run");
  }
  pending_restarts_.clear();
}

}  // namespace swarmform::world
