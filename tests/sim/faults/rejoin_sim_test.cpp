// A robot killed and restarted with a fresh controller (the restart fault; a stalled agent taken for dead
// comes back the same way, docs/faults.md) rejoins the paper's shape wherever the swarm is: the run arrives,
// every live robot placed. Each case failed before robot_agent/README.md's "A robot that comes back" rules:
// - back before its neighbours freed its label: the label's entry still named it, its neighbours heard it
// alive
//   and never freed the label, and the barrier waited for ever (not_formed);
// - back after the barrier had abandoned its label: the reserve it became took only labels of dead members,
// so
//   the shape arrived with a hole and the world, counting nine live robots for nine places, never saw it
//   arrive.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "tests/sim/measured.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::harness {
namespace {

const std::string kPaper = std::string(SWARMFORM_REPO_DIR) + "/scenarios/paper.yaml";
constexpr Tick kMaxTicks = 6000;  // the paper run arrives at ~2000; with a rejoin by ~2700

struct RejoinRun {
  bool arrived = false;
  std::vector<std::string> events_of_robot;  // the rejoined robot's controller events
};

RejoinRun run_paper_with(const std::vector<std::string>& faults, RobotId robot) {
  world::ScenarioOverrides ov;
  ov.faults = faults;
  ov.max_ticks = kMaxTicks;
  Harness h(world::load_scenario(kPaper, ov, controller::builtin_registry()));
  RejoinRun out;
  while (h.world().tick() < kMaxTicks && !measured(h).goal_tick) {
    h.step();
    for (const auto& e : h.world().robots()[robot].telemetry.events) out.events_of_robot.push_back(e);
  }
  out.arrived = measured(h).goal_tick.has_value();
  return out;
}

bool has_event(const RejoinRun& r, const std::string& text) {
  for (const auto& e : r.events_of_robot) {
    if (e.find(text) != std::string::npos) return true;
  }
  return false;
}

// Robot 5 (the seed, label 0) dies at its place at tick 400 and is back at 410, before label_timeout.
TEST(RejoinInProcess, ARobotBackBeforeItsLabelWasFreedFreesItItselfAndTheRunArrives) {
  for (const RobotId id : {5u, 2u}) {
    const std::string k = std::to_string(id);
    const RejoinRun r = run_paper_with({"kill:" + k + "@400", "restart:" + k + "@410"}, id);
    EXPECT_TRUE(r.arrived) << "robot " << id;
    EXPECT_TRUE(has_event(r, "not mine")) << "robot " << id << " did not free its earlier run's label";
  }
}

// Robot 5 dies at 400 and is back at 600: its label was freed (~441) and abandoned at the barrier (~545), the
// shape is moving. The reserve it becomes takes the abandoned label.
TEST(RejoinInProcess, ARobotBackAfterItsLabelWasAbandonedTakesItAsAReserveAndTheRunArrives) {
  for (const RobotId id : {5u, 7u}) {
    const std::string k = std::to_string(id);
    const RejoinRun r = run_paper_with({"kill:" + k + "@400", "restart:" + k + "@600"}, id);
    EXPECT_TRUE(r.arrived) << "robot " << id;
    EXPECT_TRUE(has_event(r, "reserve_takes")) << "robot " << id << " never took a vacancy";
  }
}

}  // namespace
}  // namespace swarmform::harness
