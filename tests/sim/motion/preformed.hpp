// A test rig for the motion phases alone: the robots start at their places, already holding their labels
// (label = id), and enter Ready at tick 0, skipping the shape formation. The controller mirrors the paper
// controller's plumbing (neighbour table, stigmergy, message, drive) around motion::PaperMotion, and the run
// loop mirrors the in-process harness (kills -> controllers -> world -> record). Used by the failure tests,
// which need many short runs; the paper, corridor and tree tests run the real controller in the harness.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/motion_phase.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/shape_table.hpp"
#include "robot_agent/controller/stigmergy.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::sim_motion {

// `scenario` with one robot per label standing on its place (label 0 at `origin`), facing the common heading.
world::Scenario preformed_scenario(world::Scenario scenario, Vec2 origin);

class PreformedController final : public controller::Controller {
 public:
  explicit PreformedController(Vec2 origin) : origin_(origin) {}
  void init(const Mission& mission, RobotId self) override;
  Command step(const Perception& perception) override;
  void reset() override { init(mission_, self_); }
  const controller::motion::PaperMotion& motion() const { return *motion_; }

 private:
  Vec2 origin_;
  Mission mission_;
  RobotId self_ = 0;
  controller::FormationParams params_;
  controller::ShapeTable table_;
  std::unique_ptr<controller::motion::PaperMotion> motion_;
  controller::NeighbourTable neighbours_;
  controller::Stigmergy stigmergy_;
  std::map<RobotId, int> members_;
  bool ready_ = false;
  RobotState state_ = RobotState::Ready;
};

// The world with preformed controllers; `observe` runs after every tick and may stop the run (true).
struct PreformedRun {
  explicit PreformedRun(const world::Scenario& scenario, Vec2 origin, const std::string& run_dir = "");
  void step();
  void run(Tick max_ticks, const std::function<bool(const PreformedRun&)>& stop = {});
  void kill(RobotId id);

  world::World world;
  world::RunSession session;
  std::vector<std::unique_ptr<PreformedController>> controllers;  // null: dead
};

}  // namespace swarmform::sim_motion
