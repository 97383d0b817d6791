// The motion targets (scenarios/README.md, Figures), each reproduced in-process with a deadline and judged by
// the world's arrival rule from the truth (sim_checks.hpp, ArrivalJudge): the live shape at rest with shape
// error <= 0.1 grid units and its centroid within the goal radius. The figures are printed for
// robot_agent/README.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "common/shape.hpp"
#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "tests/sim/motion/preformed.hpp"
#include "tests/sim/motion/sim_checks.hpp"
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
  double minimum = 0.0;  // ticks: at motion start, (centroid's distance to the goal - radius) at the limit
  double peak = 0.0;     // largest shape error from motion start on
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
    const bool arrived = judge.observe(h.world().tick(), robots);
    if (o.motion_start) {
      if (o.minimum == 0.0) {
        o.minimum = std::max(0.0, judge.to_goal() - scenario.mission.goal_radius) /
                    (scenario.mission.max_speed / scenario.tick_rate);
      }
      o.peak = std::max(o.peak, judge.error());
    }
    if (arrived) break;
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
  const auto scenario =
      world::load_scenario(repo("scenarios/paper.yaml"), o, swarmform::controller::builtin_registry());
  const auto out = run_to_arrival(scenario);
  print("kill 2@1500", out);
  ASSERT_TRUE(out.arrived.has_value()) << "not arrived by tick 7000: error " << out.error << ", centroid "
                                       << out.to_goal << " m from the goal";
}

// The paper's run: arrival by the rule, and the motion's pace (the leader cruises at the limit).
TEST(MotionArrival, PaperRunArrivesAtPace) {
  const auto scenario =
      world::load_scenario(repo("scenarios/paper.yaml"), {}, swarmform::controller::builtin_registry());
  const auto out = run_to_arrival(scenario);
  print("paper", out);
  ASSERT_TRUE(out.arrived.has_value());
  ASSERT_TRUE(out.motion_start.has_value());
  // The target is 1.25 x the straight-line minimum (~1,120 ticks: the centroid's distance to the goal's
  // radius at the limit) with peak distortion <= 0.5. With the leader carrying the shape on to the goal's
  // centre it took 1.27 x; it stops inside the radius now (robot_agent/README.md, "Arrival").
  const double ratio = static_cast<double>(*out.arrived - *out.motion_start) / out.minimum;
  std::printf("paper: %.0f ticks minimum, %.3f x, peak distortion %.3f\n", out.minimum, ratio, out.peak);
  EXPECT_LE(ratio, 1.25);
  EXPECT_LE(out.peak, 0.5);
}

// Three robots cut off inside the U (u_trap.yaml, seed 10) reach the goal first and arrive alone at their own
// targets; the leader's piece stops inside the goal's radius, short of where the goal puts the centroid. They
// hear their parent again there and must follow it: standing at their own targets left them ~0.2 m off the
// shape, which was never judged arrived (25,000 ticks).
TEST(MotionArrival, APieceThatArrivedAloneFollowsAgainWhenItHearsItsParent) {
  world::ScenarioOverrides o;
  o.seed = 10;
  o.max_ticks = 12000;
  const auto scenario =
      world::load_scenario(repo("scenarios/u_trap.yaml"), o, swarmform::controller::builtin_registry());
  const auto out = run_to_arrival(scenario);
  print("u_trap seed 10", out);
  ASSERT_TRUE(out.arrived.has_value()) << "not arrived by tick 12000: error " << out.error << ", centroid "
                                       << out.to_goal << " m from the goal";
}

// The leader stops once the shape's centroid is inside the goal's radius by its margins, whatever the radius:
// a small goal (under the margins: it makes for the centre) and a large one (it stops well short of the
// centre), both judged arrived by the world's rule with the centroid inside the radius.
class MotionGoalRadius : public testing::TestWithParam<double> {};

TEST_P(MotionGoalRadius, ShapeStopsInsideTheGoalRadius) {
  auto s =
      world::load_scenario(repo("scenarios/open_field.yaml"), {}, swarmform::controller::builtin_registry());
  s.mission.goal_radius = GetParam();
  s.max_ticks = 3000;
  const auto out = run_to_arrival(s);
  print(("goal radius " + std::to_string(GetParam())).c_str(), out);
  ASSERT_TRUE(out.arrived.has_value()) << "not arrived by tick 3000: error " << out.error << ", centroid "
                                       << out.to_goal << " m from the goal";
  EXPECT_LT(out.to_goal, GetParam());
  // Not carried on to the centre when the radius leaves room: the trip ends at the radius's margins.
  if (GetParam() >= 1.0) {
    EXPECT_GT(out.to_goal, 0.5 * GetParam());
  }
}

