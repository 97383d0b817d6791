// The light sensors against hand-computed geometry (ARGoS's Khepera IV formula: exp(-2 d / I) at the 3-D
// distance d, spread over the sensors within 90 degrees by 1 - 2 a / pi), occlusion by obstacles and robots
// as prisms of their height, the sum of sources and its clamp, the noise, and the world computing it only for
// a behaviour that declares it.
#include "world_server/world/light.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "robot_agent/controller/builtins.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using testing::box;

LightSource light(double x, double y, double height, double intensity = 1.0) {
  return LightSource{Vec2{x, y}, height, intensity};
}

LightReading read(const std::vector<LightSource>& lights, const std::vector<Obstacle>& statics,
                  std::vector<Pose2D> poses) {
  LightSensors s(lights, statics, 0.0, 1);
  SpatialGrid grid;
  grid.build(poses, 1.0);
  return s.read(0, poses, grid);
}

TEST(Light, LightAheadIsSpreadOverTheSensorsWithinNinetyDegrees) {
  const auto r = read({light(1.0, 0.0, 0.5)}, {}, {Pose2D{0.0, 0.0, 0.0}});
  const double v = std::exp(-2.0 * std::sqrt(1.0 + 0.25));
  EXPECT_NEAR(r[0], v, 1e-12);
  EXPECT_NEAR(r[1], v * 0.5, 1e-12);  // 45 degrees off: 1 - 2 (pi/4) / pi
  EXPECT_NEAR(r[7], v * 0.5, 1e-12);
  for (std::size_t k : {2, 3, 4, 5, 6}) EXPECT_NEAR(r[k], 0.0, 1e-12) << "sensor " << k;
}

TEST(Light, TurnedRobotAndIntensity) {
  // Facing +y with the light at +x, -90 degrees in its frame: sensor 6 (on its right).
  const auto r = read({light(1.0, 0.0, 0.0, 2.0)}, {}, {Pose2D{0.0, 0.0, std::numbers::pi / 2.0}});
  const double v = std::exp(-2.0 * 1.0 / 2.0);
  EXPECT_NEAR(r[6], v, 1e-12);
  EXPECT_NEAR(r[5], v * 0.5, 1e-12);
  EXPECT_NEAR(r[7], v * 0.5, 1e-12);
  EXPECT_NEAR(r[0], 0.0, 1e-12);
  // Past ARGoS's 2.5 (distance over intensity): nothing.
  EXPECT_EQ(read({light(2.6, 0.0, 0.0)}, {}, {Pose2D{0.0, 0.0, 0.0}}), LightReading{});
}

TEST(Light, ObstacleBetweenHidesTheLightUnlessTheRayPassesOverIt) {
  // A 0.5 m tall box (kStaticHeight) from x = 0.4 to 0.5 across the line to a light at x = 1.
  const std::vector<Obstacle> wall{box(0.45, 0.0, 0.1, 1.0)};
  EXPECT_EQ(read({light(1.0, 0.0, 0.5)}, wall, {Pose2D{0.0, 0.0, 0.0}}), LightReading{});
  // A light 2 m up: the ray enters the box at 0.4 of the way, 0.8 m up: over it.
  const auto over = read({light(1.0, 0.0, 2.0)}, wall, {Pose2D{0.0, 0.0, 0.0}});
  EXPECT_NEAR(over[0], std::exp(-2.0 * std::sqrt(5.0)), 1e-12);
  // Exactly at the top: 1.25 m up enters at 0.4 x 1.25 = 0.5 m: hidden (touching counts).
  EXPECT_EQ(read({light(1.0, 0.0, 1.25)}, wall, {Pose2D{0.0, 0.0, 0.0}}), LightReading{});
}

TEST(Light, AnotherRobotHidesALowLightNotAHighOne) {
  // A robot centred at x = 0.3: the ray enters its body at 0.3 - R = 0.2296 of a 1 m run.
  const std::vector<Pose2D> poses{Pose2D{0.0, 0.0, 0.0}, Pose2D{0.3, 0.0, 0.0}};
  EXPECT_EQ(read({light(1.0, 0.0, 0.1)}, {}, poses), LightReading{});  // 2.3 cm up: under its 5.3 cm top
  EXPECT_GT(read({light(1.0, 0.0, 1.0)}, {}, poses)[0], 0.0);          // 23 cm up: over it
  // The robot's own body never hides anything (the ray starts inside it).
  EXPECT_GT(read({light(1.0, 0.0, 0.1)}, {}, {Pose2D{0.0, 0.0, 0.0}})[0], 0.0);
}

TEST(Light, SourcesAddUpAndTheSumIsClampedToOne) {
  const auto one = read({light(0.5, 0.0, 0.0)}, {}, {Pose2D{0.0, 0.0, 0.0}});
  const auto two = read({light(0.5, 0.0, 0.0), light(0.0, 0.5, 0.0)}, {}, {Pose2D{0.0, 0.0, 0.0}});
  EXPECT_NEAR(two[1], 2.0 * one[1], 1e-12);  // 45 degrees from both
  EXPECT_EQ(read({light(0.0, 0.0, 0.01, 10.0), light(0.01, 0.0, 0.0, 10.0)}, {}, {Pose2D{}})[0], 1.0);
}

TEST(Light, NoiseStaysWithinTheLevelAndFollowsTheSeed) {
  const std::vector<LightSource> lights{light(1.0, 0.0, 0.0)};
  const std::vector<Pose2D> poses{Pose2D{}};
  const std::vector<char> alive{1};
  SpatialGrid grid;
  grid.build(poses, 1.0);
  const double clean = read(lights, {}, poses)[0];
  LightSensors a(lights, {}, 0.05, 3), b(lights, {}, 0.05, 3), c(lights, {}, 0.05, 4);
  std::vector<LightReading> ra, rb, rc;
  double sum = 0.0;
  bool differs = false;
  for (int i = 0; i < 2000; ++i) {
    a.sense_all(poses, alive, grid, ra);
    b.sense_all(poses, alive, grid, rb);
    c.sense_all(poses, alive, grid, rc);
    ASSERT_EQ(ra, rb);
    differs = differs || ra != rc;
    EXPECT_LE(std::abs(ra[0][0] - clean), 0.05);
    sum += ra[0][0] - clean;
  }
  EXPECT_TRUE(differs);
  EXPECT_NEAR(sum / 2000.0, 0.0, 0.003);  // 5 standard errors of a uniform +-0.05
}

TEST(Light, WorldFillsItOnlyForABehaviourThatDeclaresIt) {
  Scenario s = testing::open_scenario({Pose2D{}});
  s.lights.push_back(light(1.0, 0.0, 0.5));
  s.behaviour = &controller::random_walk_descriptor();
  EXPECT_FALSE(World(s).perception(0).light.has_value());
  const behaviour::Descriptor* photo = controller::builtin_registry().find("phototaxis");
  ASSERT_NE(photo, nullptr);
  s.behaviour = photo;
  World w(s);
  ASSERT_TRUE(w.perception(0).light.has_value());
  EXPECT_NEAR((*w.perception(0).light)[0], std::exp(-2.0 * std::sqrt(1.25)), 1e-12);
}

}  // namespace
}  // namespace swarmform::world
