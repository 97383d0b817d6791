#include "world_server/process_faults.hpp"

#include <csignal>
#include <iostream>

#include "world_server/run/fault_events.hpp"

namespace swarmform::server {

ProcessFaults::ProcessFaults(const world::Scenario& scenario, PidLookup agent_pid)
    : scenario_(scenario), agent_pid_(std::move(agent_pid)), withheld_(scenario.robots.size(), 0) {}

ProcessFaults::~ProcessFaults() {
  resume_all(nullptr);
}

pid_t ProcessFaults::signalable(RobotId id, Tick t) const {
  for (const world::Kill& k : scenario_.kills) {
    if (k.id == id && k.tick <= t) return 0;
  }
  return agent_pid_ ? agent_pid_(id).value_or(0) : 0;
}

void ProcessFaults::at_round(Tick t, world::RunSession& session, const world::World& world) {
  for (const world::Fault& f : scenario_.faults) {
    if (f.kind == world::FaultKind::Stall) {
      const RobotId id = *f.robot;
      if (f.tick == t) {
        const pid_t pid = signalable(id, t);
        if (pid != 0 && ::kill(pid, SIGSTOP) == 0) {
          stopped_[&f] = pid;
          world::record_process_fault_event(session, f, true, "SIGSTOP pid " + std::to_string(pid));
        } else {
          withheld_[id] = 1;
          const std::string why =
              pid != 0 ? "SIGSTOP pid " + std::to_string(pid) + " failed" : "no process of its own to stop";
          world::record_process_fault_event(
              session, f, true,
              why + (world.alive(id)
                         ? "; its packets are withheld for " + std::to_string(*f.duration) + " ticks"
                         : "; the robot is dead"));
        }
      } else if (f.end_tick() == t) {
        if (const auto it = stopped_.find(&f); it != stopped_.end()) {
          const bool ok = ::kill(it->second, SIGCONT) == 0;
          world::record_process_fault_event(session, f, false,
                                            std::string("SIGCONT pid ") + std::to_string(it->second) +
                                                (ok ? "" : " failed (the process is gone)"));
          stopped_.erase(it);
        } else {
          withheld_[id] = 0;
          world::record_process_fault_event(session, f, false, "its packets are sent again");
        }
      }
    } else if (f.kind == world::FaultKind::Restart && f.tick == t) {
      pending_restarts_.push_back(&f);
    }
  }
  // A restart waits for the death of the killed agent to be seen (its lease, ~0.5 s after the SIGKILL): until
  // then the old owner holds the id and would refuse the new agent's claim.
  for (auto it = pending_restarts_.begin(); it != pending_restarts_.end();) {
    const world::Fault& f = **it;
    if (world.alive(*f.robot)) {
      ++it;
      continue;
    }
    // The launcher owns the agent processes: it starts the new one on this line.
    std::cout << "restart id=" << *f.robot << " tick=" << t << std::endl;
    world::record_process_fault_event(
        session, f, true,
        "asked for a new agent process (stdout: restart id=" + std::to_string(*f.robot) +
            "; scripts/swarm run starts it)" +
            (t == f.tick ? std::string() : "; after its death was seen at tick " + std::to_string(t)));
    it = pending_restarts_.erase(it);
  }
  world::record_world_fault_events(session, scenario_.faults, t);
}

bool ProcessFaults::quiet_at(Tick t) const {
  if (!pending_restarts_.empty()) return false;
  for (const world::Fault& f : scenario_.faults) {
    if (f.tick == t || f.end_tick() == t) return false;
  }
  return true;
}

void ProcessFaults::resume_all(world::RunSession* session) {
  if (session != nullptr) {
    for (const world::Fault* f : pending_restarts_) {
      world::record_process_fault_event(
          *session, *f, true,
          "not done: robot " + std::to_string(*f->robot) + "'s death was not seen before the end of the run");
    }
  }
  pending_restarts_.clear();
  for (const auto& [fault, pid] : stopped_) {
    const bool ok = ::kill(pid, SIGCONT) == 0;
    if (session != nullptr) {
      world::record_process_fault_event(*session, *fault, false,
                                        "SIGCONT pid " + std::to_string(pid) + " at the end of the run" +
                                            (ok ? "" : " failed (the process is gone)"));
    }
  }
  stopped_.clear();
}

}  // namespace swarmform::server
