// Runs a behaviour's experiment (behaviour/experiment.hpp) over a run: made from the descriptor, shown the
// truth after every recorded tick, concluded at the end and its result checked against what the descriptor
// declares. Both front ends get it through RunSession, so an in-process run and a multi-process run judge the
// same truth with the same code. An experiment that throws or breaks its declaration is a bug in the
// behaviour: the run goes on and the verdict says so (outcome experiment_failed), never a silent default.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "behaviour/descriptor.hpp"
#include "behaviour/experiment.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

// What summary.json says of the behaviour's judgement (docs/recording-format.md).
struct ExperimentVerdict {
  std::string outcome = "none";  // the experiment's, "none" without one, "experiment_failed"
  std::optional<bool> success;   // null without an experiment
  nlohmann::ordered_json metrics = nlohmann::ordered_json::object();  // behaviour_metrics
  // The experiment's own top-level keys (Result::summary): every key its descriptor declares, in the declared
  // order, null when conclude did not give it (or the experiment failed); `series` the keys declared a series
  // ([[tick, value]...], written last), `fields` the others. Empty without an experiment.
  nlohmann::ordered_json fields = nlohmann::ordered_json::object();
  nlohmann::ordered_json series = nlohmann::ordered_json::object();
  std::string error;  // with experiment_failed: what went wrong
};

inline constexpr const char* kExperimentFailed = "experiment_failed";

// The verdict of behaviour `d` before its experiment concluded: without an experiment, outcome none; with
// one, success false and every declared metric and summary key null. What summary.json's keys will be,
// whatever the run (the summary template of `world_server --check` is made from it).
ExperimentVerdict declared_verdict(const behaviour::Descriptor* d);

class ExperimentRunner {
 public:
  // The experiment of robot group `group`'s behaviour (robot_groups.hpp; 0 without groups: every robot's),
  // shown the truth of that group's robots only (their global ids, in id order).
  explicit ExperimentRunner(const World& world, std::size_t group = 0);
  bool active() const { return experiment_ != nullptr; }
  // The tick's truth (after World::step, or tick 0).
  void observe();
  void died(RobotId id) {
    if (mine(id)) died_.push_back(id);
  }
  void rejoined(RobotId id) {
    if (mine(id)) rejoined_.push_back(id);
  }
  // Whether the behaviour has an experiment (even one that failed since): a run with groups ends early only
  // when each of these is done.
  bool judges() const { return descriptor_ != nullptr && descriptor_->experiment.make != nullptr; }
  // Once; later calls return the same verdict.
  const ExperimentVerdict& conclude();
  // The tick after whose observe the experiment first said it was done (Experiment::done), if it has.
  std::optional<Tick> done_at() const { return done_at_; }
  // What the experiment said of its formation after the last observe (none without an experiment).
  const experiment::Formation& formation() const { return formation_; }
  // The experiment (null without one or once it failed), and the verdict as it stands (conclude's once run).
  const experiment::Experiment* experiment() const { return experiment_.get(); }
  const ExperimentVerdict& verdict() const { return verdict_; }
  // Set once the experiment failed (for world.log), else empty.
  const std::string& error() const { return verdict_.error; }

 private:
  void fail(const std::string& what);
  bool mine(RobotId id) const { return id >= first_ && id - first_ < count_; }

  const World& world_;
  const behaviour::Descriptor* descriptor_ = nullptr;
  RobotId first_ = 0;  // the group's robots: first_..first_+count_-1
  std::size_t count_ = 0;
  std::unique_ptr<experiment::Experiment> experiment_;
  std::vector<experiment::RobotTruth> robots_;
  bool obstacles_stale() const;
  void refresh_obstacles();
  std::vector<experiment::ObstacleTruth> obstacles_;
  std::optional<Tick> obstacles_of_;  // the tick obstacles_ was built at (rebuilt only after a world event)
  std::vector<RobotId> died_, rejoined_;
  experiment::ArenaTruth arena_;
  std::optional<experiment::Goal> goal_;
  experiment::Formation formation_;
  bool concluded_ = false;
  std::optional<Tick> done_at_;
  Tick last_goal_move_ = 0;  // the scenario's last goal move (goal_events.hpp), 0: none
  ExperimentVerdict verdict_;
};

}  // namespace swarmform::world
