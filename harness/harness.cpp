// The in-process harness: the round of the DDS world_server without DDS; Impl::step lists its stages.
// The kills and faults are the same stage as the world_server's (run/fault_schedule.hpp); what they do to a
// robot's agent here (FaultActions): a kill drops its controller; a stall holds the robot in the schedule, so
// its controller is not stepped for its ticks (the world keeps the robot's last wheel speeds and it says
// nothing, as with a SIGSTOPped agent); a restart is a fresh controller (init with the mission) for the
// robot, which comes back to life where its body stands. The world faults act inside World.
// The controllers step on the worker pool (world_server/world/parallel_for.hpp): each reads only its own
// perception (copied into its worker's buffer) and writes only its own command slot; the commands then go to
// the world one after the other in id order, exactly as a serial loop would, so a run is deterministic for a
// scenario and seed whatever the worker count.
#include "harness/harness.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "behaviour/registry.hpp"
#include "world_server/run/fault_schedule.hpp"
#include "world_server/run/run_end.hpp"
#include "world_server/world/parallel_for.hpp"
#include "world_server/world/robot_groups.hpp"

namespace swarmform::harness {

namespace {
thread_local std::int64_t t_stepping = -1;  // robot_being_stepped()
}  // namespace

std::int64_t robot_being_stepped() {
  return t_stepping;
}

struct Harness::Impl : world::FaultActions {
  Impl(const world::Scenario& s, HarnessOptions o)
      : scenario(s),
        options(std::move(o)),
        world(scenario),
        session(world, {options.run_dir, "in-process", options.fragment_range, options.record_every}),
        schedule(scenario) {
    // Every perception is read by copy_perception on the worker pool (step below): each inbox is gathered
    // and each robot's ultrasonics read there, into the reading core's copy, instead of at the world's step.
    world.defer_perceptions(true);
    controllers.reserve(scenario.robots.size());
    for (RobotId id = 0; id < scenario.robots.size(); ++id) {
      controllers.push_back(make(id));
    }
  }

  // A controller of the robot's behaviour (its group's, with groups; resolved through the registry when the
  // scenario was loaded), told its group's mission.
  std::unique_ptr<controller::Controller> make(RobotId id) const {
    const behaviour::Descriptor* d = world::behaviour_of(scenario, id);
    if (d == nullptr) throw std::logic_error("harness: the scenario has no behaviour");
    return behaviour::make_controller(*d, world::mission_of(scenario, id), id);
  }

  BehaviourFailure failure(RobotId id, const std::string& what) const {
    const Mission& mission = world::mission_of(scenario, id);
    std::ostringstream m;
    m << "robot " << id << "'s behaviour '" << mission.behaviour << "'"
      << (mission.plugin.empty() ? "" : " (plug-in " + mission.plugin + ")") << " at tick " << world.tick()
      << ": " << what;
    return BehaviourFailure(id, m.str());
  }

  void check_id(RobotId id) const {
    if (id >= controllers.size()) {
      throw std::out_of_range("harness: no robot " + std::to_string(id) + " (the scenario has " +
                              std::to_string(controllers.size()) + ")");
    }
  }

  void kill(RobotId id) override {
    check_id(id);
    if (!world.alive(id)) return;
    world.kill(id);
    controllers[id].reset();
    session.record_death(id);
  }

  void revive(RobotId id) {
    check_id(id);
    if (!world.alive(id)) world.revive(id);  // a live robot only gets the fresh controller (agent restart)
    controllers[id] = make(id);
    session.record_rejoin(id);
  }

  // FaultActions: a stall holds the robot in the schedule; a restart is done at once.
  Stall start_stall(const world::Fault& f) override {
    return {false, world.alive(*f.robot)
                       ? "its controller is not stepped for " + std::to_string(*f.duration) + " ticks"
                       : "the robot is dead: nothing to stall"};
  }
  std::string end_stall(const world::Fault&, bool) override { return "its controller is stepped again"; }
  std::optional<std::string> restart(const world::Fault& f, Tick) override {
    revive(*f.robot);
    return "a fresh controller for the robot";
  }

  // One round, stage by stage (the DDS world_server's Server::run_rounds, without the wire).
  void step() {
    schedule.at_round(world.tick(), session, *this);  // kills and faults
    step_controllers();                               // "publish" and "collect": each controller's command
    check_commands();
    apply_commands();
    world.step();
    session.record_tick();
  }

