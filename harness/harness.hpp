// The in-process harness: the same World with N controllers in one process, no DDS. Deterministic and fast;
// used by the simulation tests and the large-N benchmark. Each tick, the DDS world_server's round without the
// wire: kills and faults (the same stage, run/fault_schedule.hpp), every live robot's controller steps on its
// perception, the commands go to the world, the world steps, the session records.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "behaviour/controller.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::harness {

// A robot's controller threw, or returned a non-finite wheel speed: the in-process run cannot go on (all the
// behaviours share one process). what() names the robot, the behaviour, the tick and what happened.
class BehaviourFailure : public std::runtime_error {
 public:
  BehaviourFailure(RobotId robot, const std::string& what) : std::runtime_error(what), robot_(robot) {}
  RobotId robot() const { return robot_; }

 private:
  RobotId robot_;
};

// The robot whose controller the calling thread is stepping now, or -1: for a crash handler (a plug-in's
// SIGSEGV) to name the robot. A plain thread-local read, safe in a signal handler.
std::int64_t robot_being_stepped();

struct HarnessOptions {
  std::string run_dir;          // empty: no files written
  double fragment_range = 0.0;  // m, see world::RunOptions::fragment_range (0: the comm range)
  Tick record_every = 1;        // see world::RunOptions::record_every
};

class Harness {
 public:
  explicit Harness(const world::Scenario& scenario, HarnessOptions options = {});
  ~Harness();

  // One tick for everyone. Throws BehaviourFailure when a controller fails (the lowest id's failure when
  // several fail in one tick); the world has not stepped then.
  void step();
  // Steps until the scenario's max_ticks, or until `stop` returns true (checked after each tick).
  void run(const std::function<bool(const Harness&)>& stop = {});

  void kill(RobotId id);    // the robot dies now (its controller is dropped)
  void revive(RobotId id);  // a fresh controller for it (init with the mission), as a restarted agent
  // Robot `id` runs `controller` from now on (already initialised by the caller): tests put a faulty agent
  // in, e.g. one that stays alive and says nothing.
  void set_controller(RobotId id, std::unique_ptr<controller::Controller> controller);

  const world::World& world() const;
  world::World& world();
  const world::Metrics& metrics() const;
  // The run's recording and judgement: its experiment (the behaviour's measures) and, after finish(), its
  // verdict.
  const world::RunSession& session() const;
  const controller::Controller& controller(RobotId id) const;
  // Writes summary.json and returns its text; `reason` overrides the end_reason RunSession derives
  // (completed or max_ticks). Throws world::RecordingError when summary.json cannot be written.
  std::string finish(double wall_seconds, std::optional<world::EndReason> reason = std::nullopt);
  // After finish(): its words for the end-of-run line (RunSession::summary_written).
  std::string summary_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::harness
