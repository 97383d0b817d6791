// The metrics and the derived events on hand-made truth, tick by tick (no physics needed).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/robot_state.hpp"
#include "world_server/run/comm_graph.hpp"
#include "world_server/run/metrics_tracker.hpp"
#include "world_server/run/run_events.hpp"

namespace swarmform::world {
namespace {

constexpr auto kSearching = static_cast<std::int32_t>(RobotState::Searching);
constexpr auto kMoving = static_cast<std::int32_t>(RobotState::Moving);
constexpr auto kReached = static_cast<std::int32_t>(RobotState::Reached);
constexpr auto kReady = static_cast<std::int32_t>(RobotState::Ready);
constexpr auto kMotion = static_cast<std::int32_t>(RobotState::Motion);

Mission line_mission() {
  Mission m;
  m.shape = ShapeMatrix{1, 3, {0, 1, 2}};
  m.grid_spacing = 1.0;
  m.goal = {5.0, 0.0};
  m.goal_radius = 0.6;
  return m;  // max_speed 0.1 m/s at 10 ticks/s: 0.01 m a tick
}

// Robots that broadcast every tick: a last broadcast beyond any tick the tests reach never ages into silence.
constexpr Tick kSpeaking = Tick{1} << 40;

// Three robots on the line shape with their left end at x0, plus one spare far behind.
std::vector<RobotTruth> line_at(double x0, std::int32_t state) {
  std::vector<RobotTruth> robots(4);
  for (RobotId i = 0; i < 4; ++i) {
    robots[i].id = i;
    robots[i].telemetry.state = state;
    robots[i].telemetry.label = i < 3 ? static_cast<std::int32_t>(i) : -1;
    robots[i].pose = {x0 + i, 0.0, 0.0};
    robots[i].last_broadcast_tick = kSpeaking;
  }
  robots[3].pose = {-20.0, 0.0, 0.0};
  robots[3].telemetry.state = kSearching;
  return robots;
}

TEST(MetricsTracker, FormationMotionGoalAndPath) {
  MetricsTracker tracker(line_mission(), &swarmform::controller::paper_descriptor());
  // In place from tick 0, but at rest only after kRestTicks ticks: formation at tick 10, whatever the
  // robots report (all still Reached).
  Tick t = 0;
  for (; t < kRestTicks; ++t) {
    tracker.observe(t, line_at(0.0, kReached), {});
    EXPECT_FALSE(tracker.metrics().formation_tick) << t;
  }
  tracker.observe(t, line_at(0.0, kReached), {});
  ASSERT_TRUE(tracker.metrics().formation_tick);
  EXPECT_EQ(*tracker.metrics().formation_tick, kRestTicks);
  EXPECT_LT(*tracker.metrics().shape_error_at_formation, 1e-9);
  EXPECT_FALSE(tracker.metrics().peak_distortion);  // not moving yet
  EXPECT_EQ(tracker.metrics().outcome, "formed_not_arrived");

  // Motion from tick 11: 0.1 m a tick along +x to x0 = 3.5 (k = 35, tick 46); the middle robot is 0.3 m off
  // the line on tick 20. Then still.
  ++t;
  const Tick motion_start = t;
  for (int k = 0; k <= 35; ++k, ++t) {
    auto robots = line_at(0.1 * k, kMotion);
    if (t == 20) robots[1].pose.y = 0.3;
    tracker.observe(t, robots, {});
    EXPECT_FALSE(tracker.metrics().goal_tick) << t;  // moving: not at rest
  }
  const Tick stopped = t - 1;  // 46
  for (; t <= stopped + 15; ++t) tracker.observe(t, line_at(3.5, kMotion), {});
  const Metrics& m = tracker.metrics();
  EXPECT_EQ(*m.motion_start_tick, motion_start);
  // The centroid (x0 + 1) was 4 m from the goal at motion start: 3.4 m to the goal disc, 340 ticks at 0.01 m.
  ASSERT_TRUE(m.motion_ticks_minimum);
  EXPECT_NEAR(*m.motion_ticks_minimum, 340.0, 1e-9);
  // Centroid 0.5 m from the goal, within its 0.6 m radius, at rest from tick 46 + 10.
  ASSERT_TRUE(m.goal_tick);
  EXPECT_EQ(*m.goal_tick, stopped + kRestTicks);
  EXPECT_LT(*m.shape_error_at_goal, 1e-9);
  EXPECT_EQ(m.arrived, 3u);
  EXPECT_EQ(m.outcome, "arrived");
  // The bent line: positive, and the peak; one bent tick among the motion ticks (11..56).
  ASSERT_TRUE(m.peak_distortion);
  EXPECT_GT(*m.peak_distortion, 0.05);
  const double motion_ticks = static_cast<double>(*m.goal_tick - motion_start + 1);
  EXPECT_NEAR(*m.mean_distortion, *m.peak_distortion / motion_ticks, 1e-12);
  // Centroid path: 35 steps of 0.1 m, plus the bend's side step there and back (0.1 m each way in y).
  EXPECT_NEAR(m.path_length, 3.5 + 2 * std::hypot(0.1, 0.1) - 0.2, 1e-9);
  EXPECT_EQ(m.distortion.size(), t - kRestTicks);
  tracker.conclude();
  EXPECT_TRUE(m.stuck_robots.empty());  // arrived: nobody is stuck (the spare has not moved for 60 ticks)
}

// The "arrival" row: goal_tick was set with the centroid 1.03 m from the goal (goal radius + the
// shape's radius), when every robot reported Arrived, and for a wrecked line.
TEST(MetricsTracker, ArrivalNeedsTheCentroidInTheGoalRadiusAndTheShapeFormed) {
  {
    MetricsTracker tracker(line_mission(), &swarmform::controller::paper_descriptor());
    // Formed and at rest, centroid 1.03 m short of the goal (x0 + 1 = 3.97), every robot saying Arrived.
    for (Tick t = 0; t < 40; ++t)
      tracker.observe(t, line_at(2.97, static_cast<std::int32_t>(RobotState::Arrived)), {});
    EXPECT_TRUE(tracker.metrics().formation_tick);
    EXPECT_FALSE(tracker.metrics().goal_tick);
    EXPECT_EQ(tracker.metrics().arrived, 0u);
    EXPECT_EQ(tracker.metrics().outcome, "formed_not_arrived");
  }
  {
    // The line wrecked at the goal: the three robots 0.2 m apart in a clump on the goal, at rest.
    MetricsTracker tracker(line_mission(), &swarmform::controller::paper_descriptor());
    auto robots = line_at(0.0, static_cast<std::int32_t>(RobotState::Arrived));
    robots[0].pose = {5.0, 0.0, 0.0};
    robots[1].pose = {5.2, 0.0, 0.0};
    robots[2].pose = {5.0, 0.2, 0.0};
    for (Tick t = 0; t < 40; ++t) tracker.observe(t, robots, {});
    EXPECT_FALSE(tracker.metrics().formation_tick);
    EXPECT_FALSE(tracker.metrics().goal_tick);
    EXPECT_EQ(tracker.metrics().outcome, "not_formed");
  }
}

TEST(MetricsTracker, RobotsReportingWrongLabelsAreJudgedOnTheirPositions) {
  MetricsTracker tracker(line_mission(), &swarmform::controller::paper_descriptor());
  auto robots = line_at(0.0, kReady);
  robots[0].telemetry.label = 2;  // swapped
  robots[2].telemetry.label = 0;
  robots[1].telemetry.label = 0;  // and a lie
  for (Tick t = 0; t <= kRestTicks; ++t) tracker.observe(t, robots, {});
  ASSERT_TRUE(tracker.metrics().formation_tick);
  EXPECT_LT(*tracker.metrics().shape_error_at_formation, 1e-9);
  // The line read either way round (a half turn fits it as well); the spare left out.
  const auto& labels = tracker.assigned_labels();
  EXPECT_TRUE(labels == (std::vector<int>{0, 1, 2, -1}) || labels == (std::vector<int>{2, 1, 0, -1}));
}

TEST(MetricsTracker, FewerRobotsThanPlacesCanForm) {
  MetricsTracker tracker(line_mission(), &swarmform::controller::paper_descriptor());
  auto robots = line_at(0.0, kReady);
  robots[1].alive = false;  // the middle label's robot died; the two ends still stand in line
  // With as many live robots as places, the spare would have to take a place too: it died as well.
  robots[3].alive = false;
  for (Tick t = 0; t <= kRestTicks; ++t) tracker.observe(t, robots, {});
  ASSERT_TRUE(tracker.metrics().formation_tick);
  const auto& labels = tracker.assigned_labels();
  EXPECT_TRUE(labels == (std::vector<int>{0, -1, 2, -1}) || labels == (std::vector<int>{2, -1, 0, -1}));
}

// As many robots as places, at rest far from any layout of the shape: the radial bound rules every tick out,
// no Hungarian solve runs; once they stand in the shape (and have rested there) it is formed as before.
TEST(MetricsTracker, RobotsAtRestThatCannotStandInTheShapeCostNoSolve) {
  Mission m = line_mission();
  m.shape = ShapeMatrix{3, 3, {0, 1, 2, 3, 4, 5, 6, 7, 8}};
  MetricsTracker tracker(m, &swarmform::controller::paper_descriptor());
  std::vector<RobotTruth> robots(9);
  for (RobotId i = 0; i < 9; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 9.0;
    robots[i].id = i;
    robots[i].telemetry.state = kSearching;
    robots[i].telemetry.label = static_cast<std::int32_t>(i);
    robots[i].pose = {5.0 * std::cos(a), 5.0 * std::sin(a), 0.0};  // a ring of radius 5, the block 2 x 2
    robots[i].last_broadcast_tick = kSpeaking;
  }
  Tick t = 0;
  for (; t < 3 * kRestTicks; ++t) tracker.observe(t, robots, {});
  EXPECT_FALSE(tracker.metrics().formation_tick);
  EXPECT_EQ(tracker.metrics().outcome, "not_formed");
  EXPECT_EQ(tracker.assignment_stats().ruled_out, 2 * kRestTicks);  // every tick with all 9 at rest
  EXPECT_EQ(tracker.assignment_stats().evaluations, 0u);
  EXPECT_EQ(tracker.assignment_stats().full_solves, 0u);

  for (RobotId i = 0; i < 9; ++i) robots[i].pose = {10.0 + i % 3, -1.0 * (i / 3), 0.0};
  const Tick in_shape = t;
  for (; t <= in_shape + kRestTicks; ++t) tracker.observe(t, robots, {});
  ASSERT_TRUE(tracker.metrics().formation_tick);
  EXPECT_EQ(*tracker.metrics().formation_tick, in_shape + kRestTicks);
  EXPECT_LT(*tracker.metrics().shape_error_at_formation, 1e-9);
}

TEST(MetricsTracker, OutcomeNoneForRandomWalk) {
  Mission mission = line_mission();
  mission.behaviour = "random_walk";
  MetricsTracker tracker(mission, &swarmform::controller::random_walk_descriptor());
  for (Tick t = 0; t <= 20; ++t) tracker.observe(t, line_at(0.0, kSearching), {});
  EXPECT_EQ(tracker.metrics().outcome, "none");
  EXPECT_FALSE(tracker.metrics().formation_tick);
}

// Only a behaviour that goes somewhere has stuck robots: robots of one that does not (random_walk's
// descriptor: no needs_goal) that stood still for 300 ticks have done what they were told.
TEST(MetricsTracker, NoStuckRobotsForABehaviourWithoutAGoal) {
  Mission mission = line_mission();
  mission.behaviour = "random_walk";
  MetricsTracker tracker(mission, &swarmform::controller::random_walk_descriptor());
  auto robots = line_at(0.0, kSearching);
  robots[1].pose.y += 0.5;  // off its place, still
  for (Tick t = 0; t <= 400; ++t) tracker.observe(t, robots, {});
  tracker.conclude();
  EXPECT_TRUE(tracker.metrics().stuck_robots.empty());
  MetricsTracker paper(line_mission(), &swarmform::controller::paper_descriptor());
  for (Tick t = 0; t <= 400; ++t) paper.observe(t, robots, {});
  paper.conclude();
  EXPECT_EQ(paper.metrics().stuck_robots, (std::vector<RobotId>{1, 3}))
      << "the same robots, a behaviour with a goal: the one off its place and the spare are stuck";
}

// A 4x4 block (labels row-major) with robots 0..15 on their places (left column at x0) and robot 16 a spare.
Mission block_mission() {
  Mission m;
  m.shape = ShapeMatrix{4, 4, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}};
  m.goal = {20.0, 0.0};
  return m;
}

// A live robot that has said nothing for kSilentTicks is left out of the shape (nobody hears it: it cannot
// take part), so a silent agent's body standing at its start does not keep the others from forming.
TEST(MetricsTracker, ASilentRobotIsLeftOutOfTheShapeAndListed) {
  MetricsTracker tracker(line_mission(), &swarmform::controller::paper_descriptor());
  Tick t = 0;
  for (; t < kSilentTicks + kRestTicks + 5; ++t) {
    // Two speaking robots on places 0 and 1, no spare; robot 2 (whose place is empty) never broadcast and
    // stands far away: counted, it would have to be assigned to the empty place and nothing would form.
    auto robots = line_at(0.0, kReached);
    robots.pop_back();
    robots[2].last_broadcast_tick.reset();
    robots[2].pose = {0.0, 7.0, 0.0};
    tracker.observe(t, robots, {});
    if (t < kSilentTicks) {
      EXPECT_FALSE(tracker.metrics().formation_tick) << t;
    }
  }
  ASSERT_TRUE(tracker.metrics().formation_tick);
  EXPECT_GE(*tracker.metrics().formation_tick, kSilentTicks);
  tracker.conclude();
  EXPECT_EQ(tracker.metrics().silent_robots, std::vector<RobotId>{2});
}

std::vector<RobotTruth> block_at(double x0) {
  std::vector<RobotTruth> robots(17);
  for (RobotId i = 0; i < 17; ++i) {
    robots[i].id = i;
    robots[i].telemetry.state = kMoving;
    robots[i].telemetry.label = i < 16 ? static_cast<std::int32_t>(i) : -1;
    robots[i].pose = {x0 + i % 4, -static_cast<double>(i / 4), 0.0};
    robots[i].last_broadcast_tick = kSpeaking;
  }
  robots[16].pose = {-20.0, 0.0, 0.0};
  return robots;
}

TEST(MetricsTracker, StuckRobotsAreStillAndNotAtAPlace) {
  MetricsTracker tracker(block_mission(), &swarmform::controller::paper_descriptor());
  // Robot 5 pinned 0.5 m off its place (so not formed); the spare walks, then stops for less than 300
  // ticks; robot 15 keeps trembling 2 cm off its place (it moves: not stuck).
  auto at = [](Tick t) {
    auto robots = block_at(0.0);
    robots[5].pose.y += 0.5;
    robots[16].pose.x = -20.0 + 0.02 * static_cast<double>(std::min<Tick>(t, 200));
    robots[15].pose.x += t % 2 == 0 ? 0.02 : -0.02;
    return robots;
  };
  for (Tick t = 0; t <= 400; ++t) tracker.observe(t, at(t), {});
  tracker.conclude();
  EXPECT_EQ(tracker.metrics().outcome, "not_formed");
  EXPECT_EQ(tracker.metrics().stuck_robots, (std::vector<RobotId>{5}));
  // After 300 still ticks the spare counts too: it is neither at a place nor moving.
  for (Tick t = 401; t <= 520; ++t) tracker.observe(t, at(t), {});
  tracker.conclude();
  EXPECT_EQ(tracker.metrics().stuck_robots, (std::vector<RobotId>{5, 16}));
}

TEST(MetricsTracker, StuckRobotsStrandedFarAwayDoNotMakeTheOthersStuck) {
  // Robots 14 and 15 stranded 6 m away (still); the other 14 and the spare's place: 14 in place. The least
  // squares fit of all 16 is pulled ~0.7 m towards the stranded pair; the robots in place are judged against
  // the fit of the robots that stand in shape.
  MetricsTracker tracker(block_mission(), &swarmform::controller::paper_descriptor());
  auto robots = block_at(0.0);
  robots[14].pose = {8.0, -8.0, 0.0};
  robots[15].pose = {8.5, -8.0, 0.0};
  for (Tick t = 0; t <= 310; ++t) tracker.observe(t, robots, {});
  tracker.conclude();
  EXPECT_EQ(tracker.metrics().outcome, "not_formed");
  EXPECT_EQ(tracker.metrics().stuck_robots, (std::vector<RobotId>{14, 15, 16}));
}

TEST(MetricsTracker, DeadRobotsAndContactsAndEvents) {
  MetricsTracker tracker(line_mission(), &swarmform::controller::paper_descriptor());
  auto robots = line_at(0.0, kReady);
  robots[2].alive = false;
  robots[2].telemetry.state = kSearching;  // a dead robot's report does not matter
  tracker.observe(5, robots, {2, 1});
  tracker.observe(6, robots, {1, 0});
  EXPECT_EQ(tracker.metrics().collisions_robot_robot, 3u);
  EXPECT_EQ(tracker.metrics().collisions_robot_obstacle, 1u);
  tracker.count_event(make_event(6, "death", 2));
  tracker.count_event(make_event(9, "rejoin", 2));
  tracker.count_event(make_event(10, "leader", 0));
  tracker.count_event(make_event(20, "leader", 1));
  tracker.count_event(make_event(30, "leader", 0));
  tracker.count_event(make_event(31, "fragment", -1));
  tracker.count_event(make_event(40, "rejoin_graph", -1));
  const Metrics& m = tracker.metrics();
  ASSERT_EQ(m.deaths.size(), 1u);
  EXPECT_EQ(m.deaths[0].id, 2u);
  EXPECT_EQ(m.deaths[0].tick, 6u);
  ASSERT_EQ(m.rejoins.size(), 1u);
  EXPECT_EQ(m.leader_changes, 2u);  // the first leader is not a change
  EXPECT_EQ(m.fragmentations, 1u);
  EXPECT_EQ(m.graph_rejoins, 1u);
}

std::vector<std::string> kinds(const std::vector<Event>& events) {
  std::vector<std::string> k;
  for (const auto& e : events) k.push_back(e["kind"]);
  return k;
}

// A state event names its values from the behaviour's own table, never from the paper's: a value the table
// does not list is "unknown".
TEST(EventDeriver, NamesStatesFromTheBehavioursOwnTable) {
  const std::array<swarmform::behaviour::StateSpec, 2> table{
      {{0, "walking", "#000000"}, {9, "resting", "#ffffff"}}};
  EventDeriver deriver(3.0, table);
  std::size_t components = 0;
  auto robots = line_at(0.0, 0);
  EXPECT_TRUE(deriver.observe(0, robots, false, components).empty());  // baseline
  robots[0].telemetry.state = 9;
  auto events = deriver.observe(1, robots, false, components);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"state"}));
  EXPECT_EQ(events[0]["from_name"], "walking");
  EXPECT_EQ(events[0]["to_name"], "resting");
  robots[0].telemetry.state = kReady;  // the paper's "ready": not this behaviour's
  events = deriver.observe(2, robots, false, components);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"state"}));
  EXPECT_EQ(events[0]["to_name"], "unknown");
}

