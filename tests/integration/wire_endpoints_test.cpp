// The typed endpoints of common/dds/wire.hpp on one participant on loopback in its own domain
// (test_domain(11)), no other process:
// - the world's packet writers and an agent's command writer keep their instance in Cyclone's key map
//   between writes (wire.cpp keep_instance). Without that, each write of a best-effort sample created the
//   instance and freed it again through the domain's gc thread, whose wake-ups preempted the world in the
//   middle of its publish phase;
// - a packet writer says when it has matched its robot's reader (the world starts the run only then).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "common/dds/wire.hpp"
#include "tests/integration/test_domain.hpp"

namespace {

using namespace swarmform;

dds::DdsSettings world_on_loopback() {
  dds::DdsSettings s;
  s.domain = static_cast<std::uint32_t>(swarmform::testing::test_domain(11));
  s.role = dds::Role::World;
  return s;
}

TEST(WireEndpoints, PacketWritersKeepTheirPerceptionInstanceWithNoReaderMatched) {
  const dds::Participant participant(world_on_loopback());
  for (const bool realtime : {true, false}) {  // best effort and reliable
    dds::RobotChannels channels(participant, 3, realtime);
    Perception p;
    p.tick = 7;
    for (RobotId id = 0; id < 3; ++id) {
      EXPECT_TRUE(channels.holds_instance(id)) << "robot " << id << " before its first write";
      channels.write_packet(id, dds::PacketStatus::Run, p);
      channels.write_packet(id, dds::PacketStatus::Run, p);
      EXPECT_TRUE(channels.holds_instance(id))
          << "robot " << id << " after two writes, realtime " << realtime;
    }
  }
}

TEST(WireEndpoints, CommandWriterKeepsItsRobotsInstanceFromTheClaimOn) {
  const dds::Participant participant(world_on_loopback());
  dds::CommandWriter writer(participant, /*realtime=*/true);
  EXPECT_FALSE(writer.holds_instance(5));
  writer.claim(5, 42, 1234);
  Command c;
  c.left_speed = 0.1;
  writer.step(5, 0, c);
  writer.step(5, 1, c);
  EXPECT_TRUE(writer.holds_instance(5));
  EXPECT_FALSE(writer.holds_instance(6));
}

TEST(WireEndpoints, PacketWriterSaysWhenItsRobotsReaderIsMatched) {
  const dds::Participant participant(world_on_loopback());
  dds::RobotChannels channels(participant, 2, /*realtime=*/true);
  EXPECT_FALSE(channels.reader_matched(0));
  dds::Waiter waiter(participant);
  dds::AgentInbox inbox(participant, 0, waiter, /*realtime=*/true);  // partition robot/0 only
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!channels.reader_matched(0) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(channels.reader_matched(0));
  EXPECT_FALSE(channels.reader_matched(1));
}

}  // namespace
