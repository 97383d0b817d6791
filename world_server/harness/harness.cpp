// The in-process harness: the tick order of the DDS world_server without DDS. One tick:
//   scheduled kills due now -> every live robot's controller steps on its perception -> the commands go to
//   the world (verdicts other than Ok are recorded) -> world.step() -> the session records the new tick.
// The controllers run one after the other in id order, so a run is deterministic for a scenario and seed.
#include "world_server/harness/harness.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "world_server/run/run_end.hpp"

namespace swarmform::harness {

struct Harness::Impl {
  Impl(const world::Scenario& s, HarnessOptions o)
      : scenario(s),
        options(std::move(o)),
        world(scenario),
        session(world, {options.run_dir, "in-process", options.fragment_range}) {
    controllers.reserve(scenario.robots.size());
    for (RobotId id = 0; id < scenario.robots.size(); ++id) {
      controllers.push_back(controller::make_controller(scenario.mission, id));
    }
    kills = scenario.kills;
    std::stable_sort(kills.begin(), kills.end(),
                     [](const world::Kill& a, const world::Kill& b) { return a.tick < b.tick; });
  }

  void check_id(RobotId id) const {
    if (id >= controllers.size()) {
      throw std::out_of_range("harness: no robot " + std::to_string(id) + " (the scenario has " +
                              std::to_string(controllers.size()) + ")");
    }
  }

  void kill(RobotId id) {
    check_id(id);
    if (!world.alive(id)) return;
    world.kill(id);
    controllers[id].reset();
    session.record_death(id);
  }

  void revive(RobotId id) {
    check_id(id);
    if (!world.alive(id)) world.revive(id);  // a live robot only gets the fresh controller (agent restart)
    controllers[id] = controller::make_controller(scenario.mission, id);
    session.record_rejoin(id);
  }

  void step() {
    while (next_kill < kills.size() && kills[next_kill].tick <= world.tick()) {
      kill(kills[next_kill].id);
      ++next_kill;
    }
    for (RobotId id = 0; id < controllers.size(); ++id) {
      if (!controllers[id] || !world.alive(id)) continue;
      const Command command = controllers[id]->step(world.perception(id));
      const auto verdict = world.apply_command(id, command);
      if (verdict != world::CommandVerdict::Ok) session.record_command_verdict(id, verdict);
    }
    world.step();
    session.record_tick();
  }

  const world::Scenario scenario;  // a copy: the world and the controllers refer to it for the whole run
  HarnessOptions options;
  world::World world;
  world::RunSession session;
  std::vector<std::unique_ptr<controller::Controller>> controllers;  // null: dead
  std::vector<world::Kill> kills;                                    // by tick
  std::size_t next_kill = 0;
};

Harness::Harness(const world::Scenario& scenario, HarnessOptions options)
    : impl_(std::make_unique<Impl>(scenario, std::move(options))) {}

Harness::~Harness() = default;

void Harness::step() {
  impl_->step();
}

void Harness::run(const std::function<bool(const Harness&)>& stop) {
  const Tick max_ticks = impl_->scenario.max_ticks;
  while (!world::run_complete(metrics(), impl_->world.tick(), max_ticks)) {
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

const world::World& Harness::world() const {
  return impl_->world;
}
world::World& Harness::world() {
  return impl_->world;
}
const world::Metrics& Harness::metrics() const {
  return impl_->session.metrics();
}

const controller::Controller& Harness::controller(RobotId id) const {
  impl_->check_id(id);
  if (!impl_->controllers[id]) {
    throw std::logic_error("harness: robot " + std::to_string(id) + " is dead (no controller)");
  }
  return *impl_->controllers[id];
}

std::string Harness::finish(double wall_seconds) {
  return impl_->session.finish(wall_seconds);
}

}  // namespace swarmform::harness
