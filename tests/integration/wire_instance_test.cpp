// The world's packet writers and an agent's command writer keep their instance in Cyclone's key map between
// writes (common/dds/wire.cpp keep_instance). Without that, each write of a best-effort sample created the
// instance and freed it again through the domain's gc thread, whose wake-ups preempted the world in the
// middle of its publish phase. One participant on loopback in its own domain (111), no other process.
#include <gtest/gtest.h>

#include "common/dds/wire.hpp"

namespace {

using namespace swarmform;

dds::DdsSettings world_on_loopback() {
  dds::DdsSettings s;
  s.domain = 111;
  s.role = dds::Role::World;
  return s;
}

TEST(WireInstances, PacketWritersKeepTheirPerceptionInstanceWithNoReaderMatched) {
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

TEST(WireInstances, CommandWriterKeepsItsRobotsInstanceFromTheClaimOn) {
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

}  // namespace
