// Issue 17's last ways out in the motion phase, as pure units: EchoMemory::gap_ahead (a gap between two
// obstacles is not a wall: no slide), PlaceApproach (the last approach and a cut-off robot's way: go round
// the echoes, a committed side, a detour; never stuck-handling within `there` of the place) and
// BoundaryFollower's kept side (Bug's memory: the turn-back counts from when the side was first taken, the
// exit from the episode's start).
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "robot_agent/controller/motion_math.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/place_approach.hpp"
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

TEST(PlaceApproach, FreeWayIsTheDesiredVelocity) {
  PlaceApproach a;
  std::mt19937_64 rng(1);
  std::vector<std::string> events;
  const Vec2 v = a.step({0, 0}, {2, 0}, {0.1, 0}, 0, {}, {}, rng, events);
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
    a.step({0, 0}, {2, 0}, {0.1, 0}, t, wall, {}, rng, events);
    if (!events.empty()) detour_at = t;
  }
  EXPECT_EQ(detour_at, 250u);  // 50 ticks to commit to a side, 200 on it, then the detour
  EXPECT_TRUE(a.detouring());
  // Within `there` of its place a robot is settling, never stuck.
  PlaceApproach b;
  events.clear();
  for (Tick t = 0; t < 1000; ++t) b.step({0, 0}, {0.05, 0}, {0.01, 0}, t, wall, {}, rng, events);
  EXPECT_TRUE(events.empty());
  EXPECT_FALSE(b.detouring());
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
