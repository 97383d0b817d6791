// RunSession: after each World::step, derive the events, update the metrics, hash the poses and (with a run
// directory) write the recording. The experiment observes first in record_tick because the formation tick it
// finds switches on the graph events of the same tick.
#include "world_server/run/run_session.hpp"

#include <bit>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "world_server/run/experiment_runner.hpp"
#include "world_server/run/metrics_tracker.hpp"
#include "world_server/run/provenance.hpp"
#include "world_server/run/recorder.hpp"
#include "world_server/run/recording_format.hpp"
#include "world_server/run/run_end.hpp"
#include "world_server/run/run_events.hpp"
#include "world_server/run/sha256.hpp"
#include "world_server/run/telemetry_columns.hpp"
#include "world_server/world/robot_groups.hpp"

namespace swarmform::world {

namespace {

static_assert(std::endian::native == std::endian::little, "the trajectory hash is defined little-endian");

// One line of world.log for an event: "kind id {fields}".
std::string log_line(const Event& e) {
  // Appends, not operator+ chains: GCC 12 gives a false -Wrestrict on those at -O2.
  std::string line = e.value("kind", "?");
  line.append(" robot ");
  line.append(std::to_string(e.value("id", std::int64_t{-1})));
  Event rest = e;
  rest.erase("tick");
  rest.erase("kind");
  rest.erase("id");
  if (!rest.empty()) {
    line.push_back(' ');
    line.append(rest.dump());
  }
  return line;
}

}  // namespace

std::vector<std::unique_ptr<ExperimentRunner>> make_experiments(const World& w) {
  std::vector<std::unique_ptr<ExperimentRunner>> out;
  for (std::size_t k = 0; k < group_count(w.scenario()); ++k)
    out.push_back(std::make_unique<ExperimentRunner>(w, k));
  return out;
}

struct RunSession::Impl {
  Impl(const World& w, RunOptions o)
      : world(w),
        options(std::move(o)),
        experiments(make_experiments(w)),
        experiment(*experiments.front()),
        fragment_range(options.fragment_range > 0.0 ? options.fragment_range : w.scenario().comm_range),
        events(fragment_range, w.scenario().behaviour ? w.scenario().behaviour->states
                                                      : std::span<const behaviour::StateSpec>{}) {
    if (options.record_every < 1) throw std::invalid_argument("RunOptions::record_every must be at least 1");
    const Scenario& scenario = world.scenario();
    events.set_known_columns(known_columns_by_robot(scenario));
    if (!scenario.groups.empty()) {
      std::vector<std::span<const behaviour::StateSpec>> by_id;
      for (RobotId id = 0; id < scenario.robots.size(); ++id)
        by_id.push_back(behaviour_of(scenario, id)->states);
      events.set_robot_states(std::move(by_id));
    }
    if (!options.run_dir.empty()) {
      const TelemetryColumns columns = telemetry_columns(scenario);
      writer.emplace(options.run_dir, columns.names, sensors_of_run(scenario), columns.of_robot,
                     columns.known);
      auto description = describe_world(world.scenario(), options.mode);
      description["fragment_range"] = fragment_range;
      description["record_every"] = options.record_every;
      if (world.scenario().floor.image) writer->copy_in(world.scenario().floor.image->file, kFloorImageFile);
      writer->write_world(description);
      writer->log(world.tick(), "run starts: " + std::to_string(world.robot_count()) + " robots, scenario " +
                                    world.scenario().source + ", mode " + options.mode);
    }
  }

  void emit(const Event& e) {
    tracker.count_event(e);
    if (writer) {
      writer->write_event(e);
      writer->log(e.value("tick", Tick{0}), log_line(e));
    }
  }

  void record() {
    const Tick tick = world.tick();
    const auto& robots = world.robots();
    tracker.observe(tick, robots, recorded_once ? world.last_contacts() : ContactCounts{});
    for (auto& e : experiments) e->observe();
    // The communication graph is watched from the tick the behaviour's experiment says it stood formed on
    // (before it, robots joining a shape one by one would read as endless splits and rejoins); never for a
    // behaviour without one.
    const bool track_graph = experiment.formation().tick.has_value();
    std::size_t components = 0;
    for (const auto& e : events.observe(tick, robots, track_graph, components)) emit(e);
    // What the controllers said happened (label taken/lost/freed, barrier, leader elected, parent...).
    for (const auto& e : controller_events(tick, robots)) emit(e);
    // A battery that ran out this tick (world.hpp RobotTruth::battery_empty_tick): its robot's wheels stop.
    for (const auto& r : robots) {
      if (r.battery_empty_tick == tick)
        emit(make_event(tick, "battery_empty", static_cast<std::int64_t>(r.id)));
    }
    if (track_graph) tracker.note_components(components);
    // x, y, theta of every robot in id order, each as its 8-byte little-endian bit pattern; one update a
    // tick.
    pose_bytes.resize(robots.size() * 3 * sizeof(double));
    unsigned char* out = pose_bytes.data();
    for (const auto& r : robots) {
      for (const double v : {r.pose.x, r.pose.y, r.pose.theta}) {
        std::memcpy(out, &v, sizeof(double));
        out += sizeof(double);
      }
    }
    sha.update(pose_bytes.data(), pose_bytes.size());
    if (writer && tick % options.record_every == 0) {
      // readings.csv first: write_rows may flush, and the two files are flushed together.
      writer->write_readings(tick, world);
      writer->write_rows(tick, robots);
    }
    recorded_once = true;
    last_recorded_tick = tick;
  }

