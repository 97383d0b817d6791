// BoundaryFollower (wall_follow.hpp): the way round a pinned robot commits to, the velocity that keeps the
// obstacle at a fixed distance, the exit once the way is clear, the turn back after a dead end; and
// EchoMemory::nearest, the remembered point it follows.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "robot_agent/controller/motion_math.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/wall_follow.hpp"

namespace swarmform::controller::motion {
namespace {

TEST(BoundaryFollower, SideIsTheTangentNearerTheDesiredMotionAndATieGoesToTheDraw) {
  // Obstacle point straight ahead (+x); desired up and ahead: counter-clockwise about the point is +y from
  // the robot's side (-x of the point): u = (-1, 0), u turned +pi/2 = (0, -1), so "up" is clockwise (-1).
  EXPECT_EQ(BoundaryFollower::choose_side({0, 0}, {1, 0}, {1, 0.5}, 1), -1);
  EXPECT_EQ(BoundaryFollower::choose_side({0, 0}, {1, 0}, {1, -0.5}, 1), 1);
  // Head-on: the draw decides.
  EXPECT_EQ(BoundaryFollower::choose_side({0, 0}, {1, 0}, {1, 0}, 1), 1);
  EXPECT_EQ(BoundaryFollower::choose_side({0, 0}, {1, 0}, {1, 0}, -1), -1);
}

TEST(BoundaryFollower, GoesAlongTheObstacleAtSpeedAndHoldsItsDistance) {
  BoundaryFollower f;
  const BoundaryFollowParams p{0.4, 0.1, 1.0, 20, 600};
  f.start(1, 0);
  Vec2 v;
  // At the kept distance: pure tangent, at the speed.
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, 1, p, v));
  EXPECT_NEAR(vnorm(v), 0.1, 1e-9);
  EXPECT_NEAR(v.x, 0.0, 1e-9);
  EXPECT_LT(v.y, 0.0);  // counter-clockwise about (1, 0) from its -x side: downwards
  // Too close: the velocity also leads away from the obstacle.
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.8, 0.0}, {1.0, 0.0}, 2, p, v));
  EXPECT_LT(v.x, 0.0);
}

TEST(BoundaryFollower, LeavesWhenTheDesiredMotionNoLongerLeadsIntoTheObstacle) {
  BoundaryFollower f;
  const BoundaryFollowParams p{0.4, 0.1, 1.0, 20, 600};
  f.start(1, 0);
  Vec2 v;
  // Still into it.
  EXPECT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.2}, 30, p, v));
  // Round the corner: the obstacle now behind-left, the desired motion ahead and away from it.
  EXPECT_FALSE(f.update(Vec2{1.0, 0.0}, {1.2, -0.4}, {1.0, 0.0}, 40, p, v));
  EXPECT_FALSE(f.active());
  // Nothing remembered near: it leaves too.
  f.start(1, 50);
  EXPECT_FALSE(f.update(std::nullopt, {0.0, 0.0}, {1.0, 0.0}, 51, p, v));
}

TEST(BoundaryFollower, TurnsBackAfterMaxTicksOneWay) {
  BoundaryFollower f;
  const BoundaryFollowParams p{0.4, 0.1, 1.0, 20, 100};
  f.start(1, 0);
  Vec2 v;
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, 99, p, v));
  EXPECT_EQ(f.side(), 1);
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, 100, p, v));
  EXPECT_EQ(f.side(), -1);
  EXPECT_GT(v.y, 0.0);
}

TEST(EchoMemory, NearestIsTheClosestRecentEchoWithinReach) {
  EchoMemory m;
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  SensorMask mask{};
  r[2] = 0.5;  // the front sensor
  m.add(r, mask, Pose2D{0.0, 0.0, 0.0}, 10, 0.6);
  const auto near = m.nearest({0.0, 0.0}, 20, 1.0, 60);
  ASSERT_TRUE(near.has_value());
  EXPECT_NEAR(near->x, 0.5 + kRobotRadius, 1e-9);
  EXPECT_FALSE(m.nearest({0.0, 0.0}, 20, 0.3, 60).has_value());   // out of reach
  EXPECT_FALSE(m.nearest({0.0, 0.0}, 100, 1.0, 60).has_value());  // forgotten
}

}  // namespace
}  // namespace swarmform::controller::motion
