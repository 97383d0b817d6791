// World: the tick (messages at t+1), command checks, kill and revive, contacts, determinism.
#include "world_server/world/world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "test_scenarios.hpp"
#include "tests/support/paper_columns.hpp"
#include "world_server/world/faults.hpp"
#include "world_server/world/placement.hpp"

namespace swarmform::world {
namespace {

// Reproducible uniform draws in [0, 1) for the tests' commands (a 64-bit LCG: the same on every platform).
struct Uniform01 {
  std::uint64_t state;
  double operator()() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  }
};

using testing::open_scenario;

Command drive(double l, double r, std::vector<std::uint8_t> msg = {}) {
  Command c;
  c.left_speed = l;
  c.right_speed = r;
  c.message = std::move(msg);
  return c;
}

TEST(World, MessageOfTickTArrivesAtTickTPlusOneOnly) {
  World w(open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}}));
  EXPECT_EQ(w.tick(), 0u);
  EXPECT_EQ(w.apply_command(0, drive(0, 0, {1, 2, 3})), CommandVerdict::Ok);
  EXPECT_TRUE(w.perception(1).messages.empty());  // not before the step
  w.step();
  EXPECT_EQ(w.tick(), 1u);
  EXPECT_EQ(w.perception(1).tick, 1u);
  ASSERT_EQ(w.perception(1).messages.size(), 1u);
  EXPECT_EQ(w.perception(1).messages[0].data, (std::vector<std::uint8_t>{1, 2, 3}));
  EXPECT_TRUE(w.perception(0).messages.empty());
  w.step();  // nothing said at tick 1
  EXPECT_TRUE(w.perception(1).messages.empty());
}

// The bytes of a perception's messages are copied in when it is read (World::perception) or straight into a
// caller's buffer (World::copy_perception); both must show the bytes sent at the last tick, also when the
// sender has already given its next command (the harness and the DDS world apply commands robot by robot).
TEST(World, MessageBytesAreThoseOfTheLastTickWhenReadLateOrCopied) {
  World w(open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}, Pose2D{0, 1, 0}}));
  w.apply_command(0, drive(0, 0, {1, 2, 3}));
  w.apply_command(2, drive(0, 0, std::vector<std::uint8_t>(500, 9)));
  w.step();
  // Robot 0 and 2 speak again before robot 1's perception is read or copied.
  w.apply_command(0, drive(0, 0, {4, 5}));
  w.apply_command(2, drive(0, 0, {}));
  World::PerceptionCopy copy;
  // A copy made from a buffer that held more readings before (they go to its spare list).
  copy.perception.messages.resize(5);
  const Perception& c = w.copy_perception(1, copy);
  ASSERT_EQ(c.messages.size(), 2u);
  const Perception& p = w.perception(1);
  ASSERT_EQ(p.messages.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const std::vector<std::uint8_t> sent =
        p.messages[k].sender == 0 ? std::vector<std::uint8_t>{1, 2, 3} : std::vector<std::uint8_t>(500, 9);
    EXPECT_EQ(p.messages[k].data, sent);
    EXPECT_EQ(c.messages[k].sender, p.messages[k].sender);
    EXPECT_EQ(c.messages[k].range, p.messages[k].range);
    EXPECT_EQ(c.messages[k].bearing, p.messages[k].bearing);
    EXPECT_EQ(c.messages[k].data, sent);
  }
  EXPECT_EQ(c.pose.x, p.pose.x);
  EXPECT_EQ(c.ultrasonic, p.ultrasonic);
  EXPECT_EQ(c.tick, p.tick);
  // Once read (bytes filled in), a copy is still the same; then the next tick brings the new messages.
  EXPECT_EQ(w.copy_perception(1, copy).messages[0].data, p.messages[0].data);
  w.step();
  ASSERT_EQ(w.copy_perception(1, copy).messages.size(), 1u);
  EXPECT_EQ(copy.perception.messages[0].data, (std::vector<std::uint8_t>{4, 5}));
  EXPECT_EQ(w.perception(1).messages[0].data, (std::vector<std::uint8_t>{4, 5}));
}

