// The DDS world_server's side of the scheduled process faults (world/faults.hpp: stall, restart; kills stay
// in server.cpp), executed at the start of each round like the kills:
//
//   stall:K@T+D   SIGSTOP agent K's process at tick T, SIGCONT at tick T+D. Only with its --agent-pid and
//                 while no kill of K has been sent (the pid may be reused after a kill): otherwise the world
//                 withholds K's packets for those ticks instead (its agent is then not stepped, as the
//                 in-process harness does).
//   restart:K@T   the world prints `restart id=K tick=T` on stdout (at T, or later when the kill's death is
//                 not yet seen at T: the old owner would refuse the claim); scripts/swarm run (which owns the
//                 agent processes) starts a new robot_agent --id K, which claims the id and rejoins. A world
//                 run by hand prints the line and nothing else happens until someone starts that agent.
//
// Each start and end is an event (`fault` / `fault_end`) saying what was done. A stopped agent is always
// continued before the world ends the run (resume_all; also in the destructor), so the END reaches it.
#pragma once

#include <functional>
#include <optional>

#include <sys/types.h>

#include <map>
#include <string>
#include <vector>

#include "world_server/run/run_session.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

class ProcessFaults {
 public:
  // `agent_pid` gives the process of agent K when known (--agent-pid, or the launcher's --agent-pids file,
  // written after the world started: so it is asked when a fault is due, not at construction).
  using PidLookup = std::function<std::optional<pid_t>(RobotId)>;
  ProcessFaults(const world::Scenario& scenario, PidLookup agent_pid);
  ~ProcessFaults();
  ProcessFaults(const ProcessFaults&) = delete;
  ProcessFaults& operator=(const ProcessFaults&) = delete;

  // The process faults due at the start of round t, and the world faults' events of tick t.
  void at_round(Tick t, world::RunSession& session, const world::World& world);
  // True while robot `id` is stalled by the world itself (no packet goes to its agent).
  bool withheld(RobotId id) const { return id < withheld_.size() && withheld_[id] != 0; }
  // True when at_round(t) will do nothing and record nothing: no fault of the scenario starts or ends at t
  // and no restart waits for a death.
  bool quiet_at(Tick t) const;
  // SIGCONT every agent still stopped (the run ends); events when `session` is given.
  void resume_all(world::RunSession* session);

 private:
  // The pid to signal for robot `id` at tick t: its --agent-pid while no kill of it is due by t; else 0.
  pid_t signalable(RobotId id, Tick t) const;

  const world::Scenario& scenario_;
  PidLookup agent_pid_;
  std::vector<char> withheld_;
  std::map<const world::Fault*, pid_t> stopped_;       // stalls in progress by SIGSTOP, and the pid stopped
  std::vector<const world::Fault*> pending_restarts_;  // due, waiting for the killed robot's death to be seen
};

}  // namespace swarmform::server
