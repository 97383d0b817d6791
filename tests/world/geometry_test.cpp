// The analytic geometry under the sensors and the medium.
#include "world_server/world/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_scenarios.hpp"
#include "world_server/world/rng.hpp"

namespace swarmform::world {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Geometry, FastAtan2MatchesLibmEverywhere) {
  double worst = 0.0;
  for (int i = 0; i < 3600; ++i) {  // every 0.1 degree, at several radii
    const double a = -kPi + i * (2.0 * kPi / 3600.0);
    for (double r : {1e-6, 0.3, 1.0, 2.9, 1e4}) {
      const double y = r * std::sin(a), x = r * std::cos(a);
      worst = std::max(worst, std::abs(wrap_angle(fast_atan2(y, x) - std::atan2(y, x))));
    }
  }
  Rng rng(1, 1);
  for (int i = 0; i < 200000; ++i) {
    const double y = rng.uniform(-5, 5), x = rng.uniform(-5, 5);
    worst = std::max(worst, std::abs(fast_atan2(y, x) - std::atan2(y, x)));
  }
  EXPECT_LT(worst, 1e-13);
  // The axes and the octant boundaries exactly where libm puts them.
  EXPECT_EQ(fast_atan2(0.0, 1.0), 0.0);
  EXPECT_NEAR(fast_atan2(1.0, 0.0), kPi / 2.0, 1e-13);
  EXPECT_NEAR(fast_atan2(0.0, -1.0), kPi, 1e-13);
  EXPECT_NEAR(fast_atan2(-1.0, 0.0), -kPi / 2.0, 1e-13);
  EXPECT_NEAR(fast_atan2(1.0, 1.0), kPi / 4.0, 1e-13);
  EXPECT_NEAR(fast_atan2(-1.0, -1.0), -3.0 * kPi / 4.0, 1e-13);
}

TEST(Geometry, WrapAngleIntoMinusPiPi) {
  EXPECT_EQ(wrap_angle(0.5), 0.5);
  EXPECT_NEAR(wrap_angle(kPi + 0.1), -kPi + 0.1, 1e-12);
  EXPECT_NEAR(wrap_angle(-kPi - 0.1), kPi - 0.1, 1e-12);
  EXPECT_EQ(wrap_angle(-kPi), kPi);  // (-pi, pi]: -pi becomes pi
  EXPECT_NEAR(wrap_angle(7.0 * kPi + 0.2), -kPi + 0.2, 1e-9);
  EXPECT_NEAR(wrap_angle(1000.0), std::remainder(1000.0, 2.0 * kPi), 1e-9);
}

TEST(Geometry, RaysAgainstCirclesAndBoxes) {
  EXPECT_NEAR(ray_circle(0, 0, 1, 0, 3, 0, 1), 2.0, 1e-12);
  EXPECT_EQ(ray_circle(0, 0, -1, 0, 3, 0, 1), kNoHit);  // pointing away
  EXPECT_EQ(ray_circle(0, 0, 0, 1, 3, 0, 1), kNoHit);   // passing by
  EXPECT_EQ(ray_circle(3, 0, 1, 0, 3, 0, 1), 0.0);      // starting inside
  const StaticShape b =
      make_static_shape(testing::box(5, 0, 2, 2, kPi / 4.0));  // a diamond, corner at x=5-sqrt2
  EXPECT_NEAR(ray_box(0, 0, 1, 0, b), 5.0 - std::sqrt(2.0), 1e-12);
  EXPECT_EQ(ray_box(0, 3, 1, 0, b), kNoHit);
  EXPECT_EQ(ray_box(5, 0, 1, 0, b), 0.0);
  const StaticShape wall = make_static_shape(testing::box(0, 2, 10, 0.1));
  EXPECT_NEAR(ray_box(0, 0, 0, 1, wall), 1.95, 1e-12);
  EXPECT_NEAR(ray_box(0, 0, std::cos(kPi / 4), std::sin(kPi / 4), wall), 1.95 * std::sqrt(2.0), 1e-12);
}

TEST(Geometry, SegmentsAndClearances) {
  const StaticShape b = make_static_shape(testing::box(1, 0, 0.2, 1));
  EXPECT_TRUE(segment_blocked(0, 0, 2, 0, b));
  EXPECT_FALSE(segment_blocked(0, 0, 0.85, 0, b));   // stops short of it
  EXPECT_FALSE(segment_blocked(0, 0.6, 2, 0.6, b));  // passes beside it
  EXPECT_NEAR(point_clearance(0, 0, b), 0.9, 1e-12);
  EXPECT_NEAR(point_clearance(1, 0, b), -0.1, 1e-12);  // inside: minus the depth
  EXPECT_NEAR(point_clearance(2.1, 1.5, b), std::hypot(1.0, 1.0), 1e-12);
  const StaticShape c = make_static_shape(testing::cylinder(0, 0, 0.5));
  EXPECT_NEAR(point_clearance(2, 0, c), 1.5, 1e-12);
}

TEST(Geometry, WallsSitOutsideTheArena) {
  Scenario s;
  s.arena_centre = Vec2{1, 2};
  s.arena_width = 4;
  s.arena_height = 2;
  const auto statics = static_obstacles(s);
  ASSERT_EQ(statics.size(), 4u);
  // Inside the arena every wall is clear; just outside an edge, a wall is touched.
  for (const Obstacle& o : statics) EXPECT_GE(point_clearance(1, 2, make_static_shape(o)), 0.99);
  double min_out = kNoHit;
  for (const Obstacle& o : statics)
    min_out = std::min(min_out, point_clearance(3.05, 2, make_static_shape(o)));
  EXPECT_LT(min_out, 0.0);
  s.walls = false;
  EXPECT_TRUE(static_obstacles(s).empty());
}

}  // namespace
}  // namespace swarmform::world
