// BoundaryFollower (wall_follow.hpp): the way round a pinned robot commits to, the velocity that keeps the
// obstacle at a fixed distance, the exit once the way is clear, the turn back after a dead end; and
// EchoMemory::nearest, the remembered point it follows.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

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

TEST(BoundaryFollower, EachTurnBackSearchesTwiceAsLongAsTheOneBefore) {
  // A fixed period turned a leader back before it could round a long wall; doubling searches a boundary of
  // any length both ways in the end.
  BoundaryFollower f;
  const BoundaryFollowParams p{0.4, 0.1, 1.0, 20, 100};
  f.start(1, 0);
  Vec2 v;
  std::vector<Tick> turns;
  int side = f.side();
  for (Tick t = 1; t <= 1600; ++t) {
    ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, t, p, v));
    if (f.side() != side) turns.push_back(t);
    side = f.side();
  }
  EXPECT_EQ(turns, (std::vector<Tick>{100, 300, 700, 1500}));
  EXPECT_EQ(f.turns(), 4);
  // Pinned again by the same obstacle, the memory carries the count on.
  f.start(side, 1600, Tick{1500}, f.turns());
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, 3099, p, v));
  EXPECT_EQ(f.side(), side);
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, 3100, p, v));
  EXPECT_EQ(f.side(), -side);
}

TEST(BoundaryFollower, AllTheWayRoundItLeavesAsSoonAsTheWayIsClear) {
  // A post whose far side is blocked: Bug2 never gets nearer, and round the post it comes back to where it
  // began. From then on the caller's veto no longer holds it.
  BoundaryFollower f;
  const BoundaryFollowParams p{0.4, 0.1, 1.0, 20, 6000};
  const Vec2 post{0.0, 0.0};
  f.start(1, 0);
  Vec2 v;
  ASSERT_TRUE(f.update(post, {0.6, 0.0}, {-1.0, 0.0}, 1, p, v, false));     // into the post: follows
  ASSERT_TRUE(f.update(post, {-0.6, 0.0}, {-1.0, 0.0}, 100, p, v, false));  // the far side
  EXPECT_FALSE(f.looped());
  // Round again to where it began, the way clear (desired away from the post): vetoed until now, it leaves.
  EXPECT_FALSE(f.update(post, {0.6, 0.1}, {1.0, 0.0}, 200, p, v, false));
  EXPECT_TRUE(f.looped());
  // A turn-back passes back over the start: that is no loop.
  BoundaryFollower g;
  const BoundaryFollowParams q{0.4, 0.1, 1.0, 20, 100};
  g.start(1, 0);
  ASSERT_TRUE(g.update(post, {0.6, 0.0}, {-1.0, 0.0}, 1, q, v, false));
  ASSERT_TRUE(g.update(post, {0.0, 1.5}, {-1.0, 0.0}, 100, q, v, false));  // turns back here
  ASSERT_TRUE(g.update(post, {0.6, 0.1}, {-1.0, 0.3}, 150, q, v, false));
  EXPECT_FALSE(g.looped());
}

TEST(BoundaryFollower, StaysOnTheBoundaryWhileTheCallerForbidsLeaving) {
  // Bug2: round a U's corner the pull points away from the arm it now follows, but the robot is no nearer
  // its goal than where it began; leaving there took it back into the U.
  BoundaryFollower f;
  const BoundaryFollowParams p{0.4, 0.1, 1.0, 20, 600};
  f.start(1, 0);
  Vec2 v;
  EXPECT_TRUE(f.update(Vec2{1.0, 0.0}, {1.2, -0.4}, {1.0, 0.0}, 40, p, v, /*may_leave=*/false));
  EXPECT_TRUE(f.active());
  EXPECT_FALSE(f.update(Vec2{1.0, 0.0}, {1.2, -0.4}, {1.0, 0.0}, 41, p, v, /*may_leave=*/true));
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
