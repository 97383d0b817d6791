// A moved goal's turn (shape_turn.hpp), each rule on its own: nothing before the goal moves, a follower's
// push off a surface (its torque, kept with the surface, dropped when no turn can bring its place in), and
// the leader's turn (started only while it stands at the goal, by the sign of the pushes' net torque, shared
// in the stigmergy and applied by every robot).
#include "robot_agent/controller/shape_turn.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace swarmform::controller::motion {
namespace {

constexpr Vec2 kFirstGoal{10.0, 0.0};
constexpr Vec2 kMovedGoal{5.0, 3.5};
constexpr std::uint32_t kBlocked = 6;  // the Blocked namespace (stigmergy.hpp)

// A follower at (0, 5.5) beneath a wall at y = 6, its place 1 m beyond it at (0, 7), the live centroid 3 m
// below the place (offset (1, 3)): the push off the wall (downwards) turns the shape about the centroid.
PushView under_a_wall() {
  PushView v;
  v.position = {0.0, 5.5};
  v.place = {0.0, 7.0};
  v.place_still = true;
  v.offset = {1.0, 3.0};
  v.surface = [] { return std::optional<Vec2>(Vec2{0.0, 6.0}); };
  v.large = true;
  v.arrival_tolerance = 0.05;
  return v;
}

std::int64_t published(ShapeTurn& turn, const PushView& view, Stigmergy& st) {
  std::vector<std::string> events;
  turn.push(view);
  turn.publish(3, st, events);
  return st.get(stig::key(kBlocked, 3)).value_or(0);
}

TEST(ShapeTurn, NothingHappensBeforeTheGoalMoves) {
  ShapeTurn turn(kFirstGoal);
  Stigmergy st;
  turn.observe(kFirstGoal, st);
  EXPECT_FALSE(turn.goal_moved());
  EXPECT_EQ(published(turn, under_a_wall(), st), 0);
  EXPECT_FALSE(st.get(stig::key(kBlocked, 3)).has_value());  // not even a 0 is written
  EXPECT_DOUBLE_EQ(turn.turned({1.0, 2.0}).x, 1.0);
}

TEST(ShapeTurn, APlaceBeyondASurfacePushesWithTheTorqueAboutTheCentroidAndKeepsIt) {
  ShapeTurn turn(kFirstGoal);
  Stigmergy st;
  turn.observe(kMovedGoal, st);
  // offset (1, 3) x push (0, -1) = 1 * -1 - 3 * 0 = -1 m.
  EXPECT_EQ(published(turn, under_a_wall(), st), -1000);
  // The sonars no longer see the wall (the robot turned away): the surface and its torque are kept.
  PushView away = under_a_wall();
  away.surface = [] { return std::optional<Vec2>(); };
  away.large = false;
  turn.observe(kMovedGoal, st);
  EXPECT_EQ(published(turn, away, st), -1000);
  // Its place brought a body radius to this side of the wall: free.
  away.place = {0.0, 5.8};
  turn.observe(kMovedGoal, st);
  EXPECT_EQ(published(turn, away, st), 0);
}

TEST(ShapeTurn, OnlyALargeObstacleBetweenTheRobotAndItsStillPlaceBlocks) {
  Stigmergy st;
  for (int k = 0; k < 3; ++k) {
    ShapeTurn turn(kFirstGoal);
    turn.observe(kMovedGoal, st);
    PushView v = under_a_wall();
    if (k == 0) v.large = false;        // a small obstacle (a body) is gone round
    if (k == 1) v.place_still = false;  // the place still moves with its parent
    if (k == 2) v.surface = [] { return std::optional<Vec2>(Vec2{0.0, 4.5}); };  // behind the robot
    turn.push(v);
    std::vector<std::string> events;
    turn.publish(3, st, events);
    EXPECT_EQ(st.get(stig::key(kBlocked, 3)).value_or(0), 0) << "case " << k;
  }
}

TEST(ShapeTurn, APlaceNoTurnCanBringInDoesNotPush) {
  // The centroid stands 5 m beyond the wall, the place's offset 3.2 m: its circle about the centroid never
  // reaches this side (a robot left before a wall the shape has passed: it is to go round it).
  ShapeTurn turn(kFirstGoal);
  Stigmergy st;
  turn.observe(kMovedGoal, st);
  PushView v = under_a_wall();
  v.place = {0.0, 7.0};
  v.offset = {1.0, -4.0};  // centroid at (-1, 11)
  EXPECT_EQ(published(turn, v, st), 0);
  v.offset = {1.0, -0.5};  // centroid at (-1, 7.5): 1.5 m beyond, offset 1.1 m: still none
  EXPECT_EQ(published(turn, v, st), 0);
  v.offset = {1.0, 3.0};  // centroid at (-1, 4) on this side
  EXPECT_NE(published(turn, v, st), 0);
}

TEST(ShapeTurn, TheLeaderStartsOnlyAtTheGoalTurnsByTheNetTorqueAndEveryRobotAppliesIt) {
  ShapeTurn leader(kFirstGoal);
  Stigmergy st;
  st.put(stig::key(kBlocked, 3), 1500);   // a long lever one way
  st.put(stig::key(kBlocked, 4), -200);   // a push nearly straight out, the other way
  st.put(stig::key(kBlocked, 5), -5000);  // a dead member's: not counted
  const auto counts = [](RobotId id) { return id != 5; };
  std::vector<std::string> events;
  leader.observe(kMovedGoal, st);
  leader.lead(st, counts, /*standing=*/false, 0.1, 10.0, 2.0, events);
  EXPECT_FALSE(st.get(stig::key(stig::Ns::Leader, 1)).has_value()) << "turned on the way";
  leader.lead(st, counts, /*standing=*/true, 0.1, 10.0, 2.0, events);
  // +1300 mm: the positive way, the outermost place (2 m out) at half of 0.01 m a tick.
  const double rate = 0.5 * 0.1 / 10.0 / 2.0;
  ASSERT_TRUE(st.get(stig::key(stig::Ns::Leader, 1)).has_value());
  EXPECT_EQ(*st.get(stig::key(stig::Ns::Leader, 1)), std::llround(rate / 1e-6));
  EXPECT_EQ(events, std::vector<std::string>{"shape_turning 1"});
  // Once turning it goes on while it follows its own turned place (not standing).
  leader.observe(kMovedGoal, st);
  leader.lead(st, counts, /*standing=*/false, 0.1, 10.0, 2.0, events);
  EXPECT_EQ(*st.get(stig::key(stig::Ns::Leader, 1)), 2 * std::llround(rate / 1e-6));
  // Every robot reads the one value and turns its offsets by it.
  ShapeTurn member(kFirstGoal);
  member.observe(kMovedGoal, st);
  const Vec2 v = member.turned({1.0, 0.0});
  EXPECT_NEAR(std::atan2(v.y, v.x), static_cast<double>(2 * std::llround(rate / 1e-6)) * 1e-6, 1e-12);
  const Vec2 back = member.unturned(v);
  EXPECT_NEAR(back.x, 1.0, 1e-12);
  // No push left: it stops, and starts again only at the goal.
  st.put(stig::key(kBlocked, 3), 0);
  st.put(stig::key(kBlocked, 4), 0);
  leader.lead(st, counts, false, 0.1, 10.0, 2.0, events);
  st.put(stig::key(kBlocked, 3), 700);
  leader.lead(st, counts, false, 0.1, 10.0, 2.0, events);
  EXPECT_EQ(*st.get(stig::key(stig::Ns::Leader, 1)), 2 * std::llround(rate / 1e-6));
}

}  // namespace
}  // namespace swarmform::controller::motion