TEST(World, NonFiniteCommandIsRejectedAndTheRobotKeepsStill) {
  World w(open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}}));
  w.apply_command(0, drive(0.1, 0.1));
  w.step();
  const double x = w.robots()[0].pose.x;
  EXPECT_EQ(w.apply_command(0, drive(std::numeric_limits<double>::quiet_NaN(), 0.1, {9})),
            CommandVerdict::RejectedNonFinite);
  EXPECT_EQ(w.apply_command(0, drive(0.1, std::numeric_limits<double>::infinity(), {9})),
            CommandVerdict::RejectedNonFinite);
  w.step();
  EXPECT_EQ(w.robots()[0].pose.x, x);
  EXPECT_TRUE(w.perception(1).messages.empty());
}

TEST(World, OverLimitSpeedIsClampedToTheLimit) {
  Scenario s = open_scenario({Pose2D{0, 0, 0}});
  s.mission.max_speed = 0.1;
  World w(s);
  EXPECT_EQ(w.apply_command(0, drive(5.0, 5.0)), CommandVerdict::Clamped);
  for (int t = 0; t < 10; ++t) w.step();  // the wheel speeds persist
  EXPECT_NEAR(w.robots()[0].pose.x, 0.1, 0.001);
  EXPECT_EQ(w.apply_command(0, drive(-0.1, 0.1)), CommandVerdict::Ok);
  EXPECT_EQ(w.apply_command(0, drive(-0.2, 0.05)), CommandVerdict::Clamped);
}

TEST(World, OversizeMessageIsDroppedButTheWheelsApply) {
  Scenario s = open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}});
  s.mission.max_message_bytes = 8;
  World w(s);
  EXPECT_EQ(w.apply_command(0, drive(0.1, 0.1, std::vector<std::uint8_t>(9, 1))),
            CommandVerdict::MessageDropped);
  w.step();
  EXPECT_TRUE(w.perception(1).messages.empty());
  EXPECT_GT(w.robots()[0].pose.x, 0.005);
  EXPECT_EQ(w.apply_command(0, drive(0.1, 0.1, std::vector<std::uint8_t>(8, 1))), CommandVerdict::Ok);
}

TEST(World, DeadAndUnknownRobotsAreRefused) {
  World w(open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}}));
  EXPECT_EQ(w.apply_command(2, drive(0, 0)), CommandVerdict::UnknownRobot);
  w.kill(1);
  EXPECT_FALSE(w.alive(1));
  EXPECT_FALSE(w.robots()[1].alive);
  EXPECT_EQ(w.apply_command(1, drive(0.1, 0.1, {1})), CommandVerdict::DeadRobot);
  w.apply_command(0, drive(0, 0, {5}));
  w.step();
  EXPECT_TRUE(w.perception(1).messages.empty());  // a dead robot hears nothing
  EXPECT_EQ(w.robots()[1].pose.x, 1.0);
}

TEST(World, KilledRobotStopsAndRevivedRobotDrivesAgain) {
  World w(open_scenario({Pose2D{0, 0, 0}, Pose2D{2, 0, 0}}));
  w.apply_command(0, drive(0.1, 0.1));
  w.step();
  w.kill(0);
  const Pose2D at_death = w.robots()[0].pose;
  for (int t = 0; t < 5; ++t) w.step();
  EXPECT_EQ(w.robots()[0].pose.x, at_death.x);
  w.revive(0);
  EXPECT_TRUE(w.alive(0));
  EXPECT_EQ(w.robots()[0].pose.x, at_death.x);  // a fresh robot where the body stood
  for (int t = 0; t < 5; ++t) w.step();
  EXPECT_EQ(w.robots()[0].pose.x, at_death.x);  // wheels start at zero
  w.apply_command(0, drive(0.1, 0.1, {3}));
  w.step();
  EXPECT_NEAR(w.robots()[0].pose.x, at_death.x + 0.01, 1e-4);
  ASSERT_EQ(w.perception(1).messages.size(), 1u);
}