  // Every live robot's controller that is not held steps on its perception, on the worker pool.
  void step_controllers() {
    const std::size_t n = controllers.size();
    commands.resize(n);
    stepped.assign(n, 0);
    errors.assign(n, std::string());
    copies.resize(parallel::worker_count());
    parallel::for_range(n, [&](std::size_t begin, std::size_t end, std::size_t worker) {
      world::World::PerceptionCopy& copy = copies[worker].copy;
      for (std::size_t i = begin; i < end; ++i) {
        const auto id = static_cast<RobotId>(i);
        if (!controllers[i] || !world.alive(id) || schedule.held(id)) continue;
        // An exception must not leave a worker thread: it is kept and raised below, on this thread.
        try {
          t_stepping = static_cast<std::int64_t>(i);
          commands[i] = controllers[i]->step(world.copy_perception(id, copy));
          t_stepping = -1;
          stepped[i] = 1;
        } catch (const std::exception& e) {
          t_stepping = -1;
          errors[i] = std::string("threw: ") + e.what();
        } catch (...) {
          t_stepping = -1;
          errors[i] = "threw an exception that is not a std::exception";
        }
      }
    });
  }

  // A controller that threw or returned a non-finite wheel speed ends the run (the lowest id's), before the
  // world steps.
  void check_commands() const {
    for (RobotId id = 0; id < controllers.size(); ++id) {
      if (!errors[id].empty()) throw failure(id, errors[id]);
      if (!stepped[id]) continue;
      const Command& c = commands[id];
      if (!std::isfinite(c.left_speed) || !std::isfinite(c.right_speed)) {
        std::ostringstream what;
        what << "returned a non-finite wheel speed (left " << c.left_speed << ", right " << c.right_speed
             << " m/s)";
        throw failure(id, what.str());
      }
    }
  }

  // In id order, exactly as a serial loop would; verdicts other than Ok are recorded.
  void apply_commands() {
    for (RobotId id = 0; id < controllers.size(); ++id) {
      if (!stepped[id]) continue;
      const auto verdict = world.apply_command(id, commands[id]);
      if (verdict != world::CommandVerdict::Ok) session.record_command_verdict(id, verdict);
    }
  }

  const world::Scenario scenario;  // a copy: the world and the controllers refer to it for the whole run
  HarnessOptions options;
  world::World world;
  world::RunSession session;
  world::FaultSchedule schedule;
  std::vector<std::unique_ptr<controller::Controller>> controllers;  // null: dead
  std::vector<Command> commands;  // this tick's, one slot per robot (kept: their message buffers are reused)
  std::vector<char> stepped;      // 1: commands[id] is this tick's
  std::vector<std::string> errors;  // this tick's: what robot id's controller threw (empty: nothing)
  // One perception copy per worker: a controller steps on its robot's perception copied into its worker's
  // buffers, which stay in that core's cache from robot to robot (World::copy_perception says why).
  struct alignas(64) WorkerCopy {
    world::World::PerceptionCopy copy;
  };
  std::vector<WorkerCopy> copies;
};

Harness::Harness(const world::Scenario& scenario, HarnessOptions options)
    : impl_(std::make_unique<Impl>(scenario, std::move(options))) {}

Harness::~Harness() = default;

void Harness::step() {
  impl_->step();
}

void Harness::run(const std::function<bool(const Harness&)>& stop) {
  const Tick max_ticks = impl_->scenario.max_ticks;
  while (!world::run_complete(impl_->session, impl_->world.tick(), max_ticks)) {
    step();
    if (stop && stop(*this)) break;
  }
}

void Harness::kill(RobotId id) {
  impl_->kill(id);
}
void Harness::revive(RobotId id) {
  impl_->revive(id);
}

void Harness::set_controller(RobotId id, std::unique_ptr<controller::Controller> controller) {
  impl_->check_id(id);
  impl_->controllers[id] = std::move(controller);
}

const world::World& Harness::world() const {
  return impl_->world;
}
world::World& Harness::world() {
  return impl_->world;
}
const world::Metrics& Harness::metrics() const {
  return impl_->session.metrics();
}

const world::RunSession& Harness::session() const {
  return impl_->session;
}

const controller::Controller& Harness::controller(RobotId id) const {
  impl_->check_id(id);
  if (!impl_->controllers[id]) {
    throw std::logic_error("harness: robot " + std::to_string(id) + " is dead (no controller)");
  }
  return *impl_->controllers[id];
}

std::string Harness::finish(double wall_seconds, std::optional<world::EndReason> reason) {
  if (reason) impl_->session.set_end_reason(*reason);
  return impl_->session.finish(wall_seconds);
}

std::string Harness::summary_written() const {
  return impl_->session.summary_written();
}

}  // namespace swarmform::harness
