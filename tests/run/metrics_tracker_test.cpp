// The metrics and the derived events on hand-made truth, tick by tick (no physics needed).
#include <gtest/gtest.h>

#include "common/robot_state.hpp"
#include "world_server/run/comm_graph.hpp"
#include "world_server/run/metrics_tracker.hpp"
#include "world_server/run/run_events.hpp"

namespace swarmform::world {
namespace {

constexpr auto kSearching = static_cast<std::int32_t>(RobotState::Searching);
constexpr auto kReached = static_cast<std::int32_t>(RobotState::Reached);
constexpr auto kReady = static_cast<std::int32_t>(RobotState::Ready);
constexpr auto kMotion = static_cast<std::int32_t>(RobotState::Motion);

Mission line_mission() {
  Mission m;
  m.shape = ShapeMatrix{1, 3, {0, 1, 2}};
  m.grid_spacing = 1.0;
  m.goal = {5.0, 0.0};
  m.goal_radius = 0.6;  // + the line's own radius 1.0: a goal region of 1.6 m
  return m;
}

// Three robots on the line shape with their left end at x0, plus one spare far behind.
std::vector<RobotTruth> line_at(double x0, std::int32_t state) {
  std::vector<RobotTruth> robots(4);
  for (RobotId i = 0; i < 4; ++i) {
    robots[i].id = i;
    robots[i].telemetry.state = state;
    robots[i].telemetry.label = i < 3 ? static_cast<std::int32_t>(i) : -1;
    robots[i].pose = {x0 + i, 0.0, 0.0};
  }
  robots[3].pose = {-20.0, 0.0, 0.0};
  robots[3].telemetry.state = kSearching;
  return robots;
}

TEST(MetricsTracker, FormationMotionGoalAndPath) {
  MetricsTracker tracker(line_mission());
  tracker.observe(0, line_at(0.0, kReached), {});
  EXPECT_FALSE(tracker.metrics().formation_tick);
  auto almost = line_at(0.0, kReady);
  almost[1].telemetry.state = kReached;  // one shape robot not ready yet
  tracker.observe(1, almost, {});
  EXPECT_FALSE(tracker.metrics().formation_tick);
  tracker.observe(2, line_at(0.0, kReady), {});  // the spare stays searching: it does not hold formation up
  ASSERT_TRUE(tracker.metrics().formation_tick);
  EXPECT_EQ(*tracker.metrics().formation_tick, 2u);
  EXPECT_LT(*tracker.metrics().shape_error_at_formation, 1e-9);
  EXPECT_FALSE(tracker.metrics().peak_distortion);  // not moving yet

  // Motion: 0.1 m a tick along +x; the middle robot is 0.3 m off the line on tick 12.
  Tick t = 3;
  for (int k = 0; k <= 40; ++k, ++t) {
    auto robots = line_at(0.1 * k, kMotion);
    if (t == 12) robots[1].pose.y = 0.3;
    tracker.observe(t, robots, {});
  }
  const Metrics& m = tracker.metrics();
  EXPECT_EQ(*m.motion_start_tick, 3u);
  // The goal region, radius 1.6 about (5, 0), holds the three robots (x0..x0+2) once x0 >= 3.4: k = 34,
  // tick 37.
  ASSERT_TRUE(m.goal_tick);
  EXPECT_EQ(*m.goal_tick, 37u);
  EXPECT_LT(*m.shape_error_at_goal, 1e-9);
  EXPECT_EQ(m.arrived, 3u);
  // The bent line: best fit error of (0,0),(1,0.3),(2,0) against a straight line; positive, and the peak.
  ASSERT_TRUE(m.peak_distortion);
  EXPECT_GT(*m.peak_distortion, 0.05);
  EXPECT_NEAR(*m.mean_distortion, *m.peak_distortion / 35.0, 1e-12);  // 35 motion ticks (3..37), one bent
  // Centroid path over the motion window (ticks 3..37): 34 steps of 0.1 m, plus the bend's side step there
  // and back (0.1 m each way in y).
  EXPECT_NEAR(m.path_length, 3.4 + 2 * std::hypot(0.1, 0.1) - 0.2, 1e-9);
  EXPECT_EQ(m.distortion.size(), t - 2);
}

TEST(MetricsTracker, GoalReachedWhenEveryShapeRobotReportsArrived) {
  MetricsTracker tracker(line_mission());
  tracker.observe(0, line_at(-10.0, kReady), {});
  tracker.observe(1, line_at(-10.0, kMotion), {});
  EXPECT_FALSE(tracker.metrics().goal_tick);  // far from the goal region
  auto robots = line_at(-10.0, static_cast<std::int32_t>(RobotState::Arrived));
  robots[3].telemetry.state = kSearching;  // the spare is no shape robot
  tracker.observe(2, robots, {});
  ASSERT_TRUE(tracker.metrics().goal_tick);
  EXPECT_EQ(*tracker.metrics().goal_tick, 2u);
  EXPECT_EQ(tracker.metrics().arrived, 0u);  // in the goal region: none
}

TEST(MetricsTracker, DeadRobotsAndContactsAndEvents) {
  MetricsTracker tracker(line_mission());
  auto robots = line_at(0.0, kReady);
  robots[2].alive = false;
  robots[2].telemetry.state = kSearching;  // a dead robot's report does not hold formation up
  tracker.observe(5, robots, {2, 1});
  tracker.observe(6, robots, {1, 0});
  EXPECT_EQ(*tracker.metrics().formation_tick, 5u);
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

TEST(EventDeriver, StateLabelLeaderDeathAndGraph) {
  EventDeriver deriver(3.0);
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
