#include "world_server/run/experiment_runner.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <set>
#include <span>
#include <type_traits>

#include "behaviour/descriptor_check.hpp"
#include "world_server/run/metrics.hpp"
#include "world_server/world/robot_groups.hpp"

namespace swarmform::world {

ExperimentRunner::ExperimentRunner(const World& world, std::size_t group) : world_(world) {
  const Scenario& s = world.scenario();
  const GroupView g = group_view(s, group);
  descriptor_ = g.behaviour;
  first_ = g.first_id;
  count_ = g.count;
  verdict_ = declared_verdict(descriptor_);
  if (descriptor_ == nullptr || descriptor_->experiment.make == nullptr) return;
  arena_ = {s.arena_centre, s.arena_width, s.arena_height, s.walls};
  // The scenario's goal is the run's goal only for a behaviour that goes to one (the world checks it then).
  if (descriptor_->needs_goal) goal_ = experiment::Goal{s.mission.goal, s.mission.goal_radius};
  if (!s.goal_events.empty()) last_goal_move_ = s.goal_events.back().tick;
  try {
    experiment_ = descriptor_->experiment.make();
    if (!experiment_) {
      fail("made no experiment");
      return;
    }
    experiment_->init(*g.mission, g.count);
  } catch (const std::exception& e) {
    fail(std::string("threw in init: ") + e.what());
  }
}

void ExperimentRunner::fail(const std::string& what) {
  experiment_.reset();
  verdict_ = declared_verdict(descriptor_);  // every declared key, null: the summary's keys stay the same
  verdict_.outcome = kExperimentFailed;
  verdict_.error = "experiment of behaviour '" + std::string(descriptor_->name) + "' " + what;
  formation_ = {};
}

ExperimentVerdict declared_verdict(const behaviour::Descriptor* d) {
  ExperimentVerdict v;
  if (d == nullptr || d->experiment.make == nullptr) return v;
  v.success = false;
  for (const auto& m : d->experiment.metrics) v.metrics[std::string(m.name)] = nullptr;
  for (const auto& f : d->experiment.summary) {
    (f.kind == behaviour::SummaryKind::Series ? v.series : v.fields)[std::string(f.key)] = nullptr;
  }
  return v;
}

namespace {

nlohmann::ordered_json field_json(const experiment::FieldValue& value) {
  return std::visit(
      [](const auto& v) -> nlohmann::ordered_json {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return nullptr;
        } else if constexpr (std::is_same_v<T, double>) {
          return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
        } else if constexpr (std::is_same_v<T, std::vector<experiment::SeriesPoint>>) {
          nlohmann::ordered_json series = nlohmann::ordered_json::array();
          for (const auto& [tick, x] : v) {
            series.push_back(nlohmann::ordered_json::array(
                {tick, std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr)}));
          }
          return series;
        } else {
          return v;
        }
      },
      value);
}

// "an integer", "a number"...: what a value is, for the message of one that is not its declared kind.
std::string value_kind(const experiment::FieldValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return "null";
        } else if constexpr (std::is_same_v<T, std::int64_t>) {
          return "an integer";
        } else if constexpr (std::is_same_v<T, double>) {
          return "a number";
        } else if constexpr (std::is_same_v<T, std::vector<std::int64_t>>) {
          return "a list of integers";
        } else {
          return "a series";
        }
      },
      value);
}

// Why the experiment's summary fields cannot be written ("" if they can): a key empty, one the world writes
// itself, one its descriptor does not declare, given twice, or a value not of its declared kind.
std::string check_fields(const behaviour::ExperimentSpec& spec,
                         const std::vector<experiment::SummaryField>& fields) {
  std::set<std::string> seen;
  for (const auto& f : fields) {
    if (f.key.empty()) return "returned a summary field with an empty key";
    if (behaviour::world_summary_key(f.key))
      return "returned summary field '" + f.key + "', a key the world writes";
    const auto declared = std::find_if(spec.summary.begin(), spec.summary.end(),
                                       [&](const behaviour::SummarySpec& s) { return s.key == f.key; });
    if (declared == spec.summary.end())
      return "returned summary field '" + f.key +
             "', which its descriptor does not declare (experiment.summary)";
    if (!seen.insert(f.key).second) return "returned summary field '" + f.key + "' twice";
    if (!behaviour::summary_value_fits(declared->kind, f.value)) {
      return "returned summary field '" + f.key + "' as " + value_kind(f.value) + ", declared " +
             std::string(behaviour::summary_kind_name(declared->kind));
    }
  }
  return {};
}

}  // namespace