TEST(World, SensorsSeeTheArenaWallsAndThePoseIsTheTruth) {
  Scenario s = open_scenario({Pose2D{1.0 - kRobotRadius - 1.0, 0.5, 0.0}});
  s.walls = true;
  s.arena_centre = Vec2{0, 0};
  s.arena_width = 2.0;  // east wall's inner face at x = 1: 1.00 m ahead of the robot's surface
  s.arena_height = 4.0;
  World w(s);
  EXPECT_NEAR(w.perception(0).ultrasonic[2], 1.0, 0.01);
  w.step();
  EXPECT_NEAR(w.perception(0).ultrasonic[2], 1.0, 0.01);
  EXPECT_EQ(w.perception(0).pose.x, w.robots()[0].pose.x);
  EXPECT_EQ(w.perception(0).pose.theta, w.robots()[0].pose.theta);
  EXPECT_EQ(w.perception(0).tick, 1u);
}

TEST(World, TelemetryFromTheLastCommandIsKept) {
  World w(open_scenario({Pose2D{0, 0, 0}}));
  Command c = drive(0, 0);
  c.telemetry.state = 3;
  swarmform::testing::set_label(c.telemetry, 5);
  swarmform::testing::set_leader(c.telemetry, true);
  w.apply_command(0, c);
  w.step();
  EXPECT_EQ(w.robots()[0].telemetry.state, 3);
  EXPECT_EQ(w.robots()[0].telemetry.extra, c.telemetry.extra);
  EXPECT_EQ(controller::kPaperColumns.label_of(w.robots()[0].telemetry), 5);
}

TEST(World, ContactsCountedThroughTheWorld) {
  Scenario s = open_scenario({Pose2D{0, 0, 0}, Pose2D{0.5, 0, std::numbers::pi}});
  s.obstacles.push_back(testing::box(0.25, 1.0, 0.5, 0.2));
  World w(s);
  std::uint32_t rr = 0, ro = 0;
  w.apply_command(0, drive(0.1, 0.1));
  w.apply_command(1, drive(0.1, 0.1));
  for (int t = 0; t < 40; ++t) {
    w.step();
    rr += w.last_contacts().robot_robot;
    ro += w.last_contacts().robot_obstacle;
  }
  EXPECT_EQ(rr, 1u);
  EXPECT_EQ(ro, 0u);
}

// defer_perceptions(true) (the in-process harness, world_server) gathers each inbox and reads each robot's
// ultrasonics when its perception is read instead of at the step: the perceptions, read by perception() or
// copied by copy_perception(), must be those of the default world bit for bit, also with occlusion, loss,
// range and ultrasonic faults, a robot killed or revived between the step and the read, and on a scenario
// whose medium and sonars draw random numbers (where deferring is switched off).
TEST(World, DeferredPerceptionsAreTheSamePerceptions) {
  for (const bool noisy : {false, true}) {
    Scenario s;
    s.arena_centre = Vec2{0, 0};
    s.arena_width = 5.0;
    s.arena_height = 5.0;
    s.obstacles.push_back(testing::box(0.6, -0.4, 0.5, 0.3));
    s.occlusion = true;
    s.comm_range = 2.0;
    s.seed = 5;
    s.mission.max_speed = 0.3;
    if (noisy) {
      s.packet_loss = 0.1;
      s.bearing_noise_sd = 0.02;
      s.ultrasonic_noise_sd = 0.01;
    }
    for (const char* text : {"loss:3@20+30", "range:all@60+20=1.0", "range:7@10=0.5", "ultrasonic:4@15+40",
                             "ultrasonic:9/2@25+40"}) {
      s.faults.push_back(parse_fault(text));
    }
    s.robots = *place_randomly(40, PlacementRegion{Vec2{0, 0}, 4.5, 4.5}, s, s.seed);
    World eager(s), deferred(s);
    deferred.defer_perceptions(true);
    World::PerceptionCopy copy;
    Uniform01 next{99};
    std::size_t heard = 0, echoes = 0;
    for (int t = 0; t < 120; ++t) {
      for (RobotId i = 0; i < 40; ++i) {
        std::vector<std::uint8_t> msg;
        if (next() < 0.8) msg.assign(1 + (i + t) % 40, static_cast<std::uint8_t>(i * 7 + t));
        const Command c = drive(0.6 * next() - 0.3, 0.6 * next() - 0.3, msg);
        eager.apply_command(i, c);
        deferred.apply_command(i, c);
      }
      eager.step();
      deferred.step();
      if (t == 30 || t == 50) {  // between the step and the reads: the messages of the step stand
        eager.kill(9);
        deferred.kill(9);
        eager.kill(12);
        deferred.kill(12);
      }
      if (t == 50) {
        eager.revive(9);
        deferred.revive(9);
      }
      for (RobotId i = 0; i < 40; ++i) {
        const Perception& e = eager.perception(i);
        // Odd ticks: the copy first, then perception(); even ticks: perception() only.
        const Perception* views[2] = {t % 2 ? &deferred.copy_perception(i, copy) : nullptr,
                                      &deferred.perception(i)};
        for (const Perception* d : views) {
          if (d == nullptr) continue;
          ASSERT_EQ(e.messages.size(), d->messages.size()) << "tick " << t << " robot " << i;
          for (std::size_t k = 0; k < e.messages.size(); ++k) {
            EXPECT_EQ(e.messages[k].sender, d->messages[k].sender);
            EXPECT_EQ(std::memcmp(&e.messages[k].range, &d->messages[k].range, sizeof(double)), 0);
            EXPECT_EQ(std::memcmp(&e.messages[k].bearing, &d->messages[k].bearing, sizeof(double)), 0);
            EXPECT_EQ(e.messages[k].data, d->messages[k].data);
          }
          EXPECT_EQ(e.ultrasonic, d->ultrasonic) << "tick " << t << " robot " << i;
        }
        heard += e.messages.size();
        for (const double r : e.ultrasonic) echoes += r < kUltrasonicMaxRange ? 1 : 0;
      }
    }
    EXPECT_GT(heard, 40u * 120u);   // the robots did hear each other
    EXPECT_GT(echoes, 40u * 120u);  // and their sonars saw each other
  }
}

