// Physics: differential-drive kinematics, walls that stop robots (no tunnelling), dead bodies, contact
// onsets.
#include "world_server/world/physics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_scenarios.hpp"

namespace swarmform::world {
namespace {

using testing::box;
using testing::open_scenario;

void run_ticks(Physics& p, int ticks) {
  for (int t = 0; t < ticks; ++t) p.tick_forward();
}

TEST(Physics, StraightRunCoversSpeedTimesTime) {
  for (double heading : {0.0, 0.7, -2.5}) {
    Physics p(open_scenario({Pose2D{1.0, -2.0, heading}}));
    p.set_wheels(0, 0.1, 0.1);
    run_ticks(p, 100);  // 10 s at 10 ticks/s
    const Pose2D q = p.pose(0);
    const double along = (q.x - 1.0) * std::cos(heading) + (q.y + 2.0) * std::sin(heading);
    const double across = -(q.x - 1.0) * std::sin(heading) + (q.y + 2.0) * std::cos(heading);
    EXPECT_NEAR(along, 1.0, 0.01) << "heading " << heading;
    EXPECT_NEAR(across, 0.0, 1e-3);
    EXPECT_NEAR(q.theta, heading, 1e-6);
  }
}

TEST(Physics, SpinningInPlaceKeepsPositionAndTurnsAtWheelRate) {
  Physics p(open_scenario({Pose2D{0.5, 0.5, 0.0}}));
  p.set_wheels(0, -0.05, 0.05);  // w = 0.1 / 0.1054 rad/s
  run_ticks(p, 10);              // 1 s
  const Pose2D q = p.pose(0);
  EXPECT_NEAR(q.x, 0.5, 1e-4);
  EXPECT_NEAR(q.y, 0.5, 1e-4);
  EXPECT_NEAR(q.theta, 0.1 / kWheelSpacing, 0.01 * 0.1 / kWheelSpacing);
  run_ticks(p, 200);  // many turns
  EXPECT_NEAR(p.pose(0).x, 0.5, 1e-3);
  EXPECT_NEAR(p.pose(0).y, 0.5, 1e-3);
}

TEST(Physics, HeadingStaysAUnitRotationOverALongSpin) {
  // 20,000 substeps of turning (physics.cpp integrates the heading as a plane rotation of the basis): the
  // heading is where the wheel rate puts it, and a straight run after it still covers speed x time to 1e-9
  // (the wheels' velocity is taken from the basis, so a basis that had grown or shrunk would scale it).
  Physics p(open_scenario({Pose2D{0.5, 0.5, 0.0}}));
  const double w = 0.2 / kWheelSpacing;
  p.set_wheels(0, -0.1, 0.1);
  run_ticks(p, 2000);  // 200 s
  const double turned = std::remainder(w * 200.0, 2.0 * std::numbers::pi);
  EXPECT_NEAR(std::remainder(p.pose(0).theta - turned, 2.0 * std::numbers::pi), 0.0, 1e-6);
  const Pose2D start = p.pose(0);
  p.set_wheels(0, 0.1, 0.1);
  run_ticks(p, 100);  // 10 s at 0.1 m/s
  EXPECT_NEAR(std::hypot(p.pose(0).x - start.x, p.pose(0).y - start.y), 1.0, 1e-9);
}

TEST(Physics, ArcFollowsTheDifferentialDriveCircle) {
  // l = 0.05, r = 0.1: v = 0.075, w = 0.05/0.1054; radius v/w. After a quarter turn the robot is at (R, R).
  Physics p(open_scenario({Pose2D{0.0, 0.0, 0.0}}));
  p.set_wheels(0, 0.05, 0.1);
  const double w = 0.05 / kWheelSpacing;
  const double radius = 0.075 / w;
  const int ticks = static_cast<int>(std::lround(std::numbers::pi / 2.0 / w * 10.0));
  run_ticks(p, ticks);
  const double turned = ticks * 0.1 * w;
  EXPECT_NEAR(p.pose(0).x, radius * std::sin(turned), 0.01 * radius);
  EXPECT_NEAR(p.pose(0).y, radius * (1.0 - std::cos(turned)), 0.01 * radius);
}

// A robot driven at a wall ends against it, on the near side, whatever the speed.
void expect_stopped_by_wall(double speed, double wall_thickness) {
  Scenario s = open_scenario({Pose2D{0.0, 0.0, 0.0}});
  const double face = 1.0;  // the wall's near face at x = 1
  s.obstacles.push_back(box(face + wall_thickness / 2.0, 0.0, wall_thickness, 2.0));
  Physics p(s);
  p.set_wheels(0, speed, speed);
  run_ticks(p, static_cast<int>(30.0 / speed) + 10);  // long enough to go 3 m
  const Pose2D q = p.pose(0);
  EXPECT_LE(q.x, face - kRobotRadius + 0.006) << "speed " << speed;
  EXPECT_GE(q.x, face - kRobotRadius - 0.006) << "speed " << speed;
  EXPECT_NEAR(q.y, 0.0, 1e-3);
}

TEST(Physics, WallStopsARobotWithoutTunnelling) {
  expect_stopped_by_wall(0.1, 0.1);
  expect_stopped_by_wall(1.0, 0.1);
  expect_stopped_by_wall(1.0, 0.02);  // a thin wall at 1 m/s: 1 cm per substep
}

TEST(Physics, ArenaWallsHoldRobotsIn) {
  Scenario s = open_scenario({Pose2D{0.0, 0.0, std::numbers::pi}});
  s.walls = true;
  s.arena_centre = Vec2{0.0, 0.0};
  s.arena_width = 4.0;
  s.arena_height = 4.0;
  Physics p(s);
  p.set_wheels(0, 1.0, 1.0);
  run_ticks(p, 50);
  EXPECT_NEAR(p.pose(0).x, -2.0 + kRobotRadius, 0.006);
  EXPECT_EQ(p.onsets_robot_obstacle(), 0u);  // onset counted once, when it began, not every tick
}

TEST(Physics, ContactOnsetsCountedOncePerPair) {
  // Two robots drive head-on and keep pushing: one robot-robot onset, on the tick they meet.
  Physics p(open_scenario({Pose2D{0.0, 0.0, 0.0}, Pose2D{1.0, 0.0, std::numbers::pi}}));
  p.set_wheels(0, 0.1, 0.1);
  p.set_wheels(1, 0.1, 0.1);
  std::uint32_t rr = 0, ro = 0;
  for (int t = 0; t < 80; ++t) {
    p.tick_forward();
    rr += p.onsets_robot_robot();
    ro += p.onsets_robot_obstacle();
  }
  EXPECT_EQ(rr, 1u);
  EXPECT_EQ(ro, 0u);
  // Neither passed through the other.
  EXPECT_LT(p.pose(0).x, p.pose(1).x);
  EXPECT_GT(p.pose(1).x - p.pose(0).x, 2.0 * kRobotRadius - 0.006);
}

TEST(Physics, DeadRobotIsAnImmovableBodyCountedAsObstacle) {
  Physics p(open_scenario({Pose2D{0.0, 0.0, 0.0}, Pose2D{1.0, 0.0, 0.0}}));
  p.set_dead(1, true);
  p.set_wheels(0, 0.2, 0.2);
  std::uint32_t rr = 0, ro = 0;
  for (int t = 0; t < 80; ++t) {
    p.tick_forward();
    rr += p.onsets_robot_robot();
    ro += p.onsets_robot_obstacle();
  }
  EXPECT_EQ(p.pose(1).x, 1.0);  // not pushed at all
  EXPECT_EQ(p.pose(1).y, 0.0);
  EXPECT_NEAR(p.pose(0).x, 1.0 - 2.0 * kRobotRadius, 0.006);
  EXPECT_EQ(rr, 0u);
  EXPECT_EQ(ro, 1u);
  // Alive again: it drives (robot 0 stops pushing it first).
  p.set_wheels(0, 0.0, 0.0);
  p.set_dead(1, false);
  p.set_wheels(1, 0.1, 0.1);
  run_ticks(p, 10);
  EXPECT_NEAR(p.pose(1).x, 1.1, 0.002);
}

TEST(Physics, StaysPlanar) {
  // A crowd pushing into each other: headings stay finite and positions stay apart.
  std::vector<Pose2D> poses;
  for (int i = 0; i < 10; ++i) poses.push_back(Pose2D{0.3 * i, 0.05 * (i % 2), 0.0});
  Physics p(open_scenario(poses));
  for (int i = 0; i < 10; ++i) p.set_wheels(static_cast<RobotId>(i), i < 5 ? 0.2 : -0.2, i < 5 ? 0.2 : -0.2);
  run_ticks(p, 100);
  std::vector<Pose2D> q;
  p.read_poses(q);
  for (int i = 0; i < 10; ++i) {
    for (int j = i + 1; j < 10; ++j) {
      EXPECT_GT(std::hypot(q[i].x - q[j].x, q[i].y - q[j].y), 2.0 * kRobotRadius - 0.01) << i << " " << j;
    }
  }
}

}  // namespace
}  // namespace swarmform::world