// The obstacles change only at world events: the truth's list is built again only after one.
bool ExperimentRunner::obstacles_stale() const {
  if (!obstacles_of_) return true;
  for (const WorldEvent& e : world_.scenario().world_events) {
    if (e.tick > *obstacles_of_ && e.tick <= world_.tick()) return true;
  }
  return false;
}

void ExperimentRunner::refresh_obstacles() {
  obstacles_.clear();  // as they stand this tick (world events move, add and remove them)
  for (const Obstacle& o : world_.obstacles()) {
    if (!o.present) continue;
    experiment::ObstacleTruth ot;
    ot.kind = o.kind == Obstacle::Kind::Box ? experiment::ObstacleTruth::Kind::Box
                                            : experiment::ObstacleTruth::Kind::Cylinder;
    ot.centre = o.centre;
    ot.yaw = o.yaw;
    ot.half_extents = o.half_extents;
    ot.radius = o.radius;
    obstacles_.push_back(ot);
  }
  obstacles_of_ = world_.tick();
}

void ExperimentRunner::observe() {
  if (!experiment_) return;
  const auto& all = world_.robots();
  const std::span<const RobotTruth> truth(all.data() + first_, count_);
  robots_.resize(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    robots_[i] = {truth[i].id,         truth[i].pose, truth[i].alive,
                  &truth[i].telemetry, truth[i].leds, is_silent(truth[i], world_.tick())};
  }
  if (obstacles_stale()) refresh_obstacles();
  experiment::Truth t;
  t.tick = world_.tick();
  t.robots = robots_;
  t.died = died_;
  t.rejoined = rejoined_;
  t.obstacles = obstacles_;
  t.arena = arena_;
  if (goal_) t.goal = world_.goal();  // as it stands this tick (goal_events.hpp)
  try {
    experiment_->observe(t);
    formation_ = experiment_->formation();
    // Not before the goal's last move (goal_events.hpp): an experiment done at a goal that will move cannot
    // know it yet, and the run goes on to the goal where it moves.
    if (!done_at_ && t.tick >= last_goal_move_ && experiment_->done()) done_at_ = t.tick;
  } catch (const std::exception& e) {
    fail("threw at tick " + std::to_string(t.tick) + ": " + e.what());
  }
  died_.clear();
  rejoined_.clear();
}

const ExperimentVerdict& ExperimentRunner::conclude() {
  if (concluded_ || !experiment_) {
    concluded_ = true;
    return verdict_;
  }
  concluded_ = true;
  experiment::Result r;
  try {
    r = experiment_->conclude();
  } catch (const std::exception& e) {
    fail(std::string("threw in conclude: ") + e.what());
    return verdict_;
  }
  if (const std::string why = behaviour::check_result(*descriptor_, r); !why.empty()) {
    fail(why);
    return verdict_;
  }
  if (const std::string why = check_fields(descriptor_->experiment, r.summary); !why.empty()) {
    fail(why);
    return verdict_;
  }
  // Into the declared slots (declared_verdict): the declared order, whatever the order returned.
  for (const auto& f : r.summary) {
    auto& into = verdict_.series.contains(f.key) ? verdict_.series : verdict_.fields;
    into[f.key] = field_json(f.value);
  }
  verdict_.outcome = r.outcome;
  verdict_.success = r.outcome == descriptor_->experiment.success;
  const auto& specs = descriptor_->experiment.metrics;
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const double v = r.metrics[k];
    verdict_.metrics[std::string(specs[k].name)] = std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr;
  }
  return verdict_;
}

}  // namespace swarmform::world