  const World& world;
  RunOptions options;
  MetricsTracker tracker;
  // Each robot group's behaviour's own judge (one without groups); `experiment` is the first group's, whose
  // verdict is summary.json's top level and whose formation switches the graph watch on.
  std::vector<std::unique_ptr<ExperimentRunner>> experiments;
  ExperimentRunner& experiment;
  double fragment_range;  // m
  EventDeriver events;
  Sha256 sha;
  std::vector<unsigned char> pose_bytes;
  std::optional<RecordingWriter> writer;
  bool recorded_once = false;
  Tick last_recorded_tick = 0;
  std::uint64_t command_verdicts = 0;
  std::optional<EndReason> end_reason;
  nlohmann::ordered_json extra = nlohmann::ordered_json::object();
  bool finished = false;
  bool summary_cut = false;
};

RunSession::RunSession(const World& world, RunOptions options)
    : impl_(std::make_unique<Impl>(world, std::move(options))) {
  impl_->record();  // tick 0: the starting poses
}

RunSession::~RunSession() {
  if (impl_ && impl_->writer) {
    try {
      impl_->writer->flush();
    } catch (...) {  // a destructor must not throw; the data already written stays
    }
  }
}

void RunSession::record_tick() {
  impl_->record();
}

void RunSession::record_death(RobotId id) {
  if (auto e = impl_->events.death(impl_->world.tick(), id)) {
    impl_->emit(*e);
    for (auto& x : impl_->experiments) x->died(id);
  }
}

void RunSession::record_rejoin(RobotId id) {
  if (auto e = impl_->events.rejoin(impl_->world.tick(), id)) {
    impl_->emit(*e);
    for (auto& x : impl_->experiments) x->rejoined(id);
  }
}

void RunSession::record_command_verdict(RobotId id, CommandVerdict verdict, std::uint64_t event_for) {
  if (verdict == CommandVerdict::Ok) return;
  ++impl_->command_verdicts;
  if (event_for == 0) return;
  Event e = make_event(impl_->world.tick(), "command", id);
  e["verdict"] = to_string(verdict);
  if (event_for > 1) e["count"] = event_for;
  impl_->emit(e);
}

void RunSession::flush() {
  if (impl_->writer) impl_->writer->flush();
}

void RunSession::record_event(std::int64_t id, const std::string& kind, const std::string& detail) {
  Event e = make_event(impl_->world.tick(), kind, id);
  e["detail"] = detail;
  impl_->emit(e);
}

// With groups: the tick by which every group's experiment was done (none has one: never).
std::optional<Tick> RunSession::experiment_done_at() const {
  if (impl_->experiments.size() == 1) return impl_->experiment.done_at();
  std::optional<Tick> last;
  for (const auto& e : impl_->experiments) {
    if (!e->judges()) continue;
    const std::optional<Tick> done = e->done_at();
    if (!done) return std::nullopt;
    last = std::max(last.value_or(0), *done);
  }
  return last;
}

const Metrics& RunSession::metrics() const {
  return impl_->tracker.metrics();
}

const experiment::Experiment* RunSession::experiment() const {
  return impl_->experiment.experiment();
}

const experiment::Formation& RunSession::formation() const {
  return impl_->experiment.formation();
}

const ExperimentVerdict& RunSession::verdict() const {
  return impl_->experiment.verdict();
}

bool RunSession::summary_cut() const {
  return impl_->summary_cut;
}

std::string RunSession::summary_written() const {
  return impl_->summary_cut ? "summary.json written, cut to the run's outcome (the whole did not fit)"
                            : "summary.json written";
}

std::string RunSession::trajectory_sha256() const {
  return impl_->sha.hex_digest();
}

void RunSession::set_end_reason(EndReason reason) {
  impl_->end_reason = reason;
}

void RunSession::set_summary_field(const std::string& key, nlohmann::ordered_json value) {
  impl_->extra[key] = std::move(value);
}

std::string RunSession::finish(double wall_seconds, const SteadyWindow& steady) {
  if (!impl_->finished) impl_->tracker.conclude();
  const Tick tick = impl_->last_recorded_tick;
  const Tick max_ticks = impl_->world.scenario().max_ticks;
  EndReason reason = EndReason::Interrupted;
  if (impl_->end_reason) {
    reason = *impl_->end_reason;
  } else if (const auto done = experiment_done_at(); done && tick >= *done + kTicksAfterDone) {
    reason = EndReason::Completed;
  } else if (tick >= max_ticks) {
    reason = EndReason::MaxTicks;
  }
  SummaryInputs in;
  in.scenario = &impl_->world.scenario();
  in.mode = impl_->options.mode;
  in.ticks = impl_->last_recorded_tick;
  in.wall_seconds = wall_seconds;
  in.steady = steady;
  in.robots = &impl_->world.robots();
  in.metrics = &impl_->tracker.metrics();
  in.verdict = &impl_->experiment.conclude();
  std::vector<const ExperimentVerdict*> verdicts;
  for (auto& e : impl_->experiments) verdicts.push_back(&e->conclude());
  if (!impl_->world.scenario().groups.empty()) in.group_verdicts = &verdicts;
  in.trajectory_sha256 = trajectory_sha256();
  in.command_verdicts = impl_->command_verdicts;
  in.end_reason = std::string(to_string(reason));
  in.provenance = provenance(impl_->world.scenario());
  in.extra = impl_->extra;
  const auto summary = make_summary(in);
  const bool write = impl_->writer && !impl_->finished;
  impl_->finished = true;
  if (write) {
    try {
      if (!in.verdict->error.empty()) impl_->writer->log(impl_->last_recorded_tick, in.verdict->error);
      impl_->writer->log(impl_->last_recorded_tick, "run ends: " + in.end_reason);
    } catch (const RecordingError&) {  // world.log may be what failed; the summary is still tried
    }
    impl_->summary_cut = impl_->writer->write_summary(summary);
  }
  return summary_text(summary);
}

}  // namespace swarmform::world
