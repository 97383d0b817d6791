// The lidar against hand-computed geometry (rays from the body's edge over the field of view, the range from
// the edge to the nearest body, clamped to [min_range, max_range], max_range when nothing is in range), its
// noise statistics, and the world computing it only for a behaviour that declares it.
#include "world_server/world/lidar.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "robot_agent/controller/builtins.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/ray_fan.hpp"
#include "world_server/world/rng.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using std::numbers::pi;
using testing::box;
using testing::cylinder;

// Seven rays over 180 degrees: -90, -60, ..., 90 degrees.
LidarSpec seven() {
  LidarSpec s;
  s.rays = 7;
  s.fov = pi;
  return s;
}

LidarScan scan_alone(const LidarSpec& spec, const std::vector<Obstacle>& statics, std::vector<Pose2D> poses) {
  Lidar lidar(spec, statics, 0.0, 1);
  SpatialGrid grid;
  grid.build(poses, 1.0);
  LidarScan out;
  lidar.read(0, poses, grid, out);
  return out;
}

TEST(Lidar, DefaultsAreArgosKheperaIVFan) {
  const LidarSpec d;
  EXPECT_EQ(d.rays, 682U);
  EXPECT_DOUBLE_EQ(d.fov, 210.0 * pi / 180.0);
  EXPECT_EQ(d.min_range, 0.02);
  EXPECT_EQ(d.max_range, 4.0);
  const LidarScan s = scan_alone(d, {}, {Pose2D{0.0, 0.0, 0.0}});
  ASSERT_EQ(s.size(), 682U);
  EXPECT_DOUBLE_EQ(s.front().angle, -105.0 * pi / 180.0);
  EXPECT_DOUBLE_EQ(s.back().angle, 105.0 * pi / 180.0);
  for (const LidarRay& r : s) EXPECT_EQ(r.range, 4.0);  // nothing in range: exactly max_range
}

TEST(Lidar, WallAtAKnownDistanceAndAngleIsSeenByTheRaysFacingIt) {
  // A long wall whose face is 0.5 m from the body's edge along the ray at +60 degrees (ray 5), facing it. A
  // ray at angle delta from that normal starts at R on the ring and meets the face's plane, R + d from the
  // centre, after (R + d) / cos(delta) - R.
  const double d = 0.5, normal = pi / 3.0, half_thickness = 0.05;
  const double c = kRobotRadius + d + half_thickness;
  const LidarScan s = scan_alone(
      seven(), {box(c * std::cos(normal), c * std::sin(normal), 2.0 * half_thickness, 4.0, normal)},
      {Pose2D{0.0, 0.0, 0.0}});
  ASSERT_EQ(s.size(), 7U);
  EXPECT_NEAR(s[5].angle, normal, 1e-15);
  EXPECT_NEAR(s[5].range, d, 1e-12);
  for (std::size_t k : {3, 4, 6}) {
    const double delta = s[k].angle - normal;
    EXPECT_NEAR(s[k].range, (kRobotRadius + d) / std::cos(delta) - kRobotRadius, 1e-12) << "ray " << k;
  }
  // Rays 0..2 (-90, -60, -30 degrees) point away from it or meet its plane past the wall's end / beyond
  // range.
  for (std::size_t k : {0, 1, 2}) EXPECT_EQ(s[k].range, 4.0) << "ray " << k;
}

TEST(Lidar, TurnedRobotSeesWithTheRayFacingTheWall) {
  // Heading +y; a wall 1 m beyond the edge along +y: the middle ray (angle 0) reads 1 m, the side rays
  // (+-90 degrees) run parallel to it.
  const LidarScan s =
      scan_alone(seven(), {box(0.0, kRobotRadius + 1.0 + 0.05, 4.0, 0.1)}, {Pose2D{0.0, 0.0, pi / 2.0}});
  EXPECT_NEAR(s[3].range, 1.0, 1e-12);
  EXPECT_EQ(s[0].range, 4.0);
  EXPECT_EQ(s[6].range, 4.0);
}

TEST(Lidar, RobotsAndCylindersAreSeenOwnBodyIsNotRangesAreClamped) {
  // Another robot straight ahead, 0.3 m between the bodies; a cylinder on the left (+90 degrees) 0.2 m away.
  const LidarScan s = scan_alone(seven(), {cylinder(0.0, kRobotRadius + 0.2 + 0.1, 0.1)},
                                 {Pose2D{0.0, 0.0, 0.0}, Pose2D{2.0 * kRobotRadius + 0.3, 0.0, 2.0}});
  EXPECT_NEAR(s[3].range, 0.3, 1e-12);
  EXPECT_NEAR(s[6].range, 0.2, 1e-12);
  EXPECT_EQ(s[0].range, 4.0);
  // Closer than min_range reads min_range; farther than max_range reads max_range.
  LidarSpec short_range = seven();
  short_range.min_range = 0.05;
  short_range.max_range = 0.25;
  const LidarScan c = scan_alone(short_range, {cylinder(0.0, kRobotRadius + 0.01 + 0.1, 0.1)},
                                 {Pose2D{0.0, 0.0, 0.0}, Pose2D{2.0 * kRobotRadius + 0.3, 0.0, 2.0}});
  EXPECT_EQ(c[6].range, 0.05);
  EXPECT_EQ(c[3].range, 0.25);
}

