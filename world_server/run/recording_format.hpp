// The JSON documents of a run directory whose content is more than a stream: world.json (what the run is) and
// summary.json (what came of it). Field by field in docs/recording-format.md; a reader is written against
// that page, so a field is added, never renamed.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "world_server/run/experiment_runner.hpp"
#include "world_server/run/metrics.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

inline constexpr int kRecordingVersion = 1;

// world.json: the arena, obstacles, goal, floor, lights, battery, shape and the run's settings. `mode`:
// "lockstep", "realtime", "in-process".
nlohmann::ordered_json describe_world(const Scenario& scenario, const std::string& mode);

// The floor image's copy in the run folder, as world.json names it (floor.image.file): a run folder copied
// elsewhere keeps its floor (world_server/run/README.md).
inline constexpr const char* kFloorImageFile = "floor.png";

// world.json's `behaviour_descriptor`: the behaviour's name, plug-in path, parameters (with the run's
// values), states and colours, telemetry columns, needs_shape and needs_goal (docs/recording-format.md).
nlohmann::ordered_json describe_behaviour(const Scenario& scenario);
// The same of robot group `group`'s behaviour (robot_groups.hpp).
nlohmann::ordered_json describe_behaviour(const Scenario& scenario, std::size_t group);
// world.json's and `world_server --check`'s `groups`: [{name, first_id, count, behaviour_descriptor}] (null
// for a scenario without groups).
nlohmann::ordered_json describe_groups(const Scenario& scenario);

// The steady part of a run's wall clock: the time after its first `from_tick` ticks, which are slower than
// the rest (world_server --warmup-ticks says why). bench-lockstep compares this rate with bare_round's.
struct SteadyWindow {
  Tick from_tick = 0;
  double seconds = 0.0;  // wall time from the end of tick from_tick to the end of the run; 0: not measured
};

struct SummaryInputs {
  const Scenario* scenario = nullptr;
  std::string mode;
  Tick ticks = 0;  // ticks stepped (the last recorded tick)
  double wall_seconds = 0.0;
  SteadyWindow steady;
  const std::vector<RobotTruth>* robots = nullptr;
  const Metrics* metrics = nullptr;
  const ExperimentVerdict* verdict = nullptr;  // the behaviour's experiment: outcome, success, its metrics
  // With robot groups: each group's verdict, in group order (summary.json's `groups`); null without.
  const std::vector<const ExperimentVerdict*>* group_verdicts = nullptr;
  std::string trajectory_sha256;
  std::uint64_t command_verdicts = 0;  // commands not taken as they came (clamped, rejected, dropped)
  std::string end_reason;              // why the run stopped (end_reason.hpp)
  nlohmann::ordered_json provenance;   // provenance.hpp
  // Front-end fields, each a key of the summary (e.g. world_server's "input_dropped"); an object or null.
  nlohmann::ordered_json extra;
};

// summary.json: the world's generic metrics, then the experiment's own fields (ExperimentVerdict::fields)
// after max_components, its series last; null where not reached.
nlohmann::ordered_json make_summary(const SummaryInputs& in);
// summary.json as make_summary will write it for a run of this scenario, before the run: every key it will
// have, whatever the run (the values as before any tick: no robot counted in a state, every declared
// experiment key null). `world_server --check` and `swarm_inprocess --check` print it, so a launcher checks
// an
// --expect key against the keys of the code that writes the run's summary. Not the front end's own keys
// (world_server's input_dropped, mass_losses: RunSession::set_summary_field) nor experiment_error (a
// failure's).
nlohmann::ordered_json summary_template(const Scenario& scenario, const std::string& mode);
// What `world_server --check` and `swarm_inprocess --check` print of a loaded scenario (one JSON line):
// robots, labels, mode, max_ticks, seed, behaviour_descriptor, groups (with robot groups) and
// summary_template, for the launcher's checks before a run (docs/recording-format.md).
nlohmann::ordered_json check_info(const Scenario& scenario);
// A series: a non-empty array of [tick, value] pairs (the paper's `distortion`).
bool is_series(const nlohmann::ordered_json& value);
// The summary as text: indented, except each long series, which goes on one line at the end.
std::string summary_text(const nlohmann::ordered_json& summary);
// The summary cut to the run's outcome, for a full disk: every field but the series, each list (deaths,
// stuck robots, ...) cut to its first kOutcomeListEntries, and `summary_cut` saying so with the lists' full
// lengths. It fits the room reserved for summary.json (recorder.hpp) whatever the run.
inline constexpr std::size_t kOutcomeListEntries = 16;
nlohmann::ordered_json summary_outcome(const nlohmann::ordered_json& summary);

}  // namespace swarmform::world
