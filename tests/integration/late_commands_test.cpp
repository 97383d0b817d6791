// world_server/late_commands: the split of a missed command's wait (BENCHMARKS.md, P2) into the world's
// publish phase, the agent's answer and the transit.
#include "world_server/late_commands.hpp"

#include <gtest/gtest.h>

namespace swarmform::server {
namespace {

constexpr std::int64_t kMs = 1000000;  // ns

TEST(LateCommands, SplitsTheWaitOfALateCommandIntoItsParts) {
  LateCommands late(4);
  // Round of tick 7 from 1000 ms to 1100 ms; robot 2's packet written 30 ms in.
  late.missed(2, 7, 1000 * kMs, 1030 * kMs, 1100 * kMs);
  // Its command sent 80 ms after the packet (1110, already past the deadline), received 5 ms later.
  const auto c = late.arrived(2, 7, 1110 * kMs, 1115 * kMs);
  ASSERT_TRUE(c.has_value());
  EXPECT_DOUBLE_EQ(c->written_ms, 30.0);
  EXPECT_DOUBLE_EQ(c->answered_ms, 80.0);
  EXPECT_DOUBLE_EQ(c->transit_ms, 5.0);
  EXPECT_DOUBLE_EQ(c->late_ms, 15.0);
  EXPECT_TRUE(c->sent_late);
  EXPECT_EQ(late.count(), 1u);
  // The miss is closed: a second command for the same tick is not counted again.
  EXPECT_FALSE(late.arrived(2, 7, 1120 * kMs, 1121 * kMs).has_value());
}

TEST(LateCommands, OnlyACommandForTheMissedTickOfThatRobotCounts) {
  LateCommands late(4);
  late.missed(1, 3, 0, 10 * kMs, 100 * kMs);
  EXPECT_FALSE(late.arrived(1, 4, 50 * kMs, 120 * kMs).has_value());  // another tick
  EXPECT_FALSE(late.arrived(0, 3, 50 * kMs, 120 * kMs).has_value());  // another robot
  EXPECT_FALSE(late.arrived(9, 3, 50 * kMs, 120 * kMs).has_value());  // no such robot
  // Sent in time, received late: the transit (or the world's receive thread) made it miss.
  const auto c = late.arrived(1, 3, 90 * kMs, 130 * kMs);
  ASSERT_TRUE(c.has_value());
  EXPECT_FALSE(c->sent_late);
  EXPECT_DOUBLE_EQ(c->transit_ms, 40.0);
  EXPECT_EQ(late.count(), 1u);
}

TEST(LateCommands, SummaryGivesMediansAndMaxima) {
  LateCommands late(3);
  EXPECT_EQ(late.summary(), "no late commands");
  for (RobotId id = 0; id < 3; ++id) {
    late.missed(id, 1, 0, (10 + 10 * id) * kMs, 100 * kMs);             // written at 10, 20, 30 ms
    (void)late.arrived(id, 1, (110 + id) * kMs, (112 + 2 * id) * kMs);  // sent after the deadline
  }
  const std::string s = late.summary();
  EXPECT_NE(s.find("3 late commands (3 sent after the deadline)"), std::string::npos) << s;
  EXPECT_NE(s.find("packet written 20.0 ms (median; max 30.0)"), std::string::npos) << s;
  EXPECT_NE(s.find("transit 3.0 ms (median; max 4.0)"), std::string::npos) << s;
}

}  // namespace
}  // namespace swarmform::server
