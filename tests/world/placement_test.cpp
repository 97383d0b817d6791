// Random placement at scale: the separation grid finds every close robot however the robots crowd (a
// grid sized from the region's area lets robots grown from one another in a large region crowd a few cells,
// and 100000 of them in a 10 km region then take minutes to place; the grid changes no pose).
#include "world_server/world/placement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "world_server/world/scenario.hpp"

namespace swarmform::world {
namespace {

// The smallest distance between two of `poses` (a sweep along x: O(n log n) for spread-out points).
double min_distance(std::vector<Pose2D> poses) {
  std::sort(poses.begin(), poses.end(), [](const Pose2D& a, const Pose2D& b) { return a.x < b.x; });
  double best = INFINITY;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    for (std::size_t j = i + 1; j < poses.size() && poses[j].x - poses[i].x < best; ++j) {
      best = std::min(best, std::hypot(poses[j].x - poses[i].x, poses[j].y - poses[i].y));
    }
  }
  return best;
}

TEST(Placement, ManyRobotsInALargeRegionKeepTheirSeparation) {
  Scenario s;
  s.walls = false;
  s.arena_width = s.arena_height = 2000.0;
  const PlacementRegion region{Vec2{-300.0, 250.0}, 2000.0, 2000.0};
  const auto poses = place_randomly(20000, region, s, 7);
  ASSERT_TRUE(poses.has_value());
  ASSERT_EQ(poses->size(), 20000u);
  for (const Pose2D& p : *poses) {
    ASSERT_LE(std::abs(p.x - region.centre.x), region.width / 2.0);
    ASSERT_LE(std::abs(p.y - region.centre.y), region.height / 2.0);
  }
  EXPECT_GE(min_distance(*poses), kMinSeparation);
}

TEST(Placement, RobotsPackedIntoASmallRegionKeepTheirSeparation) {
  Scenario s;
  const PlacementRegion region{Vec2{1.0, -1.0}, 6.0, 6.0};
  const auto poses = place_randomly(120, region, s, 3);
  ASSERT_TRUE(poses.has_value());
  EXPECT_GE(min_distance(*poses), kMinSeparation);
}

}  // namespace
}  // namespace swarmform::world