TEST(Lidar, TheFanFindsEachBodysRaysFromItsAngleAsTestingEveryRayDoes) {
  // A crowd of robots and obstacles round a robot, many headings: the rays the fan's angular culling keeps
  // give the very ranges that testing every ray gives.
  Rng rng(7, 0);
  std::vector<Obstacle> statics{box(1.5, 0.3, 0.4, 1.2, 0.7), cylinder(-1.0, -1.2, 0.3),
                                box(0.0, 3.0, 6.0, 0.1)};
  std::vector<StaticShape> shapes;
  for (const Obstacle& o : statics) shapes.push_back(make_static_shape(o));
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Pose2D> poses{Pose2D{0.0, 0.0, rng.uniform(-pi, pi)}};
    for (int j = 0; j < 30; ++j) poses.push_back(Pose2D{rng.uniform(-2.5, 2.5), rng.uniform(-2.5, 2.5), 0.0});
    SpatialGrid grid;
    grid.build(poses, 1.0);
    const std::size_t n = trial % 2 == 0 ? 682 : 100;
    const double fov = trial % 4 < 2 ? LidarSpec{}.fov : 2.0 * pi;
    const double step = fov / static_cast<double>(n - 1);
    std::vector<double> dx(n), dy(n), culled(n, kNoHit), every(n, kNoHit);
    for (std::size_t k = 0; k < n; ++k) {
      const double a = poses[0].theta - fov / 2.0 + step * static_cast<double>(k);
      dx[k] = std::cos(a);
      dy[k] = std::sin(a);
    }
    cast_ring_rays(0, poses, grid, shapes, 4.0, dx, dy, culled, FanAngles{poses[0].theta - fov / 2.0, step});
    cast_ring_rays(0, poses, grid, shapes, 4.0, dx, dy, every);
    for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(culled[k], every[k]) << "trial " << trial << " ray " << k;
  }
}

TEST(Lidar, NoiseIsUniformWithinTheLevelOnHitsOnlyAndFollowsTheSeed) {
  const std::vector<Obstacle> wall{box(kRobotRadius + 1.0 + 0.05, 0.0, 0.1, 4.0)};
  const std::vector<Pose2D> poses{Pose2D{0.0, 0.0, 0.0}};
  const std::vector<char> alive{1};
  SpatialGrid grid;
  grid.build(poses, 1.0);
  const double level = 0.05;
  Lidar noisy(seven(), wall, level, 42), same(seven(), wall, level, 42), other(seven(), wall, level, 43);
  std::vector<LidarScan> a, b, c;
  double sum = 0.0, sum2 = 0.0, lo = 1.0, hi = -1.0;
  bool other_differs = false;
  constexpr int kDraws = 4000;
  for (int i = 0; i < kDraws; ++i) {
    noisy.sense_all(poses, alive, grid, a);
    same.sense_all(poses, alive, grid, b);
    other.sense_all(poses, alive, grid, c);
    for (std::size_t k = 0; k < 7; ++k) ASSERT_EQ(a[0][k].range, b[0][k].range) << "draw " << i;
    other_differs = other_differs || c[0][3].range != a[0][3].range;
    const double e = a[0][3].range - 1.0;
    sum += e;
    sum2 += e * e;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
    EXPECT_EQ(a[0][0].range, 4.0);  // saw nothing: no noise
  }
  EXPECT_TRUE(other_differs);
  const double mean = sum / kDraws;
  const double sd = std::sqrt(sum2 / kDraws - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.0025);                   // 5 standard errors (0.05 / sqrt(3) / sqrt(4000))
  EXPECT_NEAR(sd, level / std::sqrt(3.0), 0.0015);  // uniform on [-0.05, 0.05]
  EXPECT_GE(lo, -level - 1e-12);
  EXPECT_LE(hi, level + 1e-12);
  EXPECT_LT(lo, -0.95 * level);
  EXPECT_GT(hi, 0.95 * level);
}

TEST(Lidar, WorldFillsItOnlyForABehaviourThatDeclaresIt) {
  behaviour::Descriptor with_lidar = controller::random_walk_descriptor();
  with_lidar.sensors = behaviour::kLidar;
  // Two robots face to face, 0.3 m between their bodies.
  auto two = [](const behaviour::Descriptor& d) {
    Scenario s = testing::open_scenario({Pose2D{0.0, 0.0, 0.0}, Pose2D{2.0 * kRobotRadius + 0.3, 0.0, pi}});
    s.lidar = seven();
    s.behaviour = &d;
    return s;
  };
  World with(two(with_lidar));
  ASSERT_EQ(with.perception(0).lidar.size(), 7U);
  EXPECT_NEAR(with.perception(0).lidar[3].range, 0.3, 1e-12);
  EXPECT_NEAR(with.perception(1).lidar[3].range, 0.3, 1e-12);
  with.step();
  EXPECT_EQ(with.perception(1).lidar.size(), 7U);
  World::PerceptionCopy copy;
  const LidarScan& copied = with.copy_perception(1, copy).lidar;
  ASSERT_EQ(copied.size(), 7U);
  for (std::size_t k = 0; k < 7; ++k) EXPECT_EQ(copied[k].range, with.perception(1).lidar[k].range);

  World without(two(controller::random_walk_descriptor()));
  EXPECT_TRUE(without.perception(0).lidar.empty());
  without.step();
  EXPECT_TRUE(without.perception(0).lidar.empty());
}

}  // namespace
}  // namespace swarmform::world
