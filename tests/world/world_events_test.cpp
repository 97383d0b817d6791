// World events (world_server/world/world_events.hpp, goal_events.hpp): the scenario's `events:` checked at
// file:line, the world's obstacles, sensors and physics changed at the events' ticks, and every robot's
// perception telling the goal as it stands from a goal move's tick on.
#include "world_server/world/world_events.hpp"

#include <gtest/gtest.h>

#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/goal_events.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using testing::box;
using testing::open_scenario;

const std::string kOrigin = std::string(SWARMFORM_REPO_DIR) + "/scenarios/inline-test.yaml";

// A scenario of one robot with two named obstacles, then `events` (YAML lines) from line 5 on.
std::string with_events(const std::string& events, const std::string& gate_present = "true") {
  return "shape: triangle.txt\nmax_ticks: 100\n"
         "obstacles: [{type: box, name: gate, centre: [3, 0], size: [0.2, 1], present: " +
         gate_present +
         "}, {type: cylinder, name: post, centre: [-3, 0], radius: 0.2}]\n"
         "events:\n" +
         events;
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

TEST(WorldEvents, AreReadSortedByTickAndEachMistakeIsNamedAtItsLine) {
  const Scenario s =
      parse(with_events("  - {tick: 40, obstacle: gate, do: appear}\n"
                        "  - {tick: 20, obstacle: post, do: move, centre: [-2, 1]}\n",
                        "false"));
  ASSERT_EQ(s.world_events.size(), 2u);
  EXPECT_EQ(s.world_events[0].tick, 20u);
  EXPECT_EQ(s.world_events[0].obstacle, 1u);
  EXPECT_EQ(s.world_events[0].action, WorldEvent::Action::Move);
  EXPECT_EQ(s.world_events[0].centre.x, -2.0);
  EXPECT_EQ(s.world_events[1].action, WorldEvent::Action::Appear);
  EXPECT_FALSE(s.obstacles[0].present);

  expect_rejected(with_events("  - {tick: 10, obstacle: door, do: appear}\n"), 5, "no obstacle named 'door'");
  expect_rejected(with_events("  - {tick: 10, obstacle: gate, do: appear}\n"), 5, "'gate' is already there");
  expect_rejected(with_events("  - {tick: 10, obstacle: gate, do: disappear}\n", "false"), 5,
                  "'gate' is not there at tick 10");
  expect_rejected(with_events("  - {tick: 10, obstacle: gate, do: move}\n"), 5, "missing 'centre'");
  expect_rejected(with_events("  - {tick: 10, obstacle: post, do: move, centre: [0, 0], yaw: 1}\n"), 5,
                  "a cylinder has no yaw");
  expect_rejected(with_events("  - {tick: 101, obstacle: gate, do: disappear}\n"), 5, "events[0].tick");
  expect_rejected(with_events("  - {tick: 0, obstacle: gate, do: disappear}\n"), 5, "events[0].tick");
  expect_rejected(with_events("  - {tick: 10, obstacle: gate, do: vanish}\n"), 5,
                  "expected appear, disappear");
  expect_rejected(with_events("  - {tick: 10, obstacle: gate, do: disappear, centre: [1, 1]}\n"), 5,
                  "centre");
  expect_rejected(with_events("  - {tick: 10, obstacle: gate, do: disappear}\n"
                              "  - {tick: 10, obstacle: gate, do: appear}\n"),
                  6, "a second event for 'gate' at tick 10");
}

// One robot at the origin facing +x (its front sonar on the x axis), a box 1 m ahead that starts absent.
Scenario gate_ahead() {
  Scenario s = open_scenario({Pose2D{0, 0, 0}});
  Obstacle gate = box(1.0, 0.0, 0.2, 1.0);
  gate.name = "gate";
  gate.present = false;
  s.obstacles.push_back(gate);
  s.world_events = {{2, 0, WorldEvent::Action::Appear, {}, {}},
                    {4, 0, WorldEvent::Action::Move, {0.6, 0.0}, {}},
                    {6, 0, WorldEvent::Action::Disappear, {}, {}}};
  return s;
}

double front_sonar(const World& w) {
  return w.perception(0).ultrasonic[2];  // kUltrasonicAngles[2] = 0: straight ahead
}

TEST(WorldEvents, TheSensorsSeeAnObstacleFromTheTickItAppearsWhereItStandsAndNotAfterItGoes) {
  World w(gate_ahead());
  const double far = kUltrasonicMaxRange;
  EXPECT_DOUBLE_EQ(front_sonar(w), far);  // tick 0: absent
  w.step();
  EXPECT_DOUBLE_EQ(front_sonar(w), far);  // tick 1
  w.step();                               // tick 2: it appears, its near face 0.9 m from the centre
  EXPECT_TRUE(w.obstacles()[0].present);
  EXPECT_NEAR(front_sonar(w), 0.9 - kRobotRadius, 0.01);
  w.step();
  w.step();  // tick 4: moved to 0.6 m
  EXPECT_EQ(w.obstacles()[0].centre.x, 0.6);
  EXPECT_NEAR(front_sonar(w), 0.5 - kRobotRadius, 0.01);
  w.step();
  w.step();  // tick 6: gone
  EXPECT_FALSE(w.obstacles()[0].present);
  EXPECT_DOUBLE_EQ(front_sonar(w), far);
}

// Driving at the box's place: stopped by it while it stands there, through its place once it is gone.
TEST(WorldEvents, ThePhysicsStopsARobotAtAnObstacleThatAppearedAndLetsItThroughOnceGone) {
  Scenario s = gate_ahead();
  s.world_events = {{2, 0, WorldEvent::Action::Appear, {}, {}},
                    {150, 0, WorldEvent::Action::Disappear, {}, {}}};
  World w(s);
  Command go;
  go.left_speed = go.right_speed = 0.1;
  std::uint32_t contacts = 0;
  for (int t = 0; t < 140; ++t) {
    w.apply_command(0, go);
    w.step();
    contacts += w.last_contacts().robot_obstacle;
  }
  EXPECT_GE(contacts, 1u);
  EXPECT_LT(w.robots()[0].pose.x, 0.9 - kRobotRadius + 0.01);  // held at the box's face
  for (int t = 140; t < 260; ++t) {
    w.apply_command(0, go);
    w.step();
  }
  EXPECT_GT(w.robots()[0].pose.x, 1.2);  // past where the box stood
}

TEST(WorldEvents, TwoWorldsWithTheSameEventsStayBitIdentical) {
  Scenario s = gate_ahead();
  s.robots.push_back(Pose2D{0.0, 0.5, 0.3});
  World a(s), b(s);
  Command go;
  go.left_speed = 0.1;
  go.right_speed = 0.08;
  for (int t = 0; t < 80; ++t) {
    for (RobotId id = 0; id < 2; ++id) {
      a.apply_command(id, go);
      b.apply_command(id, go);
    }
    a.step();
    b.step();
  }
  for (RobotId id = 0; id < 2; ++id) {
    EXPECT_EQ(a.robots()[id].pose.x, b.robots()[id].pose.x);
    EXPECT_EQ(a.robots()[id].pose.y, b.robots()[id].pose.y);
    EXPECT_EQ(a.perception(id).ultrasonic, b.perception(id).ultrasonic);
  }
}

// The paper on a triangle, goal (10, 0) r 0.5 by default, then goal moves (YAML lines) from line 4 on.
std::string with_moves(const std::string& events, const std::string& head = "shape: triangle.txt\n") {
  return head + "max_ticks: 100\nevents:\n" + events;
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
  Scenario s = open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}});
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
