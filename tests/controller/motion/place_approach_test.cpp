// The last ways out in the motion phase, as pure units: EchoMemory::gap_ahead (a gap between two
// obstacles is not a wall: no slide), PlaceApproach (the last approach and a cut-off robot's way: go round
// the echoes, a committed side, a detour; never stuck-handling within `there` of the place) and
// BoundaryFollower's kept side (Bug's memory: the turn-back counts from when the side was first taken, the
// exit from the episode's start).
#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <string>
#include <vector>

#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/place_approach.hpp"
#include "robot_agent/controller/vec2_math.hpp"
#include "robot_agent/controller/wall_follow.hpp"

namespace swarmform::controller::motion {
namespace {

EchoMemory memory_with(std::vector<std::pair<std::size_t, double>> echoes) {
  EchoMemory m;
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  for (const auto& [sensor, reading] : echoes) r[sensor] = reading;
  m.add(r, SensorMask{}, Pose2D{0.0, 0.0, 0.0}, 10, 0.6);
  return m;
}

TEST(EchoMemory, AGapAheadHasEchoesOnBothSidesAndNoneOnTheWay) {
  constexpr double kRange = 0.6, kClearance = 2 * kRobotRadius;
  auto both = memory_with({{1, 0.4}, {3, 0.4}});  // -45 and +45 degrees: two posts flanking the way
  EXPECT_TRUE(both.gap_ahead({0, 0}, {1, 0}, kRange, kClearance, 12, 15));
  auto one = memory_with({{3, 0.4}});  // one side only: a face beside or ahead, not a gap
  EXPECT_FALSE(one.gap_ahead({0, 0}, {1, 0}, kRange, kClearance, 12, 15));
  auto ahead = memory_with({{1, 0.4}, {2, 0.4}, {3, 0.4}});  // and one on the way: a wall
  EXPECT_FALSE(ahead.gap_ahead({0, 0}, {1, 0}, kRange, kClearance, 12, 15));
  EXPECT_FALSE(both.gap_ahead({0, 0}, {1, 0}, kRange, kClearance, 40, 15));  // forgotten
}

TEST(EchoMemory, TheSurfaceAgainstAWallIsAlongItsNormalNotBesideTheRobot) {
  // Pressed against a wall ahead (+x), every cone that sees it reads the minimum range: the +-90 degree
  // sensors' echo points lie beside the robot, as near as the front one. The nearest of them alone could be
  // either; the surface lies along the wall's normal, at the nearest echo's distance.
  auto m = memory_with({{0, kUltrasonicMinRange},
                        {1, kUltrasonicMinRange},
                        {2, kUltrasonicMinRange},
                        {3, kUltrasonicMinRange},
                        {4, kUltrasonicMinRange}});
  const auto s = m.surface({0, 0}, 12, 1.0, 15);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->x, kUltrasonicMinRange + kRobotRadius, 1e-9);
  EXPECT_NEAR(s->y, 0.0, 1e-9);
  // One echo alone is its own surface.
  auto one = memory_with({{3, 0.4}});
  const auto e = one.nearest({0, 0}, 12, 1.0, 15);
  const auto t = one.surface({0, 0}, 12, 1.0, 15);
  ASSERT_TRUE(e && t);
  EXPECT_NEAR(t->x, e->x, 1e-12);
  EXPECT_NEAR(t->y, e->y, 1e-12);
  EXPECT_FALSE(one.surface({0, 0}, 12, 0.3, 15).has_value());  // none within reach
}

TEST(PlaceApproach, FreeWayIsTheDesiredVelocity) {
  PlaceApproach a;
  std::mt19937_64 rng(1);
  std::vector<std::string> events;
  const Vec2 v = a.step({0, 0}, {2, 0}, {0.1, 0}, 0, {}, std::nullopt, {}, rng, events);
  EXPECT_NEAR(v.x, 0.1, 1e-12);
  EXPECT_NEAR(v.y, 0.0, 1e-12);
}

TEST(PlaceApproach, StuckItCommitsToASideThenDetoursButNeverAtItsPlace) {
  // An echo straight ahead, the robot held where it is: no progress.
  const std::vector<NeighbourPosition> wall{{0.45, 0.0, RightOfWay::Mutual, true}};
  PlaceApproach a;
  std::mt19937_64 rng(7);
  std::vector<std::string> events;
  Tick detour_at = 0;
  for (Tick t = 0; t < 400 && detour_at == 0; ++t) {
    a.step({0, 0}, {2, 0}, {0.1, 0}, t, wall, std::nullopt, {}, rng, events);
    if (!events.empty()) detour_at = t;
  }
  EXPECT_EQ(detour_at, 250u);  // 50 ticks to commit to a side, 200 on it, then the detour
  EXPECT_TRUE(a.detouring());
  // Within `there` of its place a robot is settling, never stuck.
  PlaceApproach b;
  events.clear();
  for (Tick t = 0; t < 1000; ++t)
    b.step({0, 0}, {0.05, 0}, {0.01, 0}, t, wall, std::nullopt, {}, rng, events);
  EXPECT_TRUE(events.empty());
  EXPECT_FALSE(b.detouring());
}

TEST(PlaceApproach, StuckFarFromItsPlaceItFollowsTheBoundaryUntilNearerThanWhereItBegan) {
  // A robot on its own inside a U open towards it: its place lies beyond the U's base, 5 m away. Random
  // detours of 1 m never leave the U; following the base's boundary (Bug2) does, and it keeps following
  // until it is nearer its place than where it began.
  const std::vector<NeighbourPosition> ahead{{0.45, 0.0, RightOfWay::Mutual, true}};
  const std::optional<Vec2> base = Vec2{0.45, 0.0};
  PlaceApproachParams params;
  params.bug_from = 0.9;
  params.bug = {0.47, 0.1, 1.0, 20, 1200};
  PlaceApproach a;
  std::mt19937_64 rng(7);
  std::vector<std::string> events;
  Tick started = 0;
  for (Tick t = 0; t < 400 && started == 0; ++t) {
    a.step({0, 0}, {5, 0}, {0.1, 0}, t, ahead, base, params, rng, events);
    if (!events.empty()) started = t;
  }
  EXPECT_EQ(started, 250u);  // 50 ticks to commit to a side, 200 on it, then the boundary, not a detour
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].rfind("boundary_follow_start", 0), 0u);
  EXPECT_TRUE(a.detouring());
  // In the U's corner, following the arm above it: the pull leads away from the arm, but it is no nearer
  // its place than where it began: it stays on.
  events.clear();
  a.step({0.2, 2.0}, {5, 0}, {0.096, -0.04}, 300, {}, Vec2{0.2, 2.47}, params, rng, events);
  EXPECT_TRUE(events.empty());
  EXPECT_TRUE(a.detouring());
  // Round the base, nearer than where it began (by more than `there`), the way clear: it leaves.
  a.step({1.0, 0.6}, {5, 0}, {0.1, 0}, 301, {}, Vec2{0.45, 0.0}, params, rng, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0], "boundary_follow_end");
  EXPECT_FALSE(a.detouring());
}

TEST(BoundaryFollower, AKeptSideTurnsBackFromWhenItWasFirstTaken) {
  BoundaryFollower f;
  const BoundaryFollowParams p{0.4, 0.1, 1.0, 20, 600};
  f.start(1, 1000, Tick{500});  // pinned again at 1000, on this side since 500
  Vec2 v;
  // Desired motion away from the echo: the exit waits min_ticks from this episode's start, not from 500.
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {-1.0, 0.0}, 1010, p, v));
  EXPECT_FALSE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {-1.0, 0.0}, 1020, p, v));
  // Into the obstacle: it turns back at 500 + max_ticks.
  f.start(1, 1050, Tick{500});
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, 1099, p, v));
  EXPECT_EQ(f.side(), 1);
  ASSERT_TRUE(f.update(Vec2{1.0, 0.0}, {0.6, 0.0}, {1.0, 0.0}, 1100, p, v));
  EXPECT_EQ(f.side(), -1);
}

}  // namespace
}  // namespace swarmform::controller::motion
