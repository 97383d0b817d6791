// A run's scheduled kills and faults, round by round: the one stage both front ends (the in-process harness
// and the DDS world_server) run at the start of round t, before any robot sees tick t:
//
//   kills due by t (in the schedule's order; a kill asked during the run joins it at its tick)
//   -> each stall starting or ending at t -> each restart due at t, or due earlier and still waiting
//   -> the world faults' events (World itself executes them: wheels, sensors, losses, ranges).
//
// The front ends differ only in what a kill, a stall and a restart do to a robot's agent, which they say
// through FaultActions: the harness drops or swaps a controller, the DDS world signals the agent's process
// (world_server/process_faults.hpp). Each start and end of a fault is an event (`fault`/`fault_end`,
// fault_events.hpp) carrying what the front end did.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "world_server/run/run_session.hpp"
#include "world_server/world/faults.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

class FaultActions {
 public:
  virtual ~FaultActions() = default;
  // Robot `id`'s kill is due; the front end records what it did.
  virtual void kill(RobotId id) = 0;
  // What starting the stall `f` did.
  struct Stall {
    bool stopped = false;  // the front end stopped the agent itself; false: the schedule holds the robot
    std::string what;      // the `fault` event's detail
  };
  virtual Stall start_stall(const Fault& f) = 0;
  // Ends the stall `f` (`stopped` as start_stall said); returns the `fault_end` event's detail.
  virtual std::string end_stall(const Fault& f, bool stopped) = 0;
  // The restart `f` is due at tick t: the `fault` event's detail when done, nullopt to be asked again at the
  // next round (the DDS world waits until the killed agent's death is seen).
  virtual std::optional<std::string> restart(const Fault& f, Tick t) = 0;
};

class FaultSchedule {
 public:
  explicit FaultSchedule(const Scenario& scenario);

  // Robot `id` dies at tick t (a viewer's kill, asked during the run).
  void add_kill(Tick t, RobotId id);
  // The kills and faults due at the start of round t, in the order above.
  void at_round(Tick t, RunSession& session, FaultActions& actions);
  // True while a stall holds robot `id` in the schedule (start_stall did not stop its agent): it gets no
  // perception and its agent is not stepped.
  bool held(RobotId id) const { return id < held_.size() && held_[id] != 0; }
  // True when at_round(t) will do nothing and record nothing: no kill due, no fault starting or ending at t,
  // no restart waiting.
  bool quiet_at(Tick t) const;
  // The run ends: a restart still waiting is recorded as not done.
  void finish(RunSession& session);

 private:
  const Scenario& scenario_;
  std::multimap<Tick, RobotId> kills_;  // not yet done
  std::vector<char> held_;
  std::vector<char> stopped_;                   // per fault: start_stall stopped the agent itself
  std::vector<const Fault*> pending_restarts_;  // due, not done yet
};

}  // namespace swarmform::world
