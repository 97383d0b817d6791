// The paper controller end to end in the ideal mini world (no physics): the seed election, the allotment,
// the barrier, and robots dying before the shape is complete.
#include <gtest/gtest.h>

#include <string>

#include "common/shape.hpp"
#include "mini_world.hpp"
#include "robot_agent/controller/paper_controller.hpp"

namespace swarmform::controller {
namespace {

using testing::grid_start;
using testing::MiniWorld;

Mission mission_for(const std::string& shape_file) {
  Mission m;
  m.behaviour = "paper";
  m.shape = load_shape_file(std::string(SWARMFORM_SHAPES_DIR) + "/" + shape_file);
  return m;
}

int count_state(const MiniWorld& w, RobotState s) {
  int n = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w.alive(i) && w.last(i).telemetry.state == static_cast<int>(s)) ++n;
  }
  return n;
}

// Ready or beyond (the motion phases take over after Ready).
int count_ready(const MiniWorld& w) {
  return count_state(w, RobotState::Ready) + count_state(w, RobotState::Motion) +
         count_state(w, RobotState::Arrived);
}

// Runs until `expected` live robots are Ready or the deadline; returns the tick.
Tick run_until_ready(MiniWorld& w, int expected, Tick deadline, double* min_sep = nullptr) {
  while (w.tick() < deadline) {
    w.step();
    if (min_sep) *min_sep = std::min(*min_sep, w.min_separation());
    if (count_ready(w) == expected) break;
  }
  return w.tick();
}

TEST(PaperControllerMini, TheRobotClosestToTheOriginBecomesTheSeed) {
  auto poses = grid_start(9, {1.5, 1.5}, 0.8, 3);
  MiniWorld w(mission_for("triangle.txt"), poses);
  std::size_t closest = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (std::hypot(poses[i].x, poses[i].y) < std::hypot(poses[closest].x, poses[closest].y)) closest = i;
  }
  for (int t = 0; t < 60; ++t) w.step();
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w.last(i).telemetry.label == 0) {
      EXPECT_EQ(i, closest);
    }
  }
}

TEST(PaperControllerMini, TriangleFormsAndEveryRobotPassesTheBarrier) {
  MiniWorld w(mission_for("triangle.txt"), grid_start(9, {0.5, 0.5}, 0.8, 1));
  double min_sep = 1e9;
  const Tick t = run_until_ready(w, 9, 4000, &min_sep);
  EXPECT_LT(t, 4000u);
  EXPECT_EQ(count_ready(w), 9);
  EXPECT_GT(min_sep, 2 * kRobotRadius);
  std::set<int> labels;
  for (std::size_t i = 0; i < w.size(); ++i) labels.insert(w.last(i).telemetry.label);
  EXPECT_EQ(labels.size(), 9u);
}

TEST(PaperControllerMini, FormsUnderTwentyPercentMessageLoss) {
  MiniWorld w(mission_for("arrow.txt"), grid_start(10, {0.5, 0.5}, 0.8, 2), 0.2, 7);
  EXPECT_LT(run_until_ready(w, 10, 5000), 5000u);
}

TEST(PaperControllerMini, SparesStaySearchingAndTheShapeCompletes) {
  MiniWorld w(mission_for("triangle.txt"), grid_start(12, {0.5, 0.5}, 0.8, 4));
  EXPECT_LT(run_until_ready(w, 9, 5000), 5000u);
  EXPECT_EQ(count_state(w, RobotState::Searching), 3);
}

TEST(PaperControllerMini, ADeadRobotsLabelGoesToASpare) {
  MiniWorld w(mission_for("triangle.txt"), grid_start(10, {0.5, 0.5}, 0.8, 5));
  // Kill the first robot seen moving to a label other than the seed's.
  std::optional<std::size_t> victim;
  while (!victim && w.tick() < 2000) {
    w.step();
    for (std::size_t i = 0; i < w.size(); ++i) {
      const auto& tm = w.last(i).telemetry;
      if (tm.state == static_cast<int>(RobotState::Moving) && tm.label > 0) victim = i;
    }
  }
  ASSERT_TRUE(victim.has_value());
  const int lost_label = w.last(*victim).telemetry.label;
  w.kill(*victim);
  EXPECT_LT(run_until_ready(w, 9, 6000), 6000u);
  bool taken = false;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w.alive(i) && w.last(i).telemetry.label == lost_label) taken = true;
  }
  EXPECT_TRUE(taken);
}

TEST(PaperControllerMini, WithNoSpareTheShapeCompletesWithoutTheDeadRobotsLabel) {
  MiniWorld w(mission_for("triangle.txt"), grid_start(9, {0.5, 0.5}, 0.8, 6));
  std::optional<std::size_t> victim;
  while (!victim && w.tick() < 2000) {
    w.step();
    for (std::size_t i = 0; i < w.size(); ++i) {
      const auto& tm = w.last(i).telemetry;
      if (tm.state == static_cast<int>(RobotState::Reached) && tm.label > 0) victim = i;
    }
  }
  ASSERT_TRUE(victim.has_value());
  w.kill(*victim);
  EXPECT_LT(run_until_ready(w, 8, 6000), 6000u);
}

}  // namespace
}  // namespace swarmform::controller
