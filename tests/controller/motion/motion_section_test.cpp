// The motion section codec (motion_section.hpp) and eq. (6) with memory (EchoMemory).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "robot_agent/controller/motion_section.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {
namespace {

TEST(MotionSection, RoundTripsAndRefusesGarbage) {
  MotionSection s;
  s.leader = true;
  s.wall_following = true;
  s.parent = 42;
  s.net_force = 0.25;
  s.velocity = {0.05, -0.02};
  s.strain = 1.5;
  const auto bytes = encode_motion_section(s);
  const auto back = decode_motion_section(bytes);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(back->leader);
  EXPECT_FALSE(back->arrived);
  EXPECT_TRUE(back->wall_following);
  EXPECT_EQ(back->parent, 42);
  EXPECT_NEAR(back->net_force, 0.25, 1e-6);
  EXPECT_NEAR(back->velocity.x, 0.05, 1e-6);
  EXPECT_NEAR(back->velocity.y, -0.02, 1e-6);
  EXPECT_NEAR(back->strain, 1.5, 1e-6);
  s.parent = -1;
  EXPECT_EQ(decode_motion_section(encode_motion_section(s))->parent, -1);
  // Truncated, too long, wrong version, unknown flag bits, a NaN: nothing.
  auto cut = bytes;
  cut.pop_back();
  EXPECT_FALSE(decode_motion_section(cut).has_value());
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_FALSE(decode_motion_section(longer).has_value());
  auto version = bytes;
  version[0] = 9;
  EXPECT_FALSE(decode_motion_section(version).has_value());
  auto flags = bytes;
  flags[1] = 0x80;
  EXPECT_FALSE(decode_motion_section(flags).has_value());
  s.net_force = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(decode_motion_section(encode_motion_section(s)).has_value());
  EXPECT_FALSE(decode_motion_section({}).has_value());
}

TEST(EchoMemory, KeepsAnEchoWhileTheRobotTurnsAwayAndForgetsItLater) {
  EchoMemory memory;
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  r[2] = 0.4;  // something straight ahead of a robot at the origin facing +x
  memory.add(r, {}, {0, 0, 0}, 10, 0.6);
  const Vec2 now = memory.force({0, 0}, 10, 0.05, 0.6, 15);
  EXPECT_NEAR(now.x, -0.05 * (1 / 0.4 - 1 / 0.6), 1e-9);  // eq. (6), as the sensor alone
  EXPECT_NEAR(now.y, 0.0, 1e-9);
  // The robot turned to +y and sees nothing now: the echo still repels, from where it was.
  r.fill(kUltrasonicMaxRange);
  memory.add(r, {}, {0, 0, std::numbers::pi / 2}, 12, 0.6);
  EXPECT_NEAR(memory.force({0, 0}, 12, 0.05, 0.6, 15).x, now.x, 1e-9);
  // Moving away weakens it; after max_age it is gone.
  EXPECT_GT(memory.force({-0.1, 0}, 12, 0.05, 0.6, 15).x, now.x);
  EXPECT_EQ(vnorm(memory.force({0, 0}, 26, 0.05, 0.6, 15)), 0.0);
  // A masked direction is never remembered.
  EchoMemory masked;
  r[2] = 0.4;
  SensorMask mask{};
  mask[2] = true;
  masked.add(r, mask, {0, 0, 0}, 10, 0.6);
  EXPECT_EQ(vnorm(masked.force({0, 0}, 10, 0.05, 0.6, 15)), 0.0);
}

}  // namespace
}  // namespace swarmform::controller::motion
