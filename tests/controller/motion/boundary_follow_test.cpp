// BoundaryFollower (wall_follow.hpp): the way round a pinned robot commits to, the velocity that keeps the
// obstacle at a fixed distance (the middle of a passage narrower than two of it), the exit once the way is
// clear, the turn back after a dead end; and EchoMemory::nearest and ::across, the remembered points it
// follows.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/vec2_math.hpp"
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

TEST(BoundaryFollower, KeepsToTheMiddleOfAPassageNarrowerThanTwoKeeps) {
  // A dead robot's body in a 2 m opening leaves two passages 0.93 m wide: a robot fits, but a follower that
  // keeps 0.47 m from the nearest echo takes both sides for one obstacle and goes round them (narrow_gap.yaml
  // --seed 63 --kill 5@167 --kill 4@1242: the robots behind the wall toured the arena for good).
  const BoundaryFollowParams p{0.47, 0.1, 1.0, 20, 600};
  Vec2 v;
  // The surface 0.4 m on the right (-y), the far side 0.4 m on the left: the middle, so no push either way.
  BoundaryFollower f;
  f.start(-1, 0);
  ASSERT_TRUE(f.update(Vec2{0.0, -0.4}, {0.0, 0.0}, {1.0, 0.0}, 1, p, v, false, 0.4));
  EXPECT_NEAR(v.y, 0.0, 1e-9);
  EXPECT_NEAR(std::abs(v.x), 0.1, 1e-9);
  // Without the far side it keeps 0.47 m from the surface: pushed 7 cm into the other side's way.
  BoundaryFollower g;
  g.start(-1, 0);
  ASSERT_TRUE(g.update(Vec2{0.0, -0.4}, {0.0, 0.0}, {1.0, 0.0}, 1, p, v, false));
  EXPECT_GT(v.y, 0.04);
  // A far side beyond two keeps is no passage: the same as none.
  BoundaryFollower h;
  h.start(-1, 0);
  Vec2 w;
  ASSERT_TRUE(h.update(Vec2{0.0, -0.4}, {0.0, 0.0}, {1.0, 0.0}, 1, p, w, false, 0.6));
  EXPECT_NEAR(w.y, v.y, 1e-9);
}

TEST(BoundaryFollower, InAPassageTheWayOnHoldsWhenTheNearestSurfaceChangesSides) {
  // In the middle of a passage the nearest echo jumps from one side to the other; with the same hand on the
  // other side the tangent reversed, and the robot stood in the passage (posts and bodies).
  const BoundaryFollowParams p{0.47, 0.1, 1.0, 20, 600};
  BoundaryFollower f;
  f.start(-1, 0);
  Vec2 v;
  ASSERT_TRUE(f.update(Vec2{0.0, -0.41}, {0.0, 0.0}, {1.0, 0.0}, 1, p, v, false, 0.43));
  const double way = v.x;
  ASSERT_GT(std::abs(way), 0.05);
  ASSERT_TRUE(f.update(Vec2{0.02, 0.41}, {0.02, 0.0}, {1.0, 0.0}, 2, p, v, false, 0.43));
  EXPECT_GT(v.x * way, 0.0);  // still the same way along the passage
  EXPECT_EQ(f.side(), 1);     // the other hand
  // Outside a passage a change of side is a new surface to go round: the hand stays.
  BoundaryFollower g;
  g.start(-1, 0);
  ASSERT_TRUE(g.update(Vec2{0.0, -0.41}, {0.0, 0.0}, {1.0, 0.0}, 1, p, v));
  ASSERT_TRUE(g.update(Vec2{0.02, 0.41}, {0.02, 0.0}, {1.0, 0.0}, 2, p, v));
  EXPECT_EQ(g.side(), -1);
}

