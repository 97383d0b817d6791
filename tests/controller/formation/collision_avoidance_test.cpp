// Collision avoidance before Ready (eq. 1 and the task switch), with the controller's additions: the right of
// way that breaks symmetric deadlocks, the ultrasonic echoes no heard neighbour explains, the committed side.
#include <gtest/gtest.h>

#include <array>

#include "robot_agent/controller/collision_avoidance.hpp"

namespace swarmform::controller {
namespace {

constexpr double kK = 0.002, kRo = 0.35, kMax = 0.1;

TEST(CollisionAvoidance, FarNeighboursChangeNothing) {
  const Vec2 v = avoid_collisions({0.1, 0.0}, {{2.0, 0.0}}, kK, kRo, kMax);
  EXPECT_DOUBLE_EQ(v.x, 0.1);
  EXPECT_DOUBLE_EQ(v.y, 0.0);
}

// Two robots 0.45 m apart heading for each other: by the mutual rule each goes round (no progress into the
// other); with the right of way, the one that has it keeps going, the other backs away.
TEST(CollisionAvoidance, TheRightOfWayDecidesWhoGivesWay) {
  const Vec2 mutual = avoid_collisions({0.1, 0.0}, {{0.45, 0.0, RightOfWay::Mutual}}, kK, kRo, kMax);
  EXPECT_LE(mutual.x, 1e-9);
  EXPECT_GT(std::abs(mutual.y), 0.05);
  const Vec2 ours = avoid_collisions({0.1, 0.0}, {{0.45, 0.0, RightOfWay::Ours}}, kK, kRo, kMax);
  EXPECT_NEAR(ours.x, 0.1, 1e-9);
  const Vec2 theirs = avoid_collisions({0.1, 0.0}, {{0.45, 0.0, RightOfWay::Theirs}}, kK, kRo, kMax);
  EXPECT_LT(theirs.x, -0.05) << "it backs away";
  // Inside r_o eq. (1) still keeps the one with the right of way off the other.
  const Vec2 pushed = avoid_collisions({0.1, 0.0}, {{0.3, 0.0, RightOfWay::Ours}}, kK, kRo, kMax);
  EXPECT_LE(pushed.x, 1e-9);
}

// Backing away does not drive the robot into a third one: the go-round applies to the retreat too.
TEST(CollisionAvoidance, BackingAwayKeepsOffTheOthers) {
  const Vec2 v = avoid_collisions(
      {0.0, 0.0}, {{0.45, 0.0, RightOfWay::Theirs}, {0.4, 3.14159265, RightOfWay::Mutual}}, kK, kRo, kMax);
  EXPECT_GE(v.x, -1e-9) << "no progress towards the robot behind";
}

TEST(CollisionAvoidance, EchoesThatAHeardNeighbourExplainsAreLeftOut) {
  std::array<double, kUltrasonicCount> readings;
  readings.fill(kUltrasonicMaxRange);
  readings[2] = 0.3;  // the front sensor (0 rad)
  // Nobody heard there: an obstacle, kept as a robot standing at the echo.
  auto echoes = unexplained_echoes(readings, 0.0, {}, 0.5);
  ASSERT_EQ(echoes.size(), 1u);
  EXPECT_NEAR(echoes[0].range, 0.3 + 2 * kRobotRadius, 1e-12);
  EXPECT_NEAR(echoes[0].azimuth, 0.0, 1e-12);
  EXPECT_TRUE(echoes[0].echo);
  // A robot heard right there explains it.
  EXPECT_TRUE(unexplained_echoes(readings, 0.0, {{0.3 + 2 * kRobotRadius, 0.05}}, 0.5).empty());
  // A robot heard there but further away does not: something stands between us.
  EXPECT_EQ(unexplained_echoes(readings, 0.0, {{1.2, 0.0}}, 0.5).size(), 1u);
  // Beyond max_echo: left out.
  EXPECT_TRUE(unexplained_echoes(readings, 0.0, {}, 0.3).empty());
}

// A committed side goes round an echo on that side whatever the goal's side; robots heard keep the goal's.
TEST(CollisionAvoidance, ACommittedSideAppliesToEchoes) {
  const NeighbourPosition echo{0.45, 0.0, RightOfWay::Mutual, true};
  const Vec2 goal_side = avoid_collisions({0.1, 0.05}, {echo}, kK, kRo, kMax, 0);
  const Vec2 right = avoid_collisions({0.1, 0.05}, {echo}, kK, kRo, kMax, +1);
  const Vec2 left = avoid_collisions({0.1, 0.05}, {echo}, kK, kRo, kMax, -1);
  EXPECT_GT(goal_side.y, 0.0);
  EXPECT_LT(right.y, 0.0);
  EXPECT_GT(left.y, 0.0);
  const NeighbourPosition robot{0.45, 0.0, RightOfWay::Mutual, false};
  EXPECT_GT(avoid_collisions({0.1, 0.05}, {robot}, kK, kRo, kMax, +1).y, 0.0);
  EXPECT_GT(avoid_collisions({0.1, 0.05}, {robot}, kK, kRo, kMax, -1).y, 0.0);
  // A robot heard straight between us and the goal: the right by default, the left with side -1.
  EXPECT_LT(avoid_collisions({0.1, 0.0}, {robot}, kK, kRo, kMax, 0).y, 0.0);
  EXPECT_LT(avoid_collisions({0.1, 0.0}, {robot}, kK, kRo, kMax, +1).y, 0.0);
  EXPECT_GT(avoid_collisions({0.1, 0.0}, {robot}, kK, kRo, kMax, -1).y, 0.0);
}

}  // namespace
}  // namespace swarmform::controller
