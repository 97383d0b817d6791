// A run: one World plus its recorder and metrics, writing a run directory (format: docs/recording-format.md).
// Both front ends use it the same way: the DDS world_server and the in-process harness.
//
//   RunSession session(world, options);   // writes world.json, opens the recording, records tick 0
//   loop { ...commands...; world.step(); session.record_tick(); }
//   session.finish(wall_seconds);          // writes summary.json
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "common/types.hpp"
#include "world_server/run/end_reason.hpp"
#include "world_server/run/experiment_runner.hpp"
#include "world_server/run/metrics.hpp"
#include "world_server/run/metrics_tracker.hpp"
#include "world_server/run/recording_format.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

struct RunOptions {
  std::string run_dir;  // created if missing; empty = record nothing to disk (metrics still computed)
  std::string mode = "in-process";  // "lockstep", "realtime" or "in-process", for the summary
  // m: the shape robots' graph for the fragment/rejoin_graph events joins robots this close; 0 = the
  // scenario's comm_range (who can hear whom). E.g. 1.5 x grid spacing watches the formation's own neighbour
  // links.
  double fragment_range = 0.0;
  // robots.csv gets the rows of every record_every-th tick only (ticks 0, K, 2K...; >= 1): a long run of
  // many robots (10^7 rows for 1024 robots over 10^4 ticks) thinned. Events, metrics and
  // trajectory_sha256 still see every tick; world.json says K.
  Tick record_every = 1;
};

class RunSession {
 public:
  RunSession(const World& world, RunOptions options);
  ~RunSession();
  RunSession(const RunSession&) = delete;
  RunSession& operator=(const RunSession&) = delete;

  // After each World::step(): one recording row per robot, events derived from telemetry changes (state,
  // label, leader), fragment/rejoin of the neighbour graph, and the metrics. Flushed as it goes: a crashed
  // run keeps what it had.
  void record_tick();

  // Events the front end knows of and the world does not.
  void record_death(RobotId id);
  void record_rejoin(RobotId id);
  // Counts a command not taken as it came (summary command_verdicts) and writes its `command` event, which
  // stands for `event_for` such commands (its `count` field when > 1); 0: counted, no event (a front end
  // that logs repeated bad input once a second).
  void record_command_verdict(RobotId id, CommandVerdict verdict, std::uint64_t event_for = 1);
  // `id` -1: about no single robot (e.g. a fault of every robot).
  void record_event(std::int64_t id, const std::string& kind, const std::string& detail);
  // Writes out what is recorded so far, now rather than at the next periodic flush: for an event that says
  // why the run stands still (nothing else is recorded while it does).
  void flush();

  const Metrics& metrics() const;
  // The tick at which the behaviour's experiment said the run was done (run_end.hpp), if it has.
  std::optional<Tick> experiment_done_at() const;
  // The behaviour's experiment (its own measures: for a test that reads them), null without one or once it
  // failed; what it says of its formation after the last tick (the view's formation line).
  const experiment::Experiment* experiment() const;
  const experiment::Formation& formation() const;
  // The experiment's verdict: complete once finish() has run.
  const ExperimentVerdict& verdict() const;

  // Why the run stopped, for summary.json's end_reason. Unset, finish() says completed when the run arrived
  // and settled (run_end.hpp), else max_ticks when it used them up, else interrupted.
  void set_end_reason(EndReason reason);
  // A front end's own summary field (e.g. world_server's input_dropped counts).
  void set_summary_field(const std::string& key, nlohmann::ordered_json value);

  // Writes summary.json (the metrics plus robots, seed, mode, ticks, wall_seconds, ticks_per_second, the
  // steady rate when `steady` was measured, alive_at_end, trajectory_sha256, end_reason, provenance) and
  // closes the recording. Returns the summary as JSON text. Throws RecordingError when summary.json cannot be
  // written (a full disk); the text is then still what it would have held.
  std::string finish(double wall_seconds, const SteadyWindow& steady = {});
  // The disk was full when finish() wrote summary.json: it holds the run's outcome only
  // (recording_format.hpp summary_outcome).
  bool summary_cut() const;
  // The summary's words for the end-of-run line: "summary.json written" (", cut to the run's outcome").
  std::string summary_written() const;

  // SHA-256 over the recorded poses so far (bit patterns of x, y, theta of every robot every tick).
  std::string trajectory_sha256() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::world