INSTANTIATE_TEST_SUITE_P(Radius, MotionGoalRadius, testing::Values(0.12, 0.5, 2.0));

// The goal moves after the shape arrived (a world event, world_server/world/goal_events.hpp): every robot is
// told in its perception, the arrived leader resumes (its target moved) and the shape arrives at the new
// goal, judged by the same rule. Without the perception's goal the shape stays at the old goal for good.
TEST(MotionGoalMoves, AShapeThatArrivedSetsOffForTheGoalWhereItMovedAndArrivesThere) {
  auto s =
      world::load_scenario(repo("scenarios/open_field.yaml"), {}, swarmform::controller::builtin_registry());
  s.max_ticks = 3000;
  const auto first = run_to_arrival(s);
  ASSERT_TRUE(first.arrived.has_value());
  const Tick move = *first.arrived + 50;
  const Goal moved{{4.0, 3.0}, 0.5};  // 6.7 m back and aside, inside the walls
  s.goal_events = {{move, moved, true, 0}};
  s.max_ticks = move + 3000;
  Mission at_the_new_goal = s.mission;
  at_the_new_goal.goal = moved.at;
  harness::Harness h(s);
  ArrivalJudge judge(at_the_new_goal);
  while (h.world().tick() < s.max_ticks) {
    h.step();
    if (h.world().tick() <= move) continue;
    if (judge.observe(h.world().tick(), h.world().robots())) break;
  }
  ASSERT_TRUE(judge.arrived().has_value())
      << "not arrived at the moved goal by tick " << s.max_ticks << ": error " << judge.error()
      << ", centroid " << judge.to_goal() << " m from it";
  std::printf(
      "goal moved at tick %llu (arrived at the first at %llu): arrived at the new goal at tick %llu\n",
      static_cast<unsigned long long>(move), static_cast<unsigned long long>(*first.arrived),
      static_cast<unsigned long long>(*judge.arrived()));
}

// A goal moved to where the shape, as it stood, does not fit (scenarios/goal_moves.yaml with the V, seed 1, a
// clean radio): at tick 1800 the goal jumps back and aside to (5, 3.5), 2.5 m below the upper wall, and the V
// carried there broadside (its arms 4 m either side of its old way, +x) has its upper arm's last place
// 0.7-2.3 m beyond the wall wherever its centroid stands in the goal's radius: that arm's robots stayed
// pinned at the wall and the shape was never formed there (every seed, with any radio:
// docs/design-notes/goal-moves.md). A place found beyond a surface turns the shape (motion_phase.cpp,
// shape_turn.hpp) until it fits. Judged by the world's rule at the goal as it stands after the
// move.
TEST(MotionGoalMoves, AVSentBesideAWallTurnsOffItAndArrivesThere) {
  world::ScenarioOverrides over;
  over.shape_file = repo("shapes/v.txt");
  over.seed = 1;
  auto s = world::load_scenario(repo("scenarios/goal_moves.yaml"), over,
                                swarmform::controller::builtin_registry());
  ASSERT_EQ(s.goal_events.size(), 1u);
  const world::GoalEvent move = s.goal_events.front();
  Mission at_the_new_goal = s.mission;
  at_the_new_goal.goal = move.goal.at;
  at_the_new_goal.goal_radius = move.goal.radius;
  harness::Harness h(s);
  ArrivalJudge judge(at_the_new_goal);
  while (h.world().tick() < s.max_ticks) {
    h.step();
    if (h.world().tick() <= move.tick) continue;
    if (judge.observe(h.world().tick(), h.world().robots())) break;
  }
  std::printf(
      "V, goal moved at tick %llu: arrived at the new goal at %ld (error %.3f, centroid %.2f m off)\n",
      static_cast<unsigned long long>(move.tick), judge.arrived() ? static_cast<long>(*judge.arrived()) : -1L,
      judge.error(), judge.to_goal());
  ASSERT_TRUE(judge.arrived().has_value())
      << "not arrived at the moved goal by tick " << s.max_ticks << ": error " << judge.error()
      << ", centroid " << judge.to_goal() << " m from it";
}

