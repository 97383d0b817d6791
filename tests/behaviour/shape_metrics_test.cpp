// The shape measurement (behaviour/shape_metrics.hpp) on hand-made truth, tick by tick (no world needed):
// what the paper's experiment reports as formation_tick, goal_tick, the shape errors, the distortion, the
// path and the stuck robots.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "behaviour/shape_metrics.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"
#include "robot_agent/controller/robot_state.hpp"

namespace swarmform::shape_metrics {
namespace {

constexpr auto kSearching = static_cast<std::int32_t>(RobotState::Searching);
constexpr auto kMoving = static_cast<std::int32_t>(RobotState::Moving);
constexpr auto kReached = static_cast<std::int32_t>(RobotState::Reached);
constexpr auto kReady = static_cast<std::int32_t>(RobotState::Ready);
constexpr auto kMotion = static_cast<std::int32_t>(RobotState::Motion);

const behaviour::Descriptor& paper() {
  return controller::paper_descriptor();
}

// The paper's telemetry with this label (its other columns none).
void set_label(Telemetry& t, std::int32_t label) {
  t.extra = controller::paper_telemetry(label, -1, false, 0.0);
}

// A robot as the world holds it; the truth an experiment sees is made from it.
struct Robot {
  RobotId id = 0;
  Pose2D pose;
  bool alive = true;
  bool silent = false;
  Telemetry telemetry;
};

void observe(ShapeMetrics& metrics, Tick tick, const std::vector<Robot>& robots) {
  std::vector<experiment::RobotTruth> truth;
  for (const Robot& r : robots) truth.push_back({r.id, r.pose, r.alive, &r.telemetry, {}, r.silent});
  experiment::Truth t;
  t.tick = tick;
  t.robots = truth;
  metrics.observe(t);
}

Mission line_mission() {
  Mission m;
  m.shape = ShapeMatrix{1, 3, {0, 1, 2}};
  m.grid_spacing = 1.0;
  m.goal = {5.0, 0.0};
  m.goal_radius = 0.6;
  return m;  // max_speed 0.1 m/s at 10 ticks/s: 0.01 m a tick
}

// Three robots on the line shape with their left end at x0, plus one spare far behind.
std::vector<Robot> line_at(double x0, std::int32_t state) {
  std::vector<Robot> robots(4);
  for (RobotId i = 0; i < 4; ++i) {
    robots[i].id = i;
    robots[i].telemetry.state = state;
    set_label(robots[i].telemetry, i < 3 ? static_cast<std::int32_t>(i) : -1);
    robots[i].pose = {x0 + i, 0.0, 0.0};
  }
  robots[3].pose = {-20.0, 0.0, 0.0};
  robots[3].telemetry.state = kSearching;
  return robots;
}

TEST(ShapeMetrics, FormationMotionGoalAndPath) {
  ShapeMetrics tracker(line_mission(), paper());
  // In place from tick 0, but at rest only after kRestTicks ticks: formation at tick 10, whatever the
  // robots report (all still Reached).
  Tick t = 0;
  for (; t < kRestTicks; ++t) {
    observe(tracker, t, line_at(0.0, kReached));
    EXPECT_FALSE(tracker.measures().formation_tick) << t;
  }
  observe(tracker, t, line_at(0.0, kReached));
  ASSERT_TRUE(tracker.measures().formation_tick);
  EXPECT_EQ(*tracker.measures().formation_tick, kRestTicks);
  EXPECT_LT(*tracker.measures().shape_error_at_formation, 1e-9);
  EXPECT_FALSE(tracker.measures().peak_distortion);  // not moving yet
  EXPECT_EQ(tracker.measures().outcome, "formed_not_arrived");

  // Motion from tick 11: 0.1 m a tick along +x to x0 = 3.5 (k = 35, tick 46); the middle robot is 0.3 m off
  // the line on tick 20. Then still.
  ++t;
  const Tick motion_start = t;
  for (int k = 0; k <= 35; ++k, ++t) {
    auto robots = line_at(0.1 * k, kMotion);
    if (t == 20) robots[1].pose.y = 0.3;
    observe(tracker, t, robots);
    EXPECT_FALSE(tracker.measures().goal_tick) << t;  // moving: not at rest
  }
  const Tick stopped = t - 1;  // 46
  for (; t <= stopped + 15; ++t) observe(tracker, t, line_at(3.5, kMotion));
  const Measures& m = tracker.measures();
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
TEST(ShapeMetrics, ArrivalNeedsTheCentroidInTheGoalRadiusAndTheShapeFormed) {
  {
    ShapeMetrics tracker(line_mission(), paper());
    // Formed and at rest, centroid 1.03 m short of the goal (x0 + 1 = 3.97), every robot saying Arrived.
    for (Tick t = 0; t < 40; ++t)
      observe(tracker, t, line_at(2.97, static_cast<std::int32_t>(RobotState::Arrived)));
    EXPECT_TRUE(tracker.measures().formation_tick);
    EXPECT_FALSE(tracker.measures().goal_tick);
    EXPECT_EQ(tracker.measures().arrived, 0u);
    EXPECT_EQ(tracker.measures().outcome, "formed_not_arrived");
  }
  {
    // The line wrecked at the goal: the three robots 0.2 m apart in a clump on the goal, at rest.
    ShapeMetrics tracker(line_mission(), paper());
    auto robots = line_at(0.0, static_cast<std::int32_t>(RobotState::Arrived));
    robots[0].pose = {5.0, 0.0, 0.0};
    robots[1].pose = {5.2, 0.0, 0.0};
    robots[2].pose = {5.0, 0.2, 0.0};
    for (Tick t = 0; t < 40; ++t) observe(tracker, t, robots);
    EXPECT_FALSE(tracker.measures().formation_tick);
    EXPECT_FALSE(tracker.measures().goal_tick);
    EXPECT_EQ(tracker.measures().outcome, "not_formed");
  }
}

// The goal moves (a world event: Truth::goal) after the shape arrived: the arrival is undone, and the shape
// is judged at the goal where it now stands.
TEST(ShapeMetrics, AGoalThatMovesUndoesTheArrivalAndIsJudgedWhereItStands) {
  ShapeMetrics tracker(line_mission(), paper());
  const auto observe_at = [&](Tick t, double x0, Vec2 goal) {
    std::vector<experiment::RobotTruth> truth;
    const auto robots = line_at(x0, static_cast<std::int32_t>(RobotState::Arrived));
    for (const Robot& r : robots) truth.push_back({r.id, r.pose, r.alive, &r.telemetry, {}, r.silent});
    experiment::Truth tr;
    tr.tick = t;
    tr.robots = truth;
    tr.goal = Goal{goal, 0.6};
    tracker.observe(tr);
  };
  for (Tick t = 0; t < 40; ++t) observe_at(t, 4.0, {5.0, 0.0});  // centroid (5, 0): at the goal
  ASSERT_TRUE(tracker.measures().goal_tick);
  for (Tick t = 40; t < 80; ++t) observe_at(t, 4.0, {-5.0, 0.0});  // the goal moved away at tick 40
  EXPECT_FALSE(tracker.measures().goal_tick);
  EXPECT_EQ(tracker.measures().outcome, "formed_not_arrived");
  for (Tick t = 80; t < 120; ++t) observe_at(t, -6.0, {-5.0, 0.0});  // the line stands there from tick 80
  ASSERT_TRUE(tracker.measures().goal_tick);
  EXPECT_GE(*tracker.measures().goal_tick, 80u);
  EXPECT_EQ(tracker.measures().outcome, "arrived");
}

TEST(ShapeMetrics, RobotsReportingWrongLabelsAreJudgedOnTheirPositions) {
  ShapeMetrics tracker(line_mission(), paper());
  auto robots = line_at(0.0, kReady);
  set_label(robots[0].telemetry, 2);  // swapped
  set_label(robots[2].telemetry, 0);
  set_label(robots[1].telemetry, 0);  // and a lie
  for (Tick t = 0; t <= kRestTicks; ++t) observe(tracker, t, robots);
  ASSERT_TRUE(tracker.measures().formation_tick);
  EXPECT_LT(*tracker.measures().shape_error_at_formation, 1e-9);
  // The line read either way round (a half turn fits it as well); the spare left out.
  const auto& labels = tracker.assigned_labels();
  EXPECT_TRUE(labels == (std::vector<int>{0, 1, 2, -1}) || labels == (std::vector<int>{2, 1, 0, -1}));
}

TEST(ShapeMetrics, FewerRobotsThanPlacesCanForm) {
  ShapeMetrics tracker(line_mission(), paper());
  auto robots = line_at(0.0, kReady);
  robots[1].alive = false;  // the middle label's robot died; the two ends still stand in line
  // With as many live robots as places, the spare would have to take a place too: it died as well.
  robots[3].alive = false;
  for (Tick t = 0; t <= kRestTicks; ++t) observe(tracker, t, robots);
  ASSERT_TRUE(tracker.measures().formation_tick);
  const auto& labels = tracker.assigned_labels();
  EXPECT_TRUE(labels == (std::vector<int>{0, -1, 2, -1}) || labels == (std::vector<int>{2, -1, 0, -1}));
}

// As many robots as places, at rest far from any layout of the shape: the radial bound rules every tick out,
// no Hungarian solve runs; once they stand in the shape (and have rested there) it is formed as before.
TEST(ShapeMetrics, RobotsAtRestThatCannotStandInTheShapeCostNoSolve) {
  Mission m = line_mission();
  m.shape = ShapeMatrix{3, 3, {0, 1, 2, 3, 4, 5, 6, 7, 8}};
  ShapeMetrics tracker(m, paper());
  std::vector<Robot> robots(9);
  for (RobotId i = 0; i < 9; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 9.0;
    robots[i].id = i;
    robots[i].telemetry.state = kSearching;
    set_label(robots[i].telemetry, static_cast<std::int32_t>(i));
    robots[i].pose = {5.0 * std::cos(a), 5.0 * std::sin(a), 0.0};  // a ring of radius 5, the block 2 x 2
  }
  Tick t = 0;
  for (; t < 3 * kRestTicks; ++t) observe(tracker, t, robots);
  EXPECT_FALSE(tracker.measures().formation_tick);
  EXPECT_EQ(tracker.measures().outcome, "not_formed");
  EXPECT_EQ(tracker.assignment_stats().ruled_out, 2 * kRestTicks);  // every tick with all 9 at rest
  EXPECT_EQ(tracker.assignment_stats().evaluations, 0u);
  EXPECT_EQ(tracker.assignment_stats().full_solves, 0u);

  for (RobotId i = 0; i < 9; ++i) robots[i].pose = {10.0 + i % 3, -1.0 * (i / 3), 0.0};
  const Tick in_shape = t;
  for (; t <= in_shape + kRestTicks; ++t) observe(tracker, t, robots);
  ASSERT_TRUE(tracker.measures().formation_tick);
  EXPECT_EQ(*tracker.measures().formation_tick, in_shape + kRestTicks);
  EXPECT_LT(*tracker.measures().shape_error_at_formation, 1e-9);
}

// A 4x4 block (labels row-major) with robots 0..15 on their places (left column at x0) and robot 16 a spare.
Mission block_mission() {
  Mission m;
  m.shape = ShapeMatrix{4, 4, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}};
  m.goal = {20.0, 0.0};
  return m;
}

// A live robot the world says is silent (nobody hears it: experiment::RobotTruth::silent) is left out of the
// shape, so a silent agent's body standing at its start does not keep the others from forming.
TEST(ShapeMetrics, ASilentRobotIsLeftOutOfTheShape) {
  ShapeMetrics tracker(line_mission(), paper());
  constexpr Tick kSilentFrom = 50;
  Tick t = 0;
  for (; t < kSilentFrom + kRestTicks + 5; ++t) {
    // Two robots on places 0 and 1, no spare; robot 2 (whose place is empty) stands far away: counted, it
    // would have to be assigned to the empty place and nothing would form.
    auto robots = line_at(0.0, kReached);
    robots.pop_back();
    robots[2].silent = t >= kSilentFrom;
    robots[2].pose = {0.0, 7.0, 0.0};
    observe(tracker, t, robots);
    if (t < kSilentFrom) {
      EXPECT_FALSE(tracker.measures().formation_tick) << t;
    }
  }
  ASSERT_TRUE(tracker.measures().formation_tick);
  EXPECT_EQ(*tracker.measures().formation_tick, kSilentFrom);  // robots 0 and 1 at rest long before
  EXPECT_EQ(tracker.assigned_labels()[2], -1);
}

std::vector<Robot> block_at(double x0) {
  std::vector<Robot> robots(17);
  for (RobotId i = 0; i < 17; ++i) {
    robots[i].id = i;
    robots[i].telemetry.state = kMoving;
    set_label(robots[i].telemetry, i < 16 ? static_cast<std::int32_t>(i) : -1);
    robots[i].pose = {x0 + i % 4, -static_cast<double>(i / 4), 0.0};
  }
  robots[16].pose = {-20.0, 0.0, 0.0};
  return robots;
}

TEST(ShapeMetrics, StuckRobotsAreStillAndNotAtAPlace) {
  ShapeMetrics tracker(block_mission(), paper());
  // Robot 5 pinned 0.5 m off its place (so not formed); the spare walks, then stops for less than 300
  // ticks; robot 15 keeps trembling 2 cm off its place (it moves: not stuck).
  auto at = [](Tick t) {
    auto robots = block_at(0.0);
    robots[5].pose.y += 0.5;
    robots[16].pose.x = -20.0 + 0.02 * static_cast<double>(std::min<Tick>(t, 200));
    robots[15].pose.x += t % 2 == 0 ? 0.02 : -0.02;
    return robots;
  };
  for (Tick t = 0; t <= 400; ++t) observe(tracker, t, at(t));
  tracker.conclude();
  EXPECT_EQ(tracker.measures().outcome, "not_formed");
  EXPECT_EQ(tracker.measures().stuck_robots, (std::vector<RobotId>{5}));
  // After 300 still ticks the spare counts too: it is neither at a place nor moving.
  for (Tick t = 401; t <= 520; ++t) observe(tracker, t, at(t));
  tracker.conclude();
  EXPECT_EQ(tracker.measures().stuck_robots, (std::vector<RobotId>{5, 16}));
}

TEST(ShapeMetrics, StuckRobotsStrandedFarAwayDoNotMakeTheOthersStuck) {
  // Robots 14 and 15 stranded 6 m away (still); the other 14 and the spare's place: 14 in place. The least
  // squares fit of all 16 is pulled ~0.7 m towards the stranded pair; the robots in place are judged against
  // the fit of the robots that stand in shape.
  ShapeMetrics tracker(block_mission(), paper());
  auto robots = block_at(0.0);
  robots[14].pose = {8.0, -8.0, 0.0};
  robots[15].pose = {8.5, -8.0, 0.0};
  for (Tick t = 0; t <= 310; ++t) observe(tracker, t, robots);
  tracker.conclude();
  EXPECT_EQ(tracker.measures().outcome, "not_formed");
  EXPECT_EQ(tracker.measures().stuck_robots, (std::vector<RobotId>{14, 15, 16}));
}

}  // namespace
}  // namespace swarmform::shape_metrics
