// The random walk (the simple behaviour): avoids what it sees, respects the limit, says its id.
#include <gtest/gtest.h>

#include <cmath>

#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/message.hpp"

namespace swarmform::controller {
namespace {

Mission walk_mission() {
  Mission m;
  m.behaviour = "random_walk";
  m.max_speed = 0.1;
  m.seed = 42;
  return m;
}

Perception open_field(Tick t) {
  Perception p;
  p.tick = t;
  p.ultrasonic.fill(kUltrasonicMaxRange);
  return p;
}

// Angular velocity of a command, rad/s (> 0 turns left).
double turn_rate(const Command& c) {
  return (c.right_speed - c.left_speed) / kWheelSpacing;
}

TEST(RandomWalk, TurnsAwayFromACloseObstacleOnItsLeft) {
  auto c = make_controller(walk_mission(), 3);
  Perception p = open_field(0);
  p.ultrasonic[3] = 0.3;  // +45 deg: front-left
  const Command cmd = c->step(p);
  EXPECT_LT(turn_rate(cmd), -0.5);  // turns right, on the spot
  EXPECT_LE(cmd.left_speed + cmd.right_speed, 1e-9);
}

TEST(RandomWalk, TurnsAwayFromACloseObstacleOnItsRight) {
  auto c = make_controller(walk_mission(), 3);
  Perception p = open_field(0);
  p.ultrasonic[0] = 0.3;  // -90 deg
  p.ultrasonic[1] = 0.4;  // -45 deg
  EXPECT_GT(turn_rate(c->step(p)), 0.5);
}

TEST(RandomWalk, KeepsItsSideWhileAHeadOnObstacleStays) {
  auto c = make_controller(walk_mission(), 5);
  Perception p = open_field(0);
  p.ultrasonic[2] = 0.3;
  const double first = turn_rate(c->step(p));
  EXPECT_GT(std::abs(first), 0.5);
  for (Tick t = 1; t < 20; ++t) {
    p.tick = t;
    EXPECT_EQ(std::signbit(turn_rate(c->step(p))), std::signbit(first));
  }
}

TEST(RandomWalk, DrivesForwardInTheOpenAndNeverExceedsTheSpeedLimit) {
  for (double limit : {0.05, 0.1, 0.3}) {
    Mission m = walk_mission();
    m.max_speed = limit;
    auto c = make_controller(m, 1);
    double forward_sum = 0.0;
    for (Tick t = 0; t < 2000; ++t) {
      Perception p = open_field(t);
      if (t % 97 < 10) p.ultrasonic[t % kUltrasonicCount] = 0.26;  // obstacles now and then
      const Command cmd = c->step(p);
      ASSERT_LE(std::abs(cmd.left_speed), limit + 1e-12);
      ASSERT_LE(std::abs(cmd.right_speed), limit + 1e-12);
      forward_sum += cmd.left_speed + cmd.right_speed;
    }
    EXPECT_GT(forward_sum / 2000.0 / 2.0, 0.5 * limit);  // mostly driving, not spinning
  }
}

TEST(RandomWalk, BroadcastsItsId) {
  auto c = make_controller(walk_mission(), 17);
  Perception p = open_field(0);
  p.pose = {1.5, -2.0, 0.3};
  const Command cmd = c->step(p);
  const auto msg = decode_message(cmd.message);
  ASSERT_TRUE(msg.has_value());
  EXPECT_EQ(msg->sender, 17u);
  EXPECT_EQ(msg->state, RobotState::Idle);
  EXPECT_NEAR(msg->pose.x, 1.5, 1e-6);
  EXPECT_EQ(cmd.telemetry.state, static_cast<int>(RobotState::Idle));
}

TEST(RandomWalk, IsSeededFromTheMissionSeedAndItsId) {
  auto run = [](std::uint64_t seed, RobotId id) {
    Mission m = walk_mission();
    m.seed = seed;
    auto c = make_controller(m, id);
    std::vector<double> turns;
    for (Tick t = 0; t < 300; ++t) turns.push_back(turn_rate(c->step(open_field(t))));
    return turns;
  };
  EXPECT_EQ(run(7, 1), run(7, 1));  // reproducible
  EXPECT_NE(run(7, 1), run(7, 2));  // robots differ
  EXPECT_NE(run(7, 1), run(8, 1));  // runs differ
}

TEST(ControllerFactory, RejectsUnknownBehaviourAndParameters) {
  Mission m = walk_mission();
  m.behaviour = "dance";
  EXPECT_THROW(make_controller(m, 0), InputError);
  m = walk_mission();
  m.params["no_such_param"] = 1.0;
  EXPECT_THROW(make_controller(m, 0), InputError);
  m = walk_mission();
  m.params["r_o"] = -1.0;
  EXPECT_THROW(make_controller(m, 0), InputError);
}

}  // namespace
}  // namespace swarmform::controller