// A goal moved past a wall the shape has still to go round: the untuned doorway layout
// (scenarios/untuned/doorway_clean.yaml: a wall with one doorway between the start and the goal), its goal
// moved 5 m aside at tick 1500 while the triangle still stands before the wall, as `scripts/sweep-untuned
// --goal-move 1500:0,-5,0.8` writes it. The front robots pinned at the wall, their places beyond it, turned
// the shape back and forth on the way (5 turns, arrived at 9406; in the hexagon's run robots touched at the
// wall). The shape fits at the new goal: it is to be gone round the wall, never turned (motion_phase.cpp,
// shape_turn.hpp: a turn starts only at the goal, for a place a turn can bring in), and it arrives.
TEST(MotionGoalMoves, AGoalMovedPastAWallStillAheadIsReachedRoundItWithoutATurn) {
  world::ScenarioOverrides over;
  over.shape_file = repo("shapes/triangle.txt");
  over.seed = 1;
  over.max_ticks = 9000;
  auto s = world::load_scenario(repo("scenarios/untuned/doorway_clean.yaml"), over,
                                swarmform::controller::builtin_registry());
  ASSERT_TRUE(s.goal_events.empty());
  world::GoalEvent move;
  move.tick = 1500;
  move.goal = {{s.mission.goal.x, s.mission.goal.y - 5.0}, 0.8};
  move.radius_given = true;
  s.goal_events.push_back(move);
  Mission at_the_new_goal = s.mission;
  at_the_new_goal.goal = move.goal.at;
  at_the_new_goal.goal_radius = move.goal.radius;
  harness::Harness h(s);
  ArrivalJudge judge(at_the_new_goal);
  std::vector<std::string> turns;
  unsigned contacts = 0;
  while (h.world().tick() < s.max_ticks) {
    h.step();
    contacts += h.world().last_contacts().robot_robot;
    for (const auto& r : h.world().robots()) {
      for (const auto& e : r.telemetry.events) {
        if (e.rfind("shape_turning", 0) == 0)
          turns.push_back("tick " + std::to_string(h.world().tick()) + " robot " + std::to_string(r.id) +
                          ": " + e);
      }
    }
    if (h.world().tick() > move.tick && judge.observe(h.world().tick(), h.world().robots())) break;
  }
  std::printf(
      "triangle, goal moved past the wall at tick %llu: arrived at %ld, %zu turn events, %u contacts\n",
      static_cast<unsigned long long>(move.tick), judge.arrived() ? static_cast<long>(*judge.arrived()) : -1L,
      turns.size(), contacts);
  EXPECT_TRUE(turns.empty()) << "turned on the way: " << turns.front() << " (" << turns.size() << " in all)";
  EXPECT_EQ(contacts, 0u) << "robots touched";
  ASSERT_TRUE(judge.arrived().has_value())
      << "not arrived at the moved goal by tick " << s.max_ticks << ": error " << judge.error()
      << ", centroid " << judge.to_goal() << " m from it";
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
  auto s = world::load_scenario(repo("scenarios/paper.yaml"), {}, swarmform::controller::builtin_registry());
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
  const auto scenario = world::load_scenario(repo("tests/sim/motion/fixtures/dead_ahead.yaml"), o,
                                             swarmform::controller::builtin_registry());
  const auto out = run_to_arrival(scenario);
  print("dead ahead", out);
  ASSERT_TRUE(out.arrived.has_value()) << "not arrived by tick " << scenario.max_ticks << ": error "
                                       << out.error << ", centroid " << out.to_goal << " m from the goal";
}

// Deaths split the line into two pieces that cannot hear each other (robots 2 and 3 die: 3 m, the radio
// range, between the pieces). The piece cut off from the leader takes its own places to where the goal puts
// them, and the line is whole again at the goal (robot_agent/README.md, "A piece that cannot hear its
// parent").
TEST(MotionArrival, PiecesSplitByDeathsMeetAgainAtTheGoal) {
  auto s =
      world::load_scenario(repo("scenarios/open_field.yaml"), {}, swarmform::controller::builtin_registry());
  s.mission.shape = load_shape_file(repo("shapes/line.txt"));
  s.max_ticks = 3000;
  s.comm_range = 2.5;
  s.mission.comm_range = 2.5;
  const auto scenario = preformed_scenario(s, {0.0, 2.5});
  PreformedRun run(scenario, {0.0, 2.5});
  ArrivalJudge judge(scenario.mission);
  run.run(100);
  run.kill(1);
  run.kill(3);
  run.run(scenario.max_ticks,
          [&](const PreformedRun& r) { return judge.observe(r.world.tick(), r.world.robots()); });
  std::printf("split line: arrived %ld (error %.3f, centroid %.2f m from the goal)\n",
              judge.arrived() ? static_cast<long>(*judge.arrived()) : -1L, judge.error(), judge.to_goal());
  ASSERT_TRUE(judge.arrived().has_value()) << "not arrived by tick 3000: error " << judge.error()
                                           << ", centroid " << judge.to_goal() << " m from the goal";
}

}  // namespace
}  // namespace swarmform::sim_motion