TEST(EventDeriver, StateLabelLeaderDeathAndGraph) {
  EventDeriver deriver(3.0, swarmform::controller::paper_descriptor().states);
  std::size_t components = 0;
  auto robots = line_at(0.0, kReached);
  EXPECT_TRUE(deriver.observe(0, robots, false, components).empty());  // baseline

  robots[0].telemetry.state = kReady;
  robots[3].telemetry.label = 7;
  auto events = deriver.observe(1, robots, false, components);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"state", "label"}));
  EXPECT_EQ(events[0]["from"], kReached);
  EXPECT_EQ(events[0]["to_name"], "ready");
  EXPECT_EQ(events[1]["to"], 7);

  // An election: 1 and 2 both claim for a while (no leader yet), then 1 alone; it is taken after
  // kLeaderSettleTicks ticks alone, with `since` = its first tick alone.
  robots[1].telemetry.leader = true;
  robots[2].telemetry.leader = true;
  Tick t = 2;
  for (; t < 10; ++t) EXPECT_TRUE(deriver.observe(t, robots, false, components).empty());
  robots[2].telemetry.leader = false;
  const Tick alone_since = t;
  for (; t < alone_since + kLeaderSettleTicks - 1; ++t) {
    EXPECT_TRUE(deriver.observe(t, robots, false, components).empty());
  }
  events = deriver.observe(t, robots, false, components);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"leader"}));
  EXPECT_EQ(events[0]["id"], 1);
  EXPECT_EQ(events[0]["previous"], -1);
  EXPECT_EQ(events[0]["since"], alone_since);
  // A second claimant while the incumbent still claims changes nothing.
  robots[2].telemetry.leader = true;
  EXPECT_TRUE(deriver.observe(++t, robots, false, components).empty());

  // The leader dies: the world's alive flag is enough for a death event, the title is lost at once, and the
  // other claimant takes over once it has claimed alone long enough.
  robots[1].alive = false;
  events = deriver.observe(++t, robots, false, components);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"death", "leader_lost"}));
  EXPECT_EQ(events[1]["id"], 1);
  const Tick lost = t;
  do {
    events = deriver.observe(++t, robots, false, components);
  } while (events.empty() && t < lost + 20);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"leader"}));
  EXPECT_EQ(events[0]["id"], 2);
  EXPECT_EQ(events[0]["previous"], 1);
  EXPECT_EQ(events[0]["since"], lost);
  EXPECT_EQ(t, lost + kLeaderSettleTicks - 1);
  // The front end reporting the same death afterwards does not count it twice; a new one does.
  EXPECT_FALSE(deriver.death(t, 1).has_value());
  EXPECT_TRUE(deriver.death(t, 0).has_value());
  robots[0].alive = false;
  EXPECT_TRUE(deriver.observe(++t, robots, false, components).empty());
  EXPECT_TRUE(deriver.rejoin(t, 0).has_value());
  robots[0].alive = true;
  EXPECT_TRUE(deriver.observe(++t, robots, false, components).empty());

  // Graph: robots 0 and 2 (1 is dead) are 2 m apart: one component with a 3 m range.
  robots[3].telemetry.label = -1;
  events = deriver.observe(++t, robots, true, components);
  EXPECT_EQ(components, 1u);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"label"}));
  robots[2].pose.x = 10.0;
  events = deriver.observe(++t, robots, true, components);
  EXPECT_EQ(components, 2u);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"fragment"}));
  EXPECT_EQ(events[0]["components"], nlohmann::ordered_json::parse("[[0],[2]]"));
  EXPECT_TRUE(deriver.observe(++t, robots, true, components).empty());  // still split: no new event
  robots[2].pose.x = 2.5;
  events = deriver.observe(++t, robots, true, components);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"rejoin_graph"}));
}

TEST(CommGraph, ComponentsByRange) {
  // A chain 0-1-2 with 2.9 m links, a pair 3-4 far away, a lone point 5.
  const std::vector<Vec2> points{{0, 0}, {2.9, 0}, {2.9, 2.9}, {100, 100}, {101, 100}, {-50, 0}};
  const auto c = range_components(points, 3.0);
  EXPECT_EQ(component_count(c), 3u);
  EXPECT_EQ(c[0], c[1]);
  EXPECT_EQ(c[1], c[2]);
  EXPECT_EQ(c[3], c[4]);
  EXPECT_NE(c[0], c[3]);
  EXPECT_NE(c[5], c[0]);
  EXPECT_EQ(component_count(range_components(points, 200.0)), 1u);
}

}  // namespace
}  // namespace swarmform::world
