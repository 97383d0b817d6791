// The paper controller end to end in the ideal mini world (no physics): the seed election, the allotment,
// the barrier, and robots dying before the shape is complete.
#include <gtest/gtest.h>

#include <string>

#include "common/shape.hpp"
#include "mini_world.hpp"
#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/paper_controller.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"

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

// A searching robot far from everyone (no label, no origin), hearing the given messages at tick `tick`.
Perception far_away(Tick tick, const std::vector<RobotMessage>& heard) {
  Perception p;
  p.tick = tick;
  p.pose = {40.0, 40.0, 0.0};
  p.ultrasonic.fill(kUltrasonicMaxRange);
  for (const auto& m : heard) p.messages.push_back({m.sender, 1.0, 0.0, encode_message(m)});
  return p;
}

TEST(PaperControllerMessages, LeaveTheStigmergyOutWhileEveryNeighbourSentOurOwnTablesDigest) {
  Stigmergy theirs(2);  // robot 2's table: two labels taken far away
  theirs.put(stig::key(stig::Ns::Labels, 0), 7);
  theirs.put(stig::key(stig::Ns::Labels, 1), 8);
  auto from = [&](RobotId id, std::uint64_t digest, std::vector<StigmergyEntry> entries) {
    RobotMessage m;
    m.sender = id;
    m.state = RobotState::Searching;
    m.pose = {41.0, 40.0, 0.0};
    m.table_digest = digest;
    m.entries = std::move(entries);
    return m;
  };
  PaperController c;
  c.init(mission_for("triangle.txt"), 5);
  // Tick 1: robot 2's entries arrive; until now our table differed from its, so ours still carries them.
  c.step(far_away(1, {from(2, theirs.digest(), theirs.entries())}));
  ASSERT_EQ(c.stigmergy().digest(), theirs.digest());
  // Tick 2: robot 2 sent our own digest: it holds all we hold, and the message goes without entries.
  auto sent = decode_message(c.step(far_away(2, {from(2, theirs.digest(), {})})).message);
  ASSERT_TRUE(sent.has_value());
  EXPECT_TRUE(sent->entries.empty());
  EXPECT_EQ(sent->table_digest, theirs.digest());
  // Tick 3: robot 3 is heard with another table (digest 0: an empty one), so the entries go out again.
  sent = decode_message(c.step(far_away(3, {from(2, theirs.digest(), {}), from(3, 0, {})})).message);
  ASSERT_TRUE(sent.has_value());
  EXPECT_EQ(sent->entries.size(), 2u);
  // Tick 4: robot 3, silent since, is still a live neighbour with its last digest: entries still go out.
  sent = decode_message(c.step(far_away(4, {from(2, theirs.digest(), {})})).message);
  ASSERT_TRUE(sent.has_value());
  EXPECT_EQ(sent->entries.size(), 2u);
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
    if (controller::kPaperColumns.label_of(w.last(i).telemetry) == 0) {
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
  for (std::size_t i = 0; i < w.size(); ++i)
    labels.insert(controller::kPaperColumns.label_of(w.last(i).telemetry));
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
      if (tm.state == static_cast<int>(RobotState::Moving) && kPaperColumns.label_of(tm) > 0) victim = i;
    }
  }
  ASSERT_TRUE(victim.has_value());
  const int lost_label = controller::kPaperColumns.label_of(w.last(*victim).telemetry);
  w.kill(*victim);
  EXPECT_LT(run_until_ready(w, 9, 6000), 6000u);
  bool taken = false;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w.alive(i) && controller::kPaperColumns.label_of(w.last(i).telemetry) == lost_label) taken = true;
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
      if (tm.state == static_cast<int>(RobotState::Reached) && kPaperColumns.label_of(tm) > 0) victim = i;
    }
  }
  ASSERT_TRUE(victim.has_value());
  w.kill(*victim);
  EXPECT_LT(run_until_ready(w, 8, 6000), 6000u);
}

}  // namespace
}  // namespace swarmform::controller
