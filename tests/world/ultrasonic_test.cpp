// Ultrasonic sensors: distances from the robot's surface, the range clamp, own body excluded, all bodies
// seen.
#include "world_server/world/ultrasonic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_scenarios.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using testing::box;
using testing::cylinder;

constexpr std::size_t kFront = 2;  // kUltrasonicAngles[2] == 0
constexpr std::size_t kLeft = 4;   // +pi/2
constexpr std::size_t kRight = 0;  // -pi/2

UltrasonicReading read_alone(const std::vector<Obstacle>& statics, const Pose2D& pose) {
  Ultrasonic u(statics, 0.0, 1);
  std::vector<Pose2D> poses{pose};
  SpatialGrid grid;
  grid.build(poses, 1.0);
  return u.read(0, poses, grid);
}

TEST(Ultrasonic, BoxOneMetreFromTheSurfaceReadsOneMetre) {
  // The box's near face is 1.00 m from the robot's surface (centre + radius + 1.00).
  const double face = kRobotRadius + 1.0;
  const auto r = read_alone({box(face + 0.5, 0.0, 1.0, 4.0)}, Pose2D{0.0, 0.0, 0.0});
  EXPECT_NEAR(r[kFront], 1.00, 0.01);
  EXPECT_EQ(r[kRight], kUltrasonicMaxRange);
  EXPECT_EQ(r[kLeft], kUltrasonicMaxRange);
}

TEST(Ultrasonic, RotatedRobotLeftSensorSeesWallOnItsLeft) {
  // Robot facing +y at the origin: its left (+pi/2) looks along -x. Wall face 1.00 m from its surface there.
  const double face = -(kRobotRadius + 1.0);
  const auto r = read_alone({box(face - 0.5, 0.0, 1.0, 4.0)}, Pose2D{0.0, 0.0, std::numbers::pi / 2.0});
  EXPECT_NEAR(r[kLeft], 1.00, 0.01);
  EXPECT_EQ(r[kRight], kUltrasonicMaxRange);
}

TEST(Ultrasonic, CylinderAndRotatedBoxSeen) {
  const auto c = read_alone({cylinder(kRobotRadius + 1.0 + 0.3, 0.0, 0.3)}, Pose2D{0.0, 0.0, 0.0});
  EXPECT_NEAR(c[kFront], 1.00, 0.01);
  // A box turned 45 degrees with a corner pointing at the robot, 0.8 m from its surface.
  const double half = 0.5;
  const double corner = kRobotRadius + 0.8;
  const auto b = read_alone({box(corner + half * std::sqrt(2.0), 0.0, 1.0, 1.0, std::numbers::pi / 4.0)},
                            Pose2D{0.0, 0.0, 0.0});
  EXPECT_NEAR(b[kFront], 0.80, 0.01);
}

TEST(Ultrasonic, NothingInRangeReadsExactlyTheMaximum) {
  const auto none = read_alone({}, Pose2D{0.0, 0.0, 0.3});
  for (double v : none) EXPECT_EQ(v, kUltrasonicMaxRange);
  // A wall 2.5 m from the surface: beyond range.
  const auto far = read_alone({box(kRobotRadius + 2.5 + 0.5, 0.0, 1.0, 1.0)}, Pose2D{0.0, 0.0, 0.0});
  EXPECT_EQ(far[kFront], kUltrasonicMaxRange);
}

TEST(Ultrasonic, TooCloseClampsToTheMinimum) {
  const auto r = read_alone({box(kRobotRadius + 0.1 + 0.5, 0.0, 1.0, 1.0)}, Pose2D{0.0, 0.0, 0.0});
  EXPECT_EQ(r[kFront], kUltrasonicMinRange);
}

TEST(Ultrasonic, ConeSeesAnObjectOffTheAxis) {
  // A thin post 1 m away on the cone's rays at +-7.5 and +-15 degrees off the front axis is seen by the front
  // sensor; at 22 degrees it is between the front cone and the 45-degree cone (30..60): seen by neither.
  const double d = kRobotRadius + 1.0 + 0.02;
  auto post_at = [&](double deg) {
    const double a = deg * std::numbers::pi / 180.0;
    return read_alone({cylinder(d * std::cos(a), d * std::sin(a), 0.02)}, Pose2D{0.0, 0.0, 0.0});
  };
  for (double deg : {7.5, -7.5, 15.0, -15.0}) EXPECT_NEAR(post_at(deg)[kFront], 1.0, 0.01) << deg;
  for (double v : post_at(22.0)) EXPECT_EQ(v, kUltrasonicMaxRange);
  EXPECT_NEAR(post_at(52.5)[3], 1.0, 0.01);  // the 45-degree sensor's outer-middle ray
  // Behind the robot: not seen.
  for (double v : post_at(180.0)) EXPECT_EQ(v, kUltrasonicMaxRange);
}

TEST(Ultrasonic, NeverSeesItsOwnBodyButSeesOtherRobots) {
  Ultrasonic u({}, 0.0, 1);
  // Robot 1 sits 0.6 m ahead of robot 0 (centres), i.e. 0.6 - 2 radii surface to surface.
  std::vector<Pose2D> poses{Pose2D{0.0, 0.0, 0.0}, Pose2D{0.6, 0.0, 0.0}};
  SpatialGrid grid;
  grid.build(poses, 1.0);
  const auto r0 = u.read(0, poses, grid);
  EXPECT_NEAR(r0[kFront], 0.6 - 2.0 * kRobotRadius, 0.01);
  const auto r1 = u.read(1, poses, grid);  // robot 1 faces away: sees nothing, and never itself
  for (double v : r1) EXPECT_EQ(v, kUltrasonicMaxRange);
}

TEST(Ultrasonic, ADeadRobotIsSeen) {
  Scenario s = testing::open_scenario({Pose2D{0.0, 0.0, 0.0}, Pose2D{0.8, 0.0, 0.0}});
  World w(s);
  w.kill(1);
  w.step();
  EXPECT_NEAR(w.perception(0).ultrasonic[kFront], 0.8 - 2.0 * kRobotRadius, 0.01);
}

TEST(Ultrasonic, NoiseHasTheScenariosStandardDeviation) {
  const double sd = 0.05;
  Ultrasonic u({box(kRobotRadius + 1.0 + 0.5, 0.0, 1.0, 4.0)}, sd, 7);
  std::vector<Pose2D> poses{Pose2D{0.0, 0.0, 0.0}};
  std::vector<char> alive{1};
  SpatialGrid grid;
  grid.build(poses, 1.0);
  std::vector<UltrasonicReading> out;
  double sum = 0.0, sum2 = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    u.sense_all(poses, alive, grid, out);
    sum += out[0][kFront];
    sum2 += out[0][kFront] * out[0][kFront];
    EXPECT_EQ(out[0][kLeft], kUltrasonicMaxRange);  // nothing seen stays exact
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 1.0, 0.003);
  EXPECT_NEAR(std::sqrt(sum2 / n - mean * mean), sd, 0.1 * sd);
}

}  // namespace
}  // namespace swarmform::world
