#include "world_server/process_faults.hpp"

#include <csignal>
#include <iostream>

#include "world_server/run/fault_events.hpp"

namespace swarmform::server {

ProcessFaults::ProcessFaults(const world::Scenario& scenario, world::World& world, world::RunSession& session,
                             PidLookup agent_pid, StatusChannel* status)
    : scenario_(scenario),
      world_(world),
      session_(session),
      agent_pid_(std::move(agent_pid)),
      status_(status) {}

ProcessFaults::~ProcessFaults() {
  resume_all(nullptr);
}

pid_t ProcessFaults::signalable(RobotId id, Tick t) const {
  for (const world::Kill& k : scenario_.kills) {
    if (k.id == id && k.tick <= t) return 0;
  }
  return agent_pid_ ? agent_pid_(id).value_or(0) : 0;
}

void ProcessFaults::kill(RobotId id) {
  if (const auto pid = agent_pid_ ? agent_pid_(id) : std::nullopt) {
    // The agent dies as any crash would; DDS liveliness tells the world (Server::on_lost), nothing else.
    if (::kill(*pid, SIGKILL) == 0) {
      kill_sent_[id] = std::chrono::steady_clock::now();
      session_.record_event(id, "kill_sent", "SIGKILL pid " + std::to_string(*pid));
    } else {
      session_.record_event(id, "kill_failed", "SIGKILL pid " + std::to_string(*pid) + " failed");
    }
  } else if (world_.alive(id)) {
    // No process to kill: the robot dies in the world; its agent gets no more packets.
    world_.kill(id);
    session_.record_death(id);
    session_.record_event(id, "killed", "no --agent-pid for it: the robot was killed in the world");
  }
}

std::optional<long long> ProcessFaults::take_kill_delay_ms(RobotId id) {
  const auto k = kill_sent_.find(id);
  if (k == kill_sent_.end()) return std::nullopt;
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - k->second);
  kill_sent_.erase(k);
  return static_cast<long long>(ms.count());
}

world::FaultActions::Stall ProcessFaults::start_stall(const world::Fault& f) {
  const RobotId id = *f.robot;
  const pid_t pid = signalable(id, f.tick);
  if (pid != 0 && ::kill(pid, SIGSTOP) == 0) {
    stopped_[&f] = pid;
    return {true, "SIGSTOP pid " + std::to_string(pid)};
  }
  const std::string why =
      pid != 0 ? "SIGSTOP pid " + std::to_string(pid) + " failed" : "no process of its own to stop";
  return {false,
          why + (world_.alive(id) ? "; its packets are withheld for " + std::to_string(*f.duration) + " ticks"
                                  : "; the robot is dead")};
}

std::string ProcessFaults::end_stall(const world::Fault& f, bool stopped) {
  const auto it = stopped_.find(&f);
  if (!stopped || it == stopped_.end()) return "its packets are sent again";
  const bool ok = ::kill(it->second, SIGCONT) == 0;
  std::string what =
      "SIGCONT pid " + std::to_string(it->second) + (ok ? "" : " failed (the process is gone)");
  stopped_.erase(it);
  return what;
}

std::optional<std::string> ProcessFaults::restart(const world::Fault& f, Tick t) {
  // A restart waits for the death of the killed agent to be seen (its lease, ~0.5 s after the SIGKILL):
  // until then the old owner holds the id and would refuse the new agent's claim.
  if (world_.alive(*f.robot)) return std::nullopt;
  // The launcher owns the agent processes: it starts the new one on this line.
  const std::string line = "restart id=" + std::to_string(*f.robot) + " tick=" + std::to_string(t);
  if (status_ != nullptr) {
    status_->emit_and_print("restart", {{"id", *f.robot}, {"tick", t}}, line);
  } else {
    std::cout << line << std::endl;
  }
  return "asked for a new agent process (stdout: restart id=" + std::to_string(*f.robot) +
         "; scripts/swarm run starts it)" +
         (t == f.tick ? std::string() : "; after its death was seen at tick " + std::to_string(t));
}

bool ProcessFaults::stopped(pid_t pid) const {
  for (const auto& [fault, p] : stopped_) {
    if (p == pid) return true;
  }
  return false;
}

void ProcessFaults::resume_all(world::RunSession* session) {
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
