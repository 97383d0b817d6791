// What the DDS world_server does to an agent's process when the fault schedule (run/fault_schedule.hpp, the
// stage it shares with the in-process harness) says so:
//
//   kill:K@T      SIGKILL agent K's process: its death is then seen through DDS liveliness, as any crash's.
//                 Without its pid the robot dies in the world, and its agent gets no more packets.
//   stall:K@T+D   SIGSTOP agent K's process at tick T, SIGCONT at tick T+D. Only with its --agent-pid and
//                 while no kill of K has been due (the pid may be reused after a kill): otherwise the
//                 schedule holds the robot (its packets are withheld for those ticks; its agent is then not
//                 stepped, as in the harness).
//   restart:K@T   the world says `restart` on its status channel and prints `restart id=K tick=T` on stdout
//                 (docs/status-channel.md; at T, or later when the kill's death is
//                 not yet seen at T: the old owner would refuse the claim); scripts/swarm run (which owns the
//                 agent processes) starts a new robot_agent --id K, which claims the id and rejoins. A world
//                 run by hand prints the line and nothing else happens until someone starts that agent.
//
// A stopped agent is always continued before the world ends the run (resume_all; also in the destructor), so
// the END reaches it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "world_server/run/fault_schedule.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/status_channel.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

class ProcessFaults : public world::FaultActions {
 public:
  // `agent_pid` gives the process of agent K when known (--agent-pid, or the launcher's --agent-pids file,
  // written after the world started: so it is asked when a fault is due, not at construction).
  using PidLookup = std::function<std::optional<pid_t>(RobotId)>;
  ProcessFaults(const world::Scenario& scenario, world::World& world, world::RunSession& session,
                PidLookup agent_pid, StatusChannel* status = nullptr);
  ~ProcessFaults() override;
  ProcessFaults(const ProcessFaults&) = delete;
  ProcessFaults& operator=(const ProcessFaults&) = delete;

  void kill(RobotId id) override;
  Stall start_stall(const world::Fault& f) override;
  std::string end_stall(const world::Fault& f, bool stopped) override;
  std::optional<std::string> restart(const world::Fault& f, Tick t) override;

  // How long ago a SIGKILL went to robot `id`'s agent (ms), if one did and was not asked for yet: the
  // detection delay its death event reports.
  std::optional<long long> take_kill_delay_ms(RobotId id);
  // The world itself stopped `pid` (a stall fault in progress): its silence is that fault's, judged as a
  // stall fault is, not the host's slowness.
  bool stopped(pid_t pid) const;
  // SIGCONT every agent still stopped (the run ends); events when `session` is given.
  void resume_all(world::RunSession* session);

 private:
  // The pid to signal for robot `id` at tick t: its --agent-pid while no kill of it is due by t; else 0.
  pid_t signalable(RobotId id, Tick t) const;

  const world::Scenario& scenario_;
  world::World& world_;
  world::RunSession& session_;
  PidLookup agent_pid_;
  StatusChannel* status_;                         // where a restart is asked for; null: stdout only
  std::map<const world::Fault*, pid_t> stopped_;  // stalls in progress by SIGSTOP, and the pid stopped
  std::map<RobotId, std::chrono::steady_clock::time_point> kill_sent_;
};

}  // namespace swarmform::server
