// robot_agent/answer_memory.hpp: a lockstep world writes a long round's packets again (world_server/README.md
// "A long lockstep round writes its packets again"); an agent answers a repeat with the command it sent and
// never steps its controller twice for one tick.
#include "robot_agent/answer_memory.hpp"

#include <gtest/gtest.h>

namespace {

using swarmform::Command;
using swarmform::agent::AnswerMemory;
using Verdict = AnswerMemory::Verdict;

TEST(AnswerMemory, ARepeatedTickIsAnsweredWithTheSameCommandAndAnOlderOneNotAtAll) {
  AnswerMemory m;
  EXPECT_EQ(m.judge(0, 1), Verdict::Step);  // nothing answered yet
  Command c;
  c.left_speed = 0.25;
  c.right_speed = -0.5;
  c.message = {1, 2, 3};
  m.answered(7, 1, c);
  EXPECT_EQ(m.judge(7, 1), Verdict::Repeat);
  EXPECT_EQ(m.last().left_speed, 0.25);
  EXPECT_EQ(m.last().right_speed, -0.5);
  EXPECT_EQ(m.last().message, c.message);
  EXPECT_EQ(m.judge(6, 1), Verdict::Stale);
  EXPECT_EQ(m.judge(8, 1), Verdict::Step);
}

TEST(AnswerMemory, ARobotBroughtBackIsSteppedEvenForATickItAnsweredBefore) {
  // A new generation (the world took it for dead and revived it): its controller starts afresh, and the
  // world's packet of the same tick is news to it.
  AnswerMemory m;
  m.answered(7, 1, Command{});
  EXPECT_EQ(m.judge(7, 2), Verdict::Step);
  EXPECT_EQ(m.judge(3, 2), Verdict::Step);
}

}  // namespace