// Robots crowded in a walled arena with pseudo-random commands (they collide), and messages with noise and
// loss: two worlds from the same scenario and commands give bit-identical poses and perceptions.
TEST(World, SameScenarioAndCommandsGiveBitIdenticalRuns) {
  Scenario s;
  s.arena_centre = Vec2{0, 0};
  s.arena_width = 4.0;
  s.arena_height = 4.0;
  s.obstacles.push_back(testing::cylinder(0.5, 0.5, 0.3));
  s.packet_loss = 0.2;
  s.range_noise_sd = 0.05;
  s.bearing_noise_sd = 0.05;
  s.ultrasonic_noise_sd = 0.02;
  s.seed = 11;
  s.mission.max_speed = 0.3;
  s.robots = *place_randomly(30, PlacementRegion{Vec2{0, 0}, 3.5, 3.5}, s, s.seed);
  World a(s), b(s);
  Uniform01 next{12345};
  std::uint32_t contacts = 0;
  for (int t = 0; t < 300; ++t) {
    for (RobotId i = 0; i < 30; ++i) {
      const Command c = drive(0.6 * next() - 0.3, 0.6 * next() - 0.3, {static_cast<std::uint8_t>(t), 1});
      a.apply_command(i, c);
      b.apply_command(i, c);
    }
    if (t == 100) {
      a.kill(4);
      b.kill(4);
    }
    a.step();
    b.step();
    contacts += a.last_contacts().robot_robot + a.last_contacts().robot_obstacle;
  }
  EXPECT_GT(contacts, 0u);  // the run did exercise collisions
  for (RobotId i = 0; i < 30; ++i) {
    const Pose2D pa = a.robots()[i].pose, pb = b.robots()[i].pose;
    EXPECT_EQ(std::memcmp(&pa, &pb, sizeof(Pose2D)), 0) << i;
    const Perception& qa = a.perception(i);
    const Perception& qb = b.perception(i);
    ASSERT_EQ(qa.messages.size(), qb.messages.size());
    for (std::size_t k = 0; k < qa.messages.size(); ++k) {
      EXPECT_EQ(qa.messages[k].range, qb.messages[k].range);
      EXPECT_EQ(qa.messages[k].bearing, qb.messages[k].bearing);
    }
    EXPECT_EQ(qa.ultrasonic, qb.ultrasonic);
  }
}

}  // namespace
}  // namespace swarmform::world
