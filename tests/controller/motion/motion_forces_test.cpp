// Unit tests of the motion forces: eq. (2)-(5) formation, eq. (3) goal, eq. (6)-(7) obstacles with
// Algorithm 2's mask, the size discrimination and the wall-following around small obstacles.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "robot_agent/controller/formation_forces.hpp"
#include "robot_agent/controller/goal_force.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/vec2_math.hpp"
#include "robot_agent/controller/wall_follow.hpp"

namespace swarmform::controller::motion {
namespace {

constexpr double kPi = std::numbers::pi;

ParentMeasure measure(Vec2 to_parent) {
  return {vnorm(to_parent), std::atan2(to_parent.y, to_parent.x)};
}

TEST(FormationForces, NetForceIsZeroAtTheReferenceGeometry) {
  const Vec2 p0{1.0, -0.5};
  const Vec2 ref = reference_force(1.0, measure(p0));
  EXPECT_NEAR(vnorm(ref), 1.0 * vnorm(p0) * vnorm(p0), 1e-12);  // eq. (2): k_o r0^2
  const Vec2 net = net_force(attractive_force(1.0, measure(p0)), ref);
  EXPECT_NEAR(vnorm(net), 0.0, 1e-12);
}

TEST(FormationForces, NetForcePullsTheFollowerAfterItsParent) {
  const Vec2 p0{1.0, 0.0};
  const Vec2 ref = reference_force(2.0, measure(p0));
  // The parent moved by d (in any direction): F_net points along d, so the follower closes the gap.
  for (double a = -kPi; a < kPi; a += kPi / 8) {
    const Vec2 d = vpolar(0.1, a);
    const Vec2 net = net_force(attractive_force(2.0, measure(vadd(p0, d))), ref);
    EXPECT_GT(vdot(net, d), 0.0) << "angle " << a;
    // Linear spring: about k_o r0 (d + (u.d) u), stiffer along the link.
    const Vec2 expected = vscale(vadd(d, vscale(p0, vdot(p0, d))), 2.0);
    EXPECT_NEAR(net.x, expected.x, 0.03);
    EXPECT_NEAR(net.y, expected.y, 0.03);
  }
}

TEST(GoalForce, PointsAtTheGoalSaturatesAndStopsInsideTheRadius) {
  const Vec2 f = goal_force({0, 0}, {10, 0}, 1.0, 0.07, 0.5);
  EXPECT_NEAR(f.x, 0.07, 1e-12);
  EXPECT_NEAR(f.y, 0.0, 1e-12);
  const Vec2 near = goal_force({9.0, 0}, {10, 0.0}, 0.05, 0.07, 0.5);
  EXPECT_NEAR(near.x, 0.05, 1e-12);  // k_goal (r_goal - r) below the saturation
  const Vec2 in = goal_force({9.7, 0.2}, {10, 0}, 1.0, 0.07, 0.5);
  EXPECT_EQ(vnorm(in), 0.0);
}

UltrasonicArray clear() {
  UltrasonicArray a;
  a.fill(kUltrasonicMaxRange);
  return a;
}

ObstacleParams params() {
  return ObstacleParams{0.05, 0.6, 1.0, 0.5};
}

TEST(ObstacleForces, RepulsionPointsAwayAndGrowsNearer) {
  auto r = clear();
  r[2] = 0.4;  // straight ahead
  const auto far = sense_obstacles(r, {}, 0.0, params());
  EXPECT_LT(far.force.x, 0.0);
  EXPECT_NEAR(far.force.y, 0.0, 1e-12);
  EXPECT_NEAR(far.force.x, -0.05 * (1 / 0.4 - 1 / 0.6), 1e-12);  // eq. (6)
  r[2] = 0.3;
  EXPECT_LT(sense_obstacles(r, {}, 0.0, params()).force.x, far.force.x);
  // An echo beyond the obstacle range repels nothing; the body frame is rotated into the arena frame.
  r[2] = 0.8;
  EXPECT_EQ(vnorm(sense_obstacles(r, {}, 0.0, params()).force), 0.0);
  r[2] = 2.0;
  r[4] = 0.3;  // left sensor, robot facing +y: the echo is at -x, the push towards +x
  const auto rotated = sense_obstacles(r, {}, kPi / 2, params());
  EXPECT_GT(rotated.force.x, 0.0);
  EXPECT_NEAR(rotated.force.y, 0.0, 1e-12);
}

TEST(ObstacleForces, Algorithm2LeavesOutTheDirectionsWhereNeighboursStand) {
  auto r = clear();
  r[3] = 0.4 - 2 * kRobotRadius + 0.02;  // the neighbour's body, seen by the 45-degree sensor
  r[1] = 0.35;                           // something at -45 degrees where no neighbour stands
  const std::vector<NeighbourBearing> n{{0.4, kPi / 4 + 0.1}};
  const auto mask = mask_neighbour_directions(r, n, 0.35, 0.1);
  EXPECT_TRUE(mask[3]);
  EXPECT_FALSE(mask[1]);
  EXPECT_FALSE(mask[2]);
  const auto sense = sense_obstacles(r, mask, 0.0, params());
  EXPECT_GT(sense.force.y, 0.0);  // pushed away from the -45 degree echo only
  EXPECT_GT(sense.force.x, -0.2);
  // An echo much nearer than the neighbour is an obstacle between us: not masked.
  r[3] = 0.1;
  EXPECT_FALSE(mask_neighbour_directions(r, n, 0.35, 0.1)[3]);
}

TEST(ObstacleForces, SizeFromTheUltrasonicFusion) {
  auto r = clear();
  EXPECT_EQ(sense_obstacles(r, {}, 0.0, params()).size, ObstacleSize::None);
  r[2] = 0.5;  // a post straight ahead, seen by one sensor
  EXPECT_EQ(sense_obstacles(r, {}, 0.0, params()).size, ObstacleSize::Small);
  // A wall across the path: the +-45 degree sensors see it too, 0.5 m to each side.
  r[1] = r[3] = 0.5 / std::cos(kPi / 4);
  const auto wall = sense_obstacles(r, {}, 0.0, params());
  EXPECT_EQ(wall.size, ObstacleSize::Large);
  EXPECT_EQ(wall.sensors_seeing, 3);
  // A narrow thing seen by two adjacent sensors close by is still small.
  r = clear();
  r[2] = 0.3;
  r[3] = 0.32;
  EXPECT_EQ(sense_obstacles(r, {}, 0.0, params()).size, ObstacleSize::Small);
}

TEST(WallFollow, GoesRoundASmallObstacleOnTheChosenSideAndLeavesPastIt) {
  WallFollower wf;
  const WallFollowParams p{0.6, 0.4, 0.5, 0.07, 0.25};
  auto r = clear();
  r[2] = 0.5;  // small post ahead, robot at the origin facing +x: its centre is at 0.5 + radius + 0.25
  Vec2 v;
  // The desired motion leans slightly left (+y), no hint: round it on the left, i.e. first towards +y.
  ASSERT_TRUE(wf.update(sense_obstacles(r, {}, 0.0, params()), {0.07, 0.01}, {}, {0, 0, 0}, p, v));
  EXPECT_NEAR(wf.centre().x, 0.5 + kRobotRadius + 0.25, 1e-9);
  EXPECT_GT(v.y, 0.06);
  // The hint wins over the lean: -1 passes it on the right.
  WallFollower right;
  ASSERT_TRUE(right.update(sense_obstacles(r, {}, 0.0, params()), {0.07, 0.01}, {}, {0, 0, 0}, p, v, -1));
  EXPECT_LT(v.y, -0.06);
  // Beside the obstacle, on the circle, still short of its centre along the travel: keeps going, now along
  // +x, whatever the sensors say (none here).
  const Vec2 c = wf.centre();
  const double radius = 0.25 + kRobotRadius + 0.4;
  ASSERT_TRUE(wf.update(sense_obstacles(clear(), {}, 0.0, params()), {0.07, 0.0}, {1, 0},
                        {c.x - 0.05, c.y + radius, 0}, p, v));
  EXPECT_GT(v.x, 0.06);
  // Past its centre along the travel: leaves.
  EXPECT_FALSE(wf.update(sense_obstacles(clear(), {}, 0.0, params()), {0.07, 0.0}, {1, 0},
                         {c.x + 0.1, c.y + radius, 0}, p, v));
  EXPECT_FALSE(wf.active());
  // A large obstacle never starts it; neither does a post behind the direction of travel.
  r = clear();
  r[2] = 0.5;
  r[1] = r[3] = 0.7;
  EXPECT_FALSE(wf.update(sense_obstacles(r, {}, 0.0, params()), {0.07, 0}, {}, {0, 0, 0}, p, v));
  r = clear();
  r[2] = 0.5;
  EXPECT_FALSE(wf.update(sense_obstacles(r, {}, 0.0, params()), {0.07, 0}, {-1, 0}, {0, 0, 0}, p, v));
}

}  // namespace
}  // namespace swarmform::controller::motion
