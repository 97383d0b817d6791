// The world's generic metrics and the derived events on hand-made truth, tick by tick (no physics needed).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/robot_state.hpp"
#include "tests/support/paper_columns.hpp"
#include "world_server/run/comm_graph.hpp"
#include "world_server/run/metrics_tracker.hpp"
#include "world_server/run/run_events.hpp"

namespace swarmform::world {
namespace {

constexpr auto kSearching = static_cast<std::int32_t>(RobotState::Searching);
constexpr auto kReached = static_cast<std::int32_t>(RobotState::Reached);
constexpr auto kReady = static_cast<std::int32_t>(RobotState::Ready);

// Robots that broadcast every tick: a last broadcast beyond any tick the tests reach never ages into silence.
constexpr Tick kSpeaking = Tick{1} << 40;

// Three robots on the line shape with their left end at x0, plus one spare far behind.
std::vector<RobotTruth> line_at(double x0, std::int32_t state) {
  std::vector<RobotTruth> robots(4);
  for (RobotId i = 0; i < 4; ++i) {
    robots[i].id = i;
    robots[i].telemetry.state = state;
    testing::set_label(robots[i].telemetry, i < 3 ? static_cast<std::int32_t>(i) : -1);
    robots[i].pose = {x0 + i, 0.0, 0.0};
    robots[i].last_broadcast_tick = kSpeaking;
  }
  robots[3].pose = {-20.0, 0.0, 0.0};
  robots[3].telemetry.state = kSearching;
  return robots;
}

// A live robot that has said nothing for kSilentTicks is silent (nobody hears it): listed at the end.
TEST(MetricsTracker, ASilentRobotIsListed) {
  MetricsTracker tracker;
  auto robots = line_at(0.0, kReached);
  robots[2].last_broadcast_tick.reset();  // never broadcast
  robots[1].last_broadcast_tick = 10;
  for (Tick t = 0; t < kSilentTicks + 5; ++t) tracker.observe(t, robots, {});
  tracker.conclude();
  EXPECT_EQ(tracker.metrics().silent_robots, std::vector<RobotId>{2});
  for (Tick t = kSilentTicks + 5; t <= kSilentTicks + 10; ++t) tracker.observe(t, robots, {});
  tracker.conclude();
  EXPECT_EQ(tracker.metrics().silent_robots, (std::vector<RobotId>{1, 2}));
  robots[2].alive = false;  // a dead robot is dead, not silent
  tracker.observe(kSilentTicks + 11, robots, {});
  tracker.conclude();
  EXPECT_EQ(tracker.metrics().silent_robots, std::vector<RobotId>{1});
}

TEST(MetricsTracker, DeadRobotsAndContactsAndEvents) {
  MetricsTracker tracker;
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

// Label and leader events come from the columns a behaviour declares as such (behaviour/known_columns.hpp):
// the same numbers from a behaviour that does not are its own, and no event.
TEST(EventDeriver, LabelAndLeaderEventsOnlyFromTheColumnsDeclaredAsSuch) {
  for (const bool declared : {false, true}) {
    EventDeriver deriver(3.0, swarmform::controller::paper_descriptor().states);
    if (declared)
      deriver.set_known_columns(std::vector<behaviour::KnownColumns>(4, controller::kPaperColumns));
    std::size_t components = 0;
    auto robots = line_at(0.0, kReached);
    EXPECT_TRUE(deriver.observe(0, robots, false, components).empty());
    testing::set_label(robots[3].telemetry, 7);
    testing::set_leader(robots[1].telemetry, true);
    std::vector<std::string> seen;
    for (Tick t = 1; t <= kLeaderSettleTicks + 1; ++t) {
      for (const auto& k : kinds(deriver.observe(t, robots, false, components))) seen.push_back(k);
    }
    const std::vector<std::string> want =
        declared ? std::vector<std::string>{"label", "leader"} : std::vector<std::string>{};
    EXPECT_EQ(seen, want) << "declared " << declared;
  }
}

TEST(EventDeriver, StateLabelLeaderDeathAndGraph) {
  EventDeriver deriver(3.0, swarmform::controller::paper_descriptor().states);
  deriver.set_known_columns(std::vector<behaviour::KnownColumns>(4, controller::kPaperColumns));
  std::size_t components = 0;
  auto robots = line_at(0.0, kReached);
  EXPECT_TRUE(deriver.observe(0, robots, false, components).empty());  // baseline

  robots[0].telemetry.state = kReady;
  testing::set_label(robots[3].telemetry, 7);
  auto events = deriver.observe(1, robots, false, components);
  ASSERT_EQ(kinds(events), (std::vector<std::string>{"state", "label"}));
  EXPECT_EQ(events[0]["from"], kReached);
  EXPECT_EQ(events[0]["to_name"], "ready");
  EXPECT_EQ(events[1]["to"], 7);

  // An election: 1 and 2 both claim for a while (no leader yet), then 1 alone; it is taken after
  // kLeaderSettleTicks ticks alone, with `since` = its first tick alone.
  testing::set_leader(robots[1].telemetry, true);
  testing::set_leader(robots[2].telemetry, true);
  Tick t = 2;
  for (; t < 10; ++t) EXPECT_TRUE(deriver.observe(t, robots, false, components).empty());
  testing::set_leader(robots[2].telemetry, false);
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
  testing::set_leader(robots[2].telemetry, true);
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
  testing::set_label(robots[3].telemetry, -1);
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
