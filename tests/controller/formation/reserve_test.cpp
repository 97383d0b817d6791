// The reserve (reserve.hpp): which labels a spare may take once the shape moves, who counts as a member
// then, and where a reserve with nothing to take waits. Hand-made stigmergy tables, no world.
#include <gtest/gtest.h>

#include <map>

#include "robot_agent/controller/allotment.hpp"
#include "robot_agent/controller/barrier.hpp"
#include "robot_agent/controller/motion_phase.hpp"
#include "robot_agent/controller/reserve.hpp"

namespace swarmform::controller {
namespace {

constexpr int kLabels = 3;
constexpr int kTimeout = 60;

void mark_dead(Stigmergy& s, RobotId id) {
  s.put(stig::key(stig::Ns::Parents, id), motion::kDeadMark);
}

// Members 10, 11, 12 hold labels 0, 1, 2 and passed the barrier; the shape is moving.
Stigmergy moving_shape() {
  Stigmergy s(99);
  for (RobotId id = 10; id <= 12; ++id) {
    put_label_holder(s, static_cast<int>(id - 10), id);
    barrier_enter(s, id, static_cast<int>(id - 10));
  }
  s.put(stig::key(stig::Ns::Leader, 0), 10);
  return s;
}

const std::map<RobotId, int> kAtReady = {{10, 0}, {11, 1}, {12, 2}};

TEST(Reserve, ALabelIsVacantOnlyOnceItsMemberIsMarkedDead) {
  Stigmergy s = moving_shape();
  EXPECT_TRUE(shape_in_motion(s));
  EXPECT_TRUE(vacant_labels(s, kLabels, {}, 100, kTimeout).empty());
  mark_dead(s, 11);
  EXPECT_EQ(vacant_labels(s, kLabels, {}, 100, kTimeout), std::vector<int>{1});
}

TEST(Reserve, ADeadMembersLabelIsVacantWhileItsLastEntryIsStillFresh) {
  // Member 11 is marked dead with its holder entry younger than the label timeout: the label is vacant at
  // once (its holder is the member whose barrier entry names it), not label_timeout ticks later.
  Stigmergy s = moving_shape();
  mark_dead(s, 11);
  const LabelTicks since = {{0, 100}, {1, 100}, {2, 100}};
  EXPECT_EQ(vacant_labels(s, kLabels, since, 101, kTimeout), std::vector<int>{1});
}

TEST(Reserve, AClaimHoldsTheVacancyWhileItsHolderHeartbeats) {
  Stigmergy s = moving_shape();
  mark_dead(s, 11);
  put_label_holder(s, 1, 20);  // reserve 20 claims label 1 at tick 100
  const LabelTicks since = {{1, 100}};
  EXPECT_TRUE(vacant_labels(s, kLabels, since, 100 + kTimeout - 1, kTimeout).empty());
  // Silent for label_timeout ticks: it died on its way, the label is vacant again.
  EXPECT_EQ(vacant_labels(s, kLabels, since, 100 + kTimeout, kTimeout), std::vector<int>{1});
}

TEST(Reserve, AStaleEntryOfARobotThatDiedBeforeTheBarrierIsWithdrawn) {
  // Robot 9 held label 1 and died in Reached; 11 took the label over. Freeing 9's label withdrew 9's entry,
  // so 11's death leaves label 1 vacant (before, 9's entry, never marked dead, held it for good).
  Stigmergy s = moving_shape();
  barrier_enter(s, 9, 1);
  barrier_withdraw(s, 9);
  mark_dead(s, 11);
  EXPECT_EQ(vacant_labels(s, kLabels, {}, 100, kTimeout), std::vector<int>{1});
  EXPECT_FALSE(live_member_of(s, 1, 20).has_value());
}

TEST(Reserve, AReserveAtTheDeadMembersPlaceCountsAsAMember) {
  Stigmergy s = moving_shape();
  mark_dead(s, 11);
  put_label_holder(s, 1, 20);
  // Claimed but not yet at its place: not a member.
  EXPECT_EQ(motion_members(s, kAtReady), kAtReady);
  barrier_enter(s, 20, 1);
  auto members = motion_members(s, kAtReady);
  EXPECT_EQ(members.at(20), 1);
  EXPECT_EQ(members.count(11), 1u);  // still listed, marked dead
  EXPECT_FALSE(live_member_of(s, 1, 20).has_value());
}

TEST(Reserve, AMemberMarkedDeadByMistakeTakesItsLabelBack) {
  Stigmergy s = moving_shape();
  mark_dead(s, 11);
  put_label_holder(s, 1, 20);
  barrier_enter(s, 20, 1);
  s.put(stig::key(stig::Ns::Parents, 11), 10);  // 11 is alive: it rewrites its parents entry
  EXPECT_EQ(motion_members(s, kAtReady).count(20), 0u);
  EXPECT_EQ(live_member_of(s, 1, 20), std::optional<RobotId>{11});
  EXPECT_TRUE(vacant_labels(s, kLabels, {}, 100, kTimeout).empty());
}

TEST(Reserve, AReserveTrailsBehindTheShapeAndStaysOnItsSideAtTheGoal) {
  const Vec2 goal{10.0, 0.0};
  // Travelling: behind the shape, seen from the goal, radius + 1.5 spacings from its centroid.
  const Vec2 behind = trailing_point({4.0, 0.0}, 1.0, goal, {4.0, 5.0}, 1.0);
  EXPECT_NEAR(behind.x, 1.5, 1e-9);
  EXPECT_NEAR(behind.y, 0.0, 1e-9);
  // At the goal: on the reserve's own side.
  const Vec2 beside = trailing_point(goal, 1.0, goal, {10.0, -4.0}, 1.0);
  EXPECT_NEAR(beside.x, 10.0, 1e-9);
  EXPECT_NEAR(beside.y, -2.5, 1e-9);
}

}  // namespace
}  // namespace swarmform::controller