TEST(BoundaryFollower, GoingRoundOnTheSpotClosesThePassagesThenCountsAsALoop) {
  // In a cell of posts and bodies smaller than a keep the middles of its gaps made a loop on the spot, and
  // a robot circled there for good (posts.yaml --seed 70 --kill 0@1956 --kill 8@2362).
  const BoundaryFollowParams p{0.47, 0.1, 1.0, 20, 600};
  BoundaryFollower f;
  f.start(-1, 0);
  Vec2 v;
  const Vec2 into{0.0, -0.1};  // the desired motion leads into the surface: no leaving on that account
  ASSERT_TRUE(f.update(Vec2{0.0, -0.4}, {0.0, 0.0}, into, 1, p, v, false, 0.4));
  EXPECT_NEAR(v.y, 0.0, 1e-9);  // the passage's middle
  ASSERT_TRUE(f.update(Vec2{0.0, -0.4}, {0.0, 0.0}, into, 100, p, v, false, 0.4));
  EXPECT_NEAR(v.y, 0.0, 1e-9);
  // 100 ticks with no way made: the passages are closed, it keeps its keep from the surface again.
  ASSERT_TRUE(f.update(Vec2{0.0, -0.4}, {0.0, 0.0}, into, 101, p, v, false, 0.4));
  ASSERT_TRUE(f.update(Vec2{0.0, -0.4}, {0.0, 0.0}, into, 102, p, v, false, 0.4));
  EXPECT_GT(v.y, 0.04);
  EXPECT_FALSE(f.looped());
  // 100 more: it has gone round all it can; it leaves as soon as the way is clear, whatever the caller says.
  ASSERT_TRUE(f.update(Vec2{0.0, -0.4}, {0.0, 0.0}, into, 201, p, v, false, 0.4));
  EXPECT_TRUE(f.looped());
  EXPECT_FALSE(f.update(Vec2{0.0, -0.4}, {0.0, 0.0}, {0.1, 0.0}, 202, p, v, false, 0.4));
  // An episode that never took a passage is not judged by its way made (a follower held by its neighbours).
  BoundaryFollower h;
  h.start(-1, 0);
  for (Tick t = 1; t <= 301; t += 100)
    ASSERT_TRUE(h.update(Vec2{0.0, -0.4}, {0.0, 0.0}, into, t, p, v, false));
  EXPECT_FALSE(h.looped());
  // A robot that makes its way (a metre in 100 ticks) keeps its passages.
  BoundaryFollower g;
  g.start(-1, 0);
  ASSERT_TRUE(g.update(Vec2{0.0, -0.4}, {0.0, 0.0}, into, 1, p, v, false, 0.4));
  ASSERT_TRUE(g.update(Vec2{1.0, -0.4}, {1.0, 0.0}, into, 101, p, v, false, 0.4));
  EXPECT_NEAR(v.y, 0.0, 1e-9);
  ASSERT_TRUE(g.update(Vec2{2.0, -0.4}, {2.0, 0.0}, into, 201, p, v, false, 0.4));
  EXPECT_FALSE(g.looped());
}

TEST(EchoMemory, AcrossIsTheNearestEchoOnTheFarSideOfTheRobot) {
  EchoMemory m;
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  SensorMask mask{};
  r[0] = 0.33;  // right: a surface 0.4 m off (reading + body radius)
  r[4] = 0.43;  // left: the far side, 0.5 m off
  m.add(r, mask, Pose2D{0.0, 0.0, 0.0}, 10, 1.0);
  const Vec2 surface{0.0, -(0.33 + kRobotRadius)};
  const auto across = m.across({0.0, 0.0}, surface, 20, 1.0, 60);
  ASSERT_TRUE(across.has_value());
  EXPECT_NEAR(*across, 0.43 + kRobotRadius, 1e-9);
  EXPECT_FALSE(m.across({0.0, 0.0}, surface, 20, 0.4, 60).has_value());  // out of reach
  // Only the surface itself on its side: nothing across.
  EchoMemory one;
  r[4] = kUltrasonicMaxRange;
  one.add(r, mask, Pose2D{0.0, 0.0, 0.0}, 10, 1.0);
  EXPECT_FALSE(one.across({0.0, 0.0}, surface, 20, 1.0, 60).has_value());
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
