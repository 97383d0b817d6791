// The infrared proximity ring against hand-computed geometry (ARGoS's Khepera IV numbers: ring on the body's
// edge, 8 sensors from angle 0 every 45 degrees, 0.12 m range, reading 4.14 exp(-33 d) - 0.085 clamped to
// [0, 1], 1 under 0.04 m), its noise statistics, and the world computing it only for a behaviour that
// declares it.
#include "world_server/world/proximity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/builtins.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using testing::box;
using testing::cylinder;

// The reading ARGoS's Khepera IV gives at d metres from the sensor, written out again here.
double argos(double d) {
  return 4.14 * std::exp(-33.0 * d) - 0.085;
}

ProximityReading read_alone(const std::vector<Obstacle>& statics, std::vector<Pose2D> poses) {
  Proximity p(statics, 0.0, 1);
  SpatialGrid grid;
  grid.build(poses, 1.0);
  return p.read(0, poses, grid);
}

TEST(Proximity, ReadingConventionIsArgosKheperaIV) {
  EXPECT_EQ(proximity_value(0.0), 1.0);
  EXPECT_EQ(proximity_value(0.039), 1.0);
  EXPECT_DOUBLE_EQ(proximity_value(0.05), argos(0.05));
  EXPECT_DOUBLE_EQ(proximity_value(0.08), argos(0.08));
  EXPECT_EQ(proximity_value(0.121), 0.0);
  EXPECT_EQ(proximity_value(kNoHit), 0.0);
  EXPECT_EQ(proximity_value(0.119), 0.0);  // the fit dips under 0 near the range: clamped
}

TEST(Proximity, WallAheadIsSeenByTheFrontSensorAndAtFortyFiveDegrees) {
  // The wall's face 6 cm in front of the front sensor (at x = R).
  const double gap = 0.06;
  const double face = kRobotRadius + gap;
  const auto r = read_alone({box(face + 0.5, 0.0, 1.0, 4.0)}, {Pose2D{0.0, 0.0, 0.0}});
  EXPECT_NEAR(r[0], argos(gap), 1e-12);
  // The 45-degree sensors sit at R (cos 45, +-sin 45) and look along 45 degrees: they meet the face
  // after (face - R cos 45) / cos 45.
  const double c = std::cos(std::numbers::pi / 4.0);
  const double d45 = (face - kRobotRadius * c) / c;
  ASSERT_LT(d45, kProximityRange);
  EXPECT_NEAR(r[1], argos(d45), 1e-12);
  EXPECT_NEAR(r[7], argos(d45), 1e-12);
  for (std::size_t k : {2, 3, 4, 5, 6}) EXPECT_EQ(r[k], 0.0) << "sensor " << k;
}

TEST(Proximity, TurnedRobotSeesTheWallWithTheSensorFacingIt) {
  // Heading +y: sensor 2 (+90 degrees) looks along -x; a wall 2 cm from it saturates it.
  const auto r = read_alone({box(-(kRobotRadius + 0.02) - 0.5, 0.0, 1.0, 4.0)},
                            {Pose2D{0.0, 0.0, std::numbers::pi / 2.0}});
  EXPECT_EQ(r[2], 1.0);
  EXPECT_EQ(r[0], 0.0);
  EXPECT_EQ(r[6], 0.0);
}

TEST(Proximity, OtherRobotsAndCylindersAreSeenOwnBodyIsNot) {
  EXPECT_EQ(read_alone({}, {Pose2D{0.0, 0.0, 0.3}}), ProximityReading{});
  // A robot behind (sensor 4, 180 degrees), 5 cm between the bodies.
  const auto r = read_alone({}, {Pose2D{0.0, 0.0, 0.0}, Pose2D{-(2.0 * kRobotRadius + 0.05), 0.0, 1.0}});
  EXPECT_NEAR(r[4], argos(0.05), 1e-12);
  EXPECT_EQ(r[0], 0.0);
  // A cylinder at -90 degrees, 0.1 m away: the right sensor (6).
  const auto c = read_alone({cylinder(0.0, -(kRobotRadius + 0.1 + 0.2), 0.2)}, {Pose2D{0.0, 0.0, 0.0}});
  EXPECT_NEAR(c[6], argos(0.1), 1e-12);
  // Just out of range.
  const auto far = read_alone({cylinder(kRobotRadius + 0.125 + 0.2, 0.0, 0.2)}, {Pose2D{0.0, 0.0, 0.0}});
  EXPECT_EQ(far, ProximityReading{});
}

