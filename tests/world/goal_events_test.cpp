// Goal moves (world_server/world/goal_events.hpp): the scenario's `events:` items with `goal:` checked at
// file:line, and every robot's perception telling the goal as it stands from the move's tick on.
#include "world_server/world/goal_events.hpp"

#include <gtest/gtest.h>

#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

const std::string kOrigin = std::string(SWARMFORM_REPO_DIR) + "/scenarios/inline-test.yaml";

// The paper on a triangle, goal (10, 0) r 0.5 by default, then `events` (YAML lines) from line 4 on.
std::string with_moves(const std::string& events, const std::string& head = "shape: triangle.txt\n") {
  return head + "max_ticks: 100\nevents:\n" + events;
}

Scenario parse(const std::string& text) {
  return parse_scenario_text(text, kOrigin, {}, swarmform::controller::builtin_registry());
}

void expect_rejected(const std::string& text, int line, const std::string& what) {
  try {
    parse(text);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(GoalEvents, AreReadSortedByTickKeepTheRadiusTheyDoNotGiveAndEachMistakeIsNamedAtItsLine) {
  const Scenario s =
      parse(with_moves("  - {tick: 40, goal: [6, 1]}\n"
                       "  - {tick: 20, goal: [2, -1], radius: 0.8}\n"));
  ASSERT_EQ(s.goal_events.size(), 2u);
  EXPECT_EQ(s.goal_events[0].tick, 20u);
  EXPECT_EQ(s.goal_events[0].goal, (Goal{{2, -1}, 0.8}));
  EXPECT_EQ(s.goal_events[1].goal, (Goal{{6, 1}, 0.8}));  // the radius it had
  EXPECT_EQ(goal_at(s, 19), (Goal{{10, 0}, 0.5}));
  EXPECT_EQ(goal_at(s, 20), (Goal{{2, -1}, 0.8}));
  EXPECT_EQ(goal_at(s, 99), (Goal{{6, 1}, 0.8}));

  expect_rejected(with_moves("  - {tick: 10, goal: [500, 0]}\n"), 4, "outside the arena's walls");
  expect_rejected(with_moves("  - {tick: 10, goal: [1, 1]}\n  - {tick: 10, goal: [2, 1]}\n"), 5,
                  "a second goal move at tick 10");
  expect_rejected(with_moves("  - {tick: 0, goal: [1, 1]}\n"), 4, "events[0].tick");
  expect_rejected(with_moves("  - {tick: 10, goal: [1, 1], radius: 0}\n"), 4, "radius");
  expect_rejected(with_moves("  - {tick: 10, goal: [1, 1], do: move}\n"), 4, "do");
  expect_rejected(with_moves("  - {tick: 10, goal: 3}\n"), 4, "goal");
  expect_rejected(with_moves("  - {tick: 10, goal: [1, 1]}\n", "behaviour: random_walk\n"), 4,
                  "the run has no goal");
}

TEST(GoalEvents, EveryRobotPerceivesTheGoalMovedFromTheTickOfTheMove) {
  Scenario s = testing::open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}});
  s.mission.goal = {5, 0};
  s.mission.goal_radius = 0.5;
  s.goal_events = {{3, Goal{{-4, 2}, 1.5}, true, 0}};
  World w(s);
  for (Tick t = 0; t <= 4; ++t) {
    const Goal want = t < 3 ? Goal{{5, 0}, 0.5} : Goal{{-4, 2}, 1.5};
    for (RobotId id = 0; id < 2; ++id) {
      ASSERT_TRUE(w.perception(id).goal) << "tick " << t;
      EXPECT_EQ(*w.perception(id).goal, want) << "tick " << t << " robot " << id;
    }
    EXPECT_EQ(w.goal(), std::optional<Goal>(want));
    w.step();
  }
  s.mission.has_goal = false;
  s.goal_events.clear();
  EXPECT_FALSE(World(s).perception(0).goal);  // a run without a goal tells none
}

}  // namespace
}  // namespace swarmform::world
