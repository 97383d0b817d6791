#include "world_server/run/experiment_runner.hpp"

#include <cmath>
#include <exception>

#include "behaviour/descriptor_check.hpp"

namespace swarmform::world {

ExperimentRunner::ExperimentRunner(const World& world) : world_(world) {
  const Scenario& s = world.scenario();
  descriptor_ = s.behaviour;
  if (descriptor_ == nullptr || descriptor_->experiment.make == nullptr) return;
  verdict_.success = false;
  for (const auto& m : descriptor_->experiment.metrics) verdict_.metrics[std::string(m.name)] = nullptr;
  arena_ = {s.arena_centre, s.arena_width, s.arena_height, s.walls};
  // The scenario's goal is the run's goal only for a behaviour that goes to one (the world checks it then).
  if (descriptor_->needs_goal) goal_ = experiment::Goal{s.mission.goal, s.mission.goal_radius};
  track_shape_ = descriptor_->needs_shape && descriptor_->needs_goal;
  try {
    experiment_ = descriptor_->experiment.make();
    if (!experiment_) {
      fail("made no experiment");
      return;
    }
    experiment_->init(s.mission, world.robot_count());
  } catch (const std::exception& e) {
    fail(std::string("threw in init: ") + e.what());
  }
}

void ExperimentRunner::fail(const std::string& what) {
  experiment_.reset();
  verdict_.outcome = kExperimentFailed;
  verdict_.success = false;
  verdict_.error = "experiment of behaviour '" + std::string(descriptor_->name) + "' " + what;
  for (auto& [name, value] : verdict_.metrics.items()) value = nullptr;
}

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

void ExperimentRunner::observe(const Metrics& metrics) {
  if (!experiment_) return;
  const auto& truth = world_.robots();
  robots_.resize(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    robots_[i] = {truth[i].id, truth[i].pose, truth[i].alive, &truth[i].telemetry, truth[i].leds};
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
  if (track_shape_) t.shape = experiment::ShapeProgress{metrics.formation_tick, metrics.goal_tick};
  try {
    experiment_->observe(t);
    if (!done_at_ && experiment_->done()) done_at_ = t.tick;
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