TEST(Proximity, NoiseIsUniformWithinTheLevelAndFollowsTheSeed) {
  // A wall where the noiseless front reading is about 0.5: the noise (level 0.2) is never clamped there.
  const double gap = std::log(4.14 / 0.585) / 33.0;
  const std::vector<Obstacle> wall{box(kRobotRadius + gap + 0.5, 0.0, 1.0, 4.0)};
  const std::vector<Pose2D> poses{Pose2D{0.0, 0.0, 0.0}};
  const std::vector<char> alive{1};
  SpatialGrid grid;
  grid.build(poses, 1.0);
  const ProximityReading clean_all = read_alone(wall, poses);
  const double clean = clean_all[0];
  Proximity noisy(wall, 0.2, 42), same(wall, 0.2, 42), other(wall, 0.2, 43);
  std::vector<ProximityReading> a, b, c;
  double sum = 0.0, sum2 = 0.0, lo = 1.0, hi = 0.0;
  bool other_differs = false;
  constexpr int kDraws = 4000;
  for (int i = 0; i < kDraws; ++i) {
    noisy.sense_all(poses, alive, grid, a);
    same.sense_all(poses, alive, grid, b);
    other.sense_all(poses, alive, grid, c);
    ASSERT_EQ(a, b) << "draw " << i;  // the same seed, the same stream
    other_differs = other_differs || c[0] != a[0];
    const double e = a[0][0] - clean;
    sum += e;
    sum2 += e * e;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
    for (std::size_t k = 1; k < kProximityCount; ++k) {
      // Readings of 0 get noise too (ARGoS adds it to every reading), clamped at 0.
      EXPECT_GE(a[0][k], std::max(0.0, clean_all[k] - 0.2));
      EXPECT_LE(a[0][k], clean_all[k] + 0.2);
    }
  }
  EXPECT_TRUE(other_differs);
  const double mean = sum / kDraws;
  const double sd = std::sqrt(sum2 / kDraws - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.01);                  // 5 standard errors (0.2 / sqrt(3) / sqrt(4000))
  EXPECT_NEAR(sd, 0.2 / std::sqrt(3.0), 0.006);  // uniform on [-0.2, 0.2]
  EXPECT_GE(lo, -0.2);
  EXPECT_LE(hi, 0.2);
  EXPECT_LT(lo, -0.19);
  EXPECT_GT(hi, 0.19);
}

Scenario two_facing(const behaviour::Descriptor& d) {
  // Two robots face to face, 3 cm between their bodies.
  Scenario s = testing::open_scenario({Pose2D{0.0, 0.0, 0.0}, Pose2D{2.0 * kRobotRadius + 0.03, 0.0, 0.0}});
  s.behaviour = &d;
  return s;
}

TEST(Proximity, WorldFillsItOnlyForABehaviourThatDeclaresIt) {
  const auto& registry = controller::builtin_registry();
  const behaviour::Descriptor* diffusion = registry.find("diffusion");
  ASSERT_NE(diffusion, nullptr);
  ASSERT_TRUE(diffusion->sensors & behaviour::kProximity);
  World with(two_facing(*diffusion));
  ASSERT_TRUE(with.perception(0).proximity.has_value());
  EXPECT_EQ((*with.perception(0).proximity)[0], 1.0);  // 3 cm: saturated
  EXPECT_EQ((*with.perception(1).proximity)[4], 1.0);
  with.step();
  EXPECT_TRUE(with.perception(1).proximity.has_value());
  World::PerceptionCopy copy;
  EXPECT_EQ(with.copy_perception(1, copy).proximity, with.perception(1).proximity);

  World without(two_facing(controller::random_walk_descriptor()));
  EXPECT_FALSE(without.perception(0).proximity.has_value());
  without.step();
  EXPECT_FALSE(without.perception(0).proximity.has_value());
}

}  // namespace
}  // namespace swarmform::world
