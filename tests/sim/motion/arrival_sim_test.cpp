// Issue 17's motion rows, each reproduced in-process with a deadline and judged by the arrival rule
// from the truth (sim_checks.hpp, ArrivalJudge): the live shape at rest with shape error <= 0.1 grid units
// and its centroid within the goal radius. The figures are printed for robot_agent/README.md.
#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "common/shape.hpp"
#include "tests/sim/motion/preformed.hpp"
#include "tests/sim/motion/sim_checks.hpp"
#include "world_server/harness/harness.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::sim_motion {
namespace {

std::string repo(const std::string& rel) {
  return std::string(SWARMFORM_REPO_DIR) + "/" + rel;
}

struct Outcome {
  std::optional<Tick> motion_start;
  std::optional<Tick> arrived;
  double error = 0.0, to_goal = 0.0;
  std::size_t live = 0;
};

Outcome run_to_arrival(const world::Scenario& scenario) {
  harness::Harness h(scenario);
  ArrivalJudge judge(scenario.mission);
  Outcome o;
  while (h.world().tick() < scenario.max_ticks) {
    h.step();
    const auto& robots = h.world().robots();
    if (!o.motion_start) {
      for (const auto& r : robots) {
        if (r.alive && r.telemetry.state == static_cast<std::int32_t>(RobotState::Motion))
          o.motion_start = h.world().tick();
      }
    }
    if (judge.observe(h.world().tick(), robots)) break;
  }
  o.arrived = judge.arrived();
  o.error = judge.error();
  o.to_goal = judge.to_goal();
  for (const auto& r : h.world().robots()) o.live += r.alive ? 1 : 0;
  return o;
}

void print(const char* what, const Outcome& o) {
  std::printf("%s: motion %ld arrived %ld (error %.3f, centroid %.2f m from the goal, %zu live)\n", what,
              o.motion_start ? static_cast<long>(*o.motion_start) : -1L,
              o.arrived ? static_cast<long>(*o.arrived) : -1L, o.error, o.to_goal, o.live);
}

// One follower dies beside the box: its subtree was pinned against the box (turning on the spot) and the
// leader went on without it. Now the pinned robots follow the box's boundary and the leader slows for them.
TEST(MotionArrival, FollowerKilledBesideTheBoxLeavesNobodyBehind) {
  world::ScenarioOverrides o;
  o.kills.push_back({2, 1500});
  o.max_ticks = 7000;
  const auto scenario = world::load_scenario(repo("scenarios/paper.yaml"), o);
  const auto out = run_to_arrival(scenario);
  print("kill 2@1500", out);
  ASSERT_TRUE(out.arrived.has_value()) << "not arrived by tick 7000: error " << out.error << ", centroid "
                                       << out.to_goal << " m from the goal";
}

// The paper's run: arrival by the rule, and the motion's pace (the leader cruises at the limit).
TEST(MotionArrival, PaperRunArrivesAtPace) {
  const auto scenario = world::load_scenario(repo("scenarios/paper.yaml"));
  const auto out = run_to_arrival(scenario);
  print("paper", out);
  ASSERT_TRUE(out.arrived.has_value());
  ASSERT_TRUE(out.motion_start.has_value());
  // The straight-line minimum from motion start is ~1,120 ticks; at 0.6 of the limit and with the strain rule
  // holding the leader at 0.02 m/s past the box it took ~2,840.
  EXPECT_LE(*out.arrived - *out.motion_start, 2100u);
}

// A 2 x 8 block (8 wide across the path) whose leader's line (its place's path to where the goal puts it)
// runs into the paper's box: the leader was held at the box for good (an obstacle on the leader's line is a
// local minimum of eq. 3 + eq. 6), its block standing still behind it. Preformed (preformed.hpp), so that the
// motion alone is judged; the parameter is the leader's y (4.0: the box's front face; 1.2: its lower corner).
Outcome run_preformed(const world::Scenario& scenario, Vec2 origin) {
  PreformedRun run(scenario, origin);
  ArrivalJudge judge(scenario.mission);
  Outcome o;
  o.motion_start = 40;  // ready_timeout from tick 0
  run.run(scenario.max_ticks,
          [&](const PreformedRun& r) { return judge.observe(r.world.tick(), r.world.robots()); });
  o.arrived = judge.arrived();
  o.error = judge.error();
  o.to_goal = judge.to_goal();
  for (const auto& r : run.world.robots()) o.live += r.alive ? 1 : 0;
  return o;
}

class MotionBlockAtTheBox : public testing::TestWithParam<double> {};

TEST_P(MotionBlockAtTheBox, LeaderHeldAtTheBoxGetsRoundAndTheBlockArrives) {
  auto s = world::load_scenario(repo("scenarios/paper.yaml"));
  s.mission.shape = load_shape_file(repo("tests/sim/motion/fixtures/block_2x8.txt"));
  s.max_ticks = 7000;
  // Label 0 (the leader: the front-most boundary robot, smallest id) at (0, y); the box spans y 1.6-4.1.
  const Vec2 origin{0.0, GetParam()};
  const auto scenario = preformed_scenario(s, origin);
  const auto out = run_preformed(scenario, origin);
  print(("block, leader at y " + std::to_string(GetParam())).c_str(), out);
  ASSERT_TRUE(out.arrived.has_value()) << "not arrived by tick 7000: error " << out.error << ", centroid "
                                       << out.to_goal << " m from the goal";
}

INSTANTIATE_TEST_SUITE_P(LeaderY, MotionBlockAtTheBox, testing::Values(4.0, 1.2));

// The large box dead ahead of the leader (tests/sim/motion/fixtures/dead_ahead.yaml), the whole run: the
// leader slid along the box's face at 0.6 of the limit, turning on the spot for long stretches (arrived at
// 5448); now it follows the box's boundary at the limit (3889).
TEST(MotionArrival, BoxDeadAheadOfTheLeader) {
  world::ScenarioOverrides o;
  o.max_ticks = 4500;
  const auto scenario = world::load_scenario(repo("tests/sim/motion/fixtures/dead_ahead.yaml"), o);
  const auto out = run_to_arrival(scenario);
  print("dead ahead", out);
  ASSERT_TRUE(out.arrived.has_value()) << "not arrived by tick " << scenario.max_ticks << ": error "
                                       << out.error << ", centroid " << out.to_goal << " m from the goal";
}

}  // namespace
}  // namespace swarmform::sim_motion
