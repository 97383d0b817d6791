// The paper's run and the corridor, end to end in the in-process harness (formation, then Ready and motion):
// every robot arrives; after each obstacle the distortion is back under 0.2 grid units within 200 ticks; the
// small obstacle splits the formation's neighbour graph and it reunites; the large obstacle shrinks the
// affected side and it recovers; no robot touches an obstacle. The figures are printed for the notes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"
#include "tests/sim/measured.hpp"
#include "tests/sim/motion/sim_checks.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::sim_motion {
namespace {

std::string repo(const std::string& rel) {
  return std::string(SWARMFORM_REPO_DIR) + "/" + rel;
}

// The far edge of an obstacle along +x (the direction of travel in our scenarios).
double far_x(const world::Obstacle& o) {
  return o.kind == world::Obstacle::Kind::Cylinder ? o.centre.x + o.radius : o.centre.x + o.half_extents.x;
}

struct PaperRunRecord {
  std::optional<Tick> motion_start;
  std::vector<std::optional<Tick>> passed;  // by obstacle: first tick every live shape robot is past it
  std::optional<Tick> split_tick, reunite_tick;
  double side_baseline = 0.0, side_min = std::numeric_limits<double>::max(), side_end = 0.0;
};

// How far the shape reaches out on the +y side (the large box's) beyond the leader's line.
double left_reach(const std::vector<world::RobotTruth>& robots) {
  double leader_y = 0.0, max_y = -1e9;
  for (const auto& r : robots) {
    if (!r.alive || controller::kPaperColumns.label_of(r.telemetry) < 0) continue;
    if (controller::kPaperColumns.leader_of(r.telemetry)) leader_y = r.pose.y;
    max_y = std::max(max_y, r.pose.y);
  }
  return max_y - leader_y;
}

TEST(MotionPaperRun, EveryRobotArrivesPastBothObstaclesAndTheShapeRecovers) {
  const auto scenario =
      world::load_scenario(repo("scenarios/paper.yaml"), {}, swarmform::controller::builtin_registry());
  ASSERT_EQ(scenario.obstacles.size(), 2u);
  const double spacing = scenario.mission.grid_spacing;
  harness::Harness h(scenario);
  PaperRunRecord rec;
  rec.passed.resize(scenario.obstacles.size());
  const auto motion = static_cast<std::int32_t>(RobotState::Motion);
  // Run to the goal, then on until every robot has arrived (or 400 ticks more) to watch the recovery.
  while (h.world().tick() < scenario.max_ticks) {
    h.step();
    const auto& robots = h.world().robots();
    const Tick t = h.world().tick();
    if (!rec.motion_start) {
      for (const auto& r : robots) {
        if (r.telemetry.state == motion) rec.motion_start = t;
      }
      if (rec.motion_start) rec.side_baseline = left_reach(robots);
      continue;
    }
    const double reach = left_reach(robots);
    if (!rec.passed[0]) rec.side_min = std::min(rec.side_min, reach);
    rec.side_end = reach;
    for (std::size_t k = 0; k < scenario.obstacles.size(); ++k) {
      if (rec.passed[k]) continue;
      bool past = true;
      for (const auto& r : robots) {
        if (r.alive && controller::kPaperColumns.label_of(r.telemetry) >= 0 &&
            r.pose.x - kRobotRadius <= far_x(scenario.obstacles[k]))
          past = false;
      }
      if (past) rec.passed[k] = t;
    }
    const std::size_t components = neighbour_components(robots, 1.5 * spacing);
    if (components > 1 && !rec.split_tick) rec.split_tick = t;
    if (components == 1 && rec.split_tick && !rec.reunite_tick) rec.reunite_tick = t;
    const auto& sh = measured(h);
    if (sh.goal_tick && (all_arrived(robots) || t > *sh.goal_tick + 400)) break;
  }
  const auto& m = h.metrics();
  const auto& sh = measured(h);
  auto at = [&](std::optional<Tick> t) { return t ? static_cast<long>(*t) : -1L; };
  std::printf(
      "paper: formation %ld motion %ld goal %ld peak %.3f mean %.3f at_goal %.3f contacts obstacle %u robot "
      "%u\n",
      at(sh.formation_tick), at(sh.motion_start_tick), at(sh.goal_tick), sh.peak_distortion.value_or(-1),
      sh.mean_distortion.value_or(-1), sh.shape_error_at_goal.value_or(-1), m.collisions_robot_obstacle,
      m.collisions_robot_robot);
  std::printf(
      "paper: box passed %ld, post passed %ld; graph split %ld reunited %ld; left reach %.2f -> min %.2f -> "
      "end %.2f\n",
      at(rec.passed[0]), at(rec.passed[1]), at(rec.split_tick), at(rec.reunite_tick), rec.side_baseline,
      rec.side_min, rec.side_end);

  ASSERT_TRUE(sh.goal_tick.has_value()) << "the swarm did not reach the goal";
  EXPECT_EQ(sh.arrived, scenario.robots.size());
  EXPECT_EQ(m.collisions_robot_obstacle, 0u);
  // After each obstacle, the distortion is back under 0.2 grid units within 200 ticks.
  for (std::size_t k = 0; k < scenario.obstacles.size(); ++k) {
    ASSERT_TRUE(rec.passed[k].has_value()) << scenario.obstacles[k].name << " never passed";
    std::optional<Tick> back;
    double at_pass = -1.0;
    for (const auto& [tick, error] : sh.distortion) {
      if (tick == *rec.passed[k]) at_pass = error;
      if (!back && tick >= *rec.passed[k] && error < 0.2) back = tick;
    }
    std::printf("paper: %s passed at %lu (distortion %.3f), under 0.2 at %ld\n",
                scenario.obstacles[k].name.c_str(), static_cast<unsigned long>(*rec.passed[k]), at_pass,
                at(back));
    ASSERT_TRUE(back.has_value()) << "after " << scenario.obstacles[k].name
                                  << " the distortion never fell under 0.2";
    EXPECT_LE(*back, *rec.passed[k] + 200) << "after " << scenario.obstacles[k].name;
  }
  // The small obstacle splits the neighbour graph and it reunites.
  ASSERT_TRUE(rec.split_tick.has_value()) << "the neighbour graph never split";
  EXPECT_TRUE(rec.reunite_tick.has_value()) << "the neighbour graph never reunited";
  // The large obstacle shrinks the affected (left) side, and it recovers.
  EXPECT_LT(rec.side_min, rec.side_baseline - 0.3 * spacing) << "the left side never gave way";
  EXPECT_NEAR(rec.side_end, rec.side_baseline, 0.15 * spacing) << "the left side did not recover";
}

TEST(MotionPaperRun, CorridorRunArrives) {
  const auto scenario =
      world::load_scenario(repo("scenarios/corridor.yaml"), {}, swarmform::controller::builtin_registry());
  harness::Harness h(scenario);
  h.run();
  const auto& m = h.metrics();
  const auto& sh = measured(h);
  auto at = [&](std::optional<Tick> t) { return t ? static_cast<long>(*t) : -1L; };
  std::printf(
      "corridor: formation %ld goal %ld peak %.3f mean %.3f at_goal %.3f contacts obstacle %u robot %u\n",
      at(sh.formation_tick), at(sh.goal_tick), sh.peak_distortion.value_or(-1),
      sh.mean_distortion.value_or(-1), sh.shape_error_at_goal.value_or(-1), m.collisions_robot_obstacle,
      m.collisions_robot_robot);
  ASSERT_TRUE(sh.goal_tick.has_value()) << "the corridor run did not reach the goal";
  EXPECT_EQ(sh.arrived, scenario.robots.size());
  EXPECT_EQ(m.collisions_robot_obstacle, 0u);
}

}  // namespace
}  // namespace swarmform::sim_motion
