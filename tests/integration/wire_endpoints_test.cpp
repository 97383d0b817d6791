// The typed endpoints of common/dds/ on one participant on loopback in its own domain
// (test_domain(11)), no other process:
// - the world's packet writers and an agent's command writer keep their instance in Cyclone's key map
//   between writes (keep_instance, common/dds/internal/endpoint_kit.hpp). Without that, each write of a
//   best-effort sample created the instance and freed it again through the domain's gc thread, whose wake-ups
//   preempted the world in the middle of its publish phase;
// - a packet writer says when it has matched its robot's reader (the world starts the run only then);
// - untrusted input (docs/faults.md): the world keeps at most kMaxExtraChannels channels for claims of ids
//   outside the run; its command reader never returns samples for ids at or above its accept_ids and, once
//   a writer sent one, drops that writer's samples for instances not known inside the run before storing
//   them; it keeps at most a writer's budget of samples a window, the rest dropped before they are decoded
//   or stored (dds::ReceiveBudget);
// - a mixed swarm's mission carries its robot groups, each agent takes its own group's behaviour and
//   parameters, and groups that do not tile the run's ids are refused (docs/wire.md, version 12);
// - a waiter counting a reader's arrivals sleeps until as many samples are in as it said it needs (so the
//   world wakes once in a lockstep round, not at each of its 64 commands).
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "behaviour/descriptor.hpp"
#include "common/dds/agent_inbox.hpp"
#include "common/dds/command_reader.hpp"
#include "common/dds/command_writer.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/matching.hpp"
#include "common/dds/mission_endpoints.hpp"
#include "common/dds/observe_wire.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/robot_channels.hpp"
#include "common/dds/waiter.hpp"
#include "common/input_error.hpp"
#include "common/sensor_readings.hpp"
#include "tests/support/test_domain.hpp"

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

// The optional sensors cross the wire bit for bit when equipped and come back empty when not (the agent's
// behaviour must not read zeros as readings).
TEST(WireEndpoints, OptionalSensorsArriveBitForBitAndOnlyWhenEquipped) {
  const dds::Participant participant(world_on_loopback());
  dds::RobotChannels channels(participant, 1, /*realtime=*/false);
  dds::Waiter waiter(participant);
  dds::AgentInbox inbox(participant, 0, waiter, /*realtime=*/false);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!channels.reader_matched(0) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(channels.reader_matched(0));
  auto receive = [&](const Perception& sent) {
    channels.write_packet(0, dds::PacketStatus::Run, sent);
    dds::SensorSample got;
    std::uint64_t foreign = 0;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (!inbox.take_packet(got, foreign) && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_EQ(got.perception.tick, sent.tick);
    return got.perception;
  };
  Perception p;
  p.tick = 1;
  p.proximity = std::array<double, kProximityCount>{1.0, 0.0, 1.0 / 3.0, 0.5, 0.0, 0.0, 1e-300, 0.25};
  p.ground = std::array<double, kGroundCount>{0.0, 1.0, 0.5, 1.0 / 9.0};
  p.battery = 0.0;  // empty, but equipped
  p.lidar = {LidarRay{-1.8325957145940461, 4.0}, LidarRay{0.0, 1.0 / 3.0}, LidarRay{1.0, 0.02}};
  const Perception full = receive(p);
  EXPECT_EQ(full.proximity, p.proximity);
  EXPECT_EQ(full.ground, p.ground);
  EXPECT_FALSE(full.light.has_value());
  EXPECT_EQ(full.battery, std::optional<double>(0.0));
  ASSERT_EQ(full.lidar.size(), p.lidar.size());
  for (std::size_t k = 0; k < p.lidar.size(); ++k) {
    EXPECT_EQ(full.lidar[k].angle, p.lidar[k].angle);
    EXPECT_EQ(full.lidar[k].range, p.lidar[k].range);
  }
  Perception bare;
  bare.tick = 2;
  const Perception none = receive(bare);
  EXPECT_FALSE(none.proximity.has_value());
  EXPECT_FALSE(none.ground.has_value());
  EXPECT_FALSE(none.battery.has_value());
  EXPECT_TRUE(none.lidar.empty());
}

// `frame` written until the reader takes it (5 s at most): true with it in `got`.
bool publish_until_taken(dds::ObserveWriter& writer, dds::ObserveReader& reader, std::uint64_t run_nonce,
                         const dds::ObserveFrameData& frame, dds::ObserveFrameData& got) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < deadline) {
    writer.publish(frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (reader.take(run_nonce, got)) return true;
  }
  return false;
}

// A viewer's frame carries each robot's optional readings (the lidar as its nearest ray), only when equipped.
TEST(WireEndpoints, ObserveFramesCarryTheOptionalReadingsTheBehaviourDeclared) {
  const dds::Participant participant(world_on_loopback());
  dds::ObserveWriter writer(participant, 77);
  dds::ObserveReader reader(participant);
  Perception p;
  p.proximity = std::array<double, kProximityCount>{1.0, 0.0, 1.0 / 3.0, 0.5, 0.0, 0.0, 0.0, 0.25};
  p.battery = 0.375;
  p.lidar = {LidarRay{-1.0, 4.0}, LidarRay{0.5, 0.42}, LidarRay{1.0, 2.0}};
  dds::ObserveFrameData frame;
  frame.robots.resize(2);
  pack_sensor_readings(p, frame.robots[0].equipped, frame.robots[0].readings);
  pack_sensor_readings(Perception{}, frame.robots[1].equipped, frame.robots[1].readings);
  EXPECT_EQ(frame.robots[0].equipped,
            swarmform::behaviour::kProximity | swarmform::behaviour::kLidar | swarmform::behaviour::kBattery);
  EXPECT_EQ(frame.robots[0].readings,
            (std::vector<double>{1.0, 0.0, 1.0 / 3.0, 0.5, 0.0, 0.0, 0.0, 0.25, 3.0, 0.5, 0.42, 0.375}));
  EXPECT_EQ(frame.robots[1].equipped, 0U);
  dds::ObserveFrameData got;
  ASSERT_TRUE(publish_until_taken(writer, reader, 77, frame, got));
  ASSERT_EQ(got.robots.size(), 2U);
  EXPECT_EQ(got.robots[0].equipped, frame.robots[0].equipped);
  EXPECT_EQ(got.robots[0].readings, frame.robots[0].readings);
  EXPECT_EQ(got.robots[1].equipped, 0U);
  EXPECT_TRUE(got.robots[1].readings.empty());
}

// A mixed swarm's frame names each robot's telemetry values by its own group's columns.
TEST(WireEndpoints, ObserveFramesCarryEachGroupsColumnsAndEachRobotsOwnValues) {
  const dds::Participant participant(world_on_loopback());
  dds::ObserveWriter writer(participant, 78);
  dds::ObserveReader reader(participant);
  dds::ObserveFrameData frame;
  frame.columns = {"a"};
  frame.groups = {{0, 2, "first", {{0, "idle", "#ff0000"}}, {"a"}}, {2, 1, "second", {}, {"b", "c"}}};
  frame.robots.resize(3);
  for (std::size_t i = 0; i < 3; ++i) frame.robots[i].id = static_cast<RobotId>(i);
  frame.robots[0].extra = {1.5};
  frame.robots[2].extra = {-2.0, 7.0};
  dds::ObserveFrameData got;
  ASSERT_TRUE(publish_until_taken(writer, reader, 78, frame, got));
  EXPECT_EQ(got.columns, frame.columns);
  ASSERT_EQ(got.groups.size(), 2U);
  EXPECT_EQ(got.groups[1].first_id, 2U);
  EXPECT_EQ(got.groups[1].count, 1U);
  EXPECT_EQ(got.groups[1].behaviour, "second");
  EXPECT_EQ(got.groups[0].states.size(), 1U);
  EXPECT_EQ(got.groups[0].states[0].name, "idle");
  ASSERT_EQ(got.robots.size(), 3U);
  EXPECT_EQ(got.robots[0].extra, (std::vector<double>{1.5}));
  EXPECT_TRUE(got.robots[1].extra.empty());
  EXPECT_EQ(got.robots[2].extra, (std::vector<double>{-2.0, 7.0}));
  EXPECT_EQ(got.columns_of(1), (std::vector<std::string>{"a"}));
  EXPECT_EQ(got.columns_of(2), (std::vector<std::string>{"b", "c"}));
  got.groups.clear();  // without groups: the frame's own
  EXPECT_EQ(got.columns_of(2), (std::vector<std::string>{"a"}));
}

TEST(WireEndpoints, ClaimsForIdsOutsideTheRunKeepAtMostEightChannels) {
  const dds::Participant participant(world_on_loopback());
  dds::RobotChannels channels(participant, 2, /*realtime=*/false);
  for (RobotId id = 2; id < 40; ++id) {
    channels.reply_claim(dds::ClaimAnswer{id, 1, false, "no robot"});
    EXPECT_LE(channels.extra_channels(), dds::kMaxExtraChannels);
  }
  EXPECT_EQ(channels.extra_channels(), dds::kMaxExtraChannels);
}

TEST(WireEndpoints, CommandReaderDropsIdsAtOrAboveItsLimitAndTheirWritersMadeUpInstancesBeforeStoringThem) {
  const dds::Participant participant(world_on_loopback());
  dds::Waiter waiter(participant);
  dds::CommandReader reader(participant, waiter, /*realtime=*/false, /*accept_ids=*/4, /*face=*/0,
                            /*count_arrivals=*/true);
  dds::CommandWriter writer(participant, /*realtime=*/false);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!dds::writer_matched(writer.get()) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  Command c;
  auto take_ids = [&](std::size_t want) {
    std::vector<dds::CommandSample> got;
    std::vector<RobotId> ids;
    while (ids.size() < want && std::chrono::steady_clock::now() < deadline) {
      const std::size_t n = reader.take(got);
      for (std::size_t i = 0; i < n; ++i) ids.push_back(got[i].robot_id);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return ids;
  };
  for (RobotId id : {1u, 3u, 4u, 1000u, 2u}) writer.step(id, 0, c);
  EXPECT_EQ(take_ids(3), (std::vector<RobotId>{1, 3, 2}));
  EXPECT_EQ(reader.filtered(), 2u);
  // The writer sent ids outside the run: its new made-up ids are dropped on arrival (never an instance of
  // the reader's), its samples for ids inside the run still come.
  const std::uint64_t stored = waiter.arrivals();  // one a sample the reader stored
  for (RobotId id : {2000u, 2001u, 2002u, 1u}) writer.step(id, 1, c);
  EXPECT_EQ(take_ids(1), (std::vector<RobotId>{1}));
  EXPECT_EQ(reader.filtered(), 5u);
  EXPECT_EQ(waiter.arrivals(), stored + 1);
}

TEST(WireEndpoints, CommandReaderKeepsAtMostAWritersBudgetAWindowTheRestDroppedBeforeDecoding) {
  const dds::Participant participant(world_on_loopback());
  dds::Waiter waiter(participant);
  constexpr std::uint32_t kBudget = 5;
  dds::CommandReader reader(participant, waiter, /*realtime=*/false, /*accept_ids=*/4, /*face=*/0,
                            /*count_arrivals=*/false, kBudget);
  dds::CommandWriter flooder(participant, /*realtime=*/false);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!dds::writer_matched(flooder.get()) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  Command c;
  constexpr std::size_t kWritten = 200;
  for (std::size_t i = 0; i < kWritten; ++i) flooder.step(1, 0, c);
  std::vector<dds::CommandSample> got;
  std::size_t kept = 0;
  while (kept + reader.over_budget() < kWritten && std::chrono::steady_clock::now() < deadline) {
    kept += reader.take(got);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kept += reader.take(got);
  // A second may have begun during the writes: a new window, at most one more budget.
  EXPECT_GE(kept, kBudget);
  EXPECT_LE(kept, 2 * kBudget);
  EXPECT_EQ(reader.over_budget(), kWritten - kept);
  std::vector<dds::ReceiveBudget::Drops> drops;
  reader.take_budget_drops(drops);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_EQ(drops[0].count, kWritten - kept);
  // A new window (lockstep: the world's next tick) renews the budget.
  reader.set_window(1);
  flooder.step(1, 1, c);
  std::size_t renewed = 0;
  while (renewed == 0 && std::chrono::steady_clock::now() < deadline) {
    renewed += reader.take(got);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(renewed, 1u);
}

// 1024 agents on 2 cores: an agent's last claim, taken by the world after its writer had gone away, bound
// the id to that writer again and kept the robot alive without an agent to the end. A sample may wait in
// the reader after its writer went away; matched() tells the world it is stale.
TEST(WireEndpoints, ASampleOutlivesItsWriterAndTheReaderSaysTheWriterIsGone) {
  const dds::Participant participant(world_on_loopback());
  dds::Waiter waiter(participant);
  dds::CommandReader reader(participant, waiter, /*realtime=*/false);
  auto writer = std::make_unique<dds::CommandWriter>(participant, /*realtime=*/false);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!dds::writer_matched(writer->get()) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  writer->claim(5, 42, 1234);
  std::vector<dds::CommandSample> got;
  std::size_t n = 0;
  while (n == 0 && std::chrono::steady_clock::now() < deadline) {
    n = reader.take(got);
    if (n == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(n, 1u);
  const dds::PublicationHandle handle = got[0].writer;
  EXPECT_TRUE(reader.matched(handle));
  writer->claim(5, 42, 1234);  // its last claim, still to be taken when the writer goes
  writer.reset();
  while (reader.matched(handle) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_FALSE(reader.matched(handle));
  ASSERT_EQ(reader.take(got), 1u);
  EXPECT_EQ(got[0].writer, handle);
  EXPECT_EQ(got[0].kind, dds::CommandKind::Claim);
  EXPECT_FALSE(reader.matched(got[0].writer));
}

// The lockstep world waits for k commands: with a counting reader (no read condition attached) its waiter
// sleeps through the first k - 1 samples and wakes at the k-th; needing one, it wakes at every sample, and
// while a counted sample waits untaken it does not sleep at all (level-triggered, as a read condition).
TEST(WireEndpoints, ACountingWaiterSleepsUntilAsManySamplesAsItNeedsAreIn) {
  using Clock = std::chrono::steady_clock;
  const dds::Participant participant(world_on_loopback());
  dds::Waiter waiter(participant);
  dds::CommandReader reader(participant, waiter, /*realtime=*/false, /*accept_ids=*/0, /*face=*/0,
                            /*count_arrivals=*/true);
  dds::CommandWriter writer(participant, /*realtime=*/false);
  const auto deadline = Clock::now() + std::chrono::seconds(5);
  while (!dds::writer_matched(writer.get()) && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const auto arrived = [&](std::uint64_t n) {
    while (waiter.arrivals() < n && Clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return waiter.arrivals() >= n;
  };
  const auto in_ms = [](int ms) { return dds_time() + DDS_MSECS(ms); };
  Command c;
  waiter.need(3);
  writer.step(1, 0, c);
  writer.step(2, 0, c);
  ASSERT_TRUE(arrived(2));
  // The writer's first samples made it alive, and the liveliness listener woke the waiter: let that settle
  // and take the wake, so that only the counts can wake it below.
  std::vector<dds::CommandReader::LivelinessChange> changes;
  while (changes.empty() && Clock::now() < deadline) {
    reader.take_liveliness_changes(changes);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  waiter.wait_until(dds_time());
  const auto slept_from = Clock::now();
  EXPECT_FALSE(waiter.wait_until(in_ms(300))) << "woke with 2 of the 3 samples it needs";
  EXPECT_GE(Clock::now() - slept_from, std::chrono::milliseconds(250));
  writer.step(3, 0, c);
  EXPECT_TRUE(waiter.wait_until(in_ms(5000))) << "the third sample did not wake it";
  EXPECT_TRUE(waiter.wait_until(in_ms(5000))) << "slept with 3 counted samples untaken";

  std::vector<dds::CommandSample> got;
  const std::uint64_t before = waiter.arrivals();
  ASSERT_EQ(reader.take(got), 3u);
  waiter.drained(before);
  waiter.need(1);
  EXPECT_FALSE(waiter.wait_until(in_ms(200))) << "woke with nothing pending after a drain";
  writer.step(4, 0, c);
  EXPECT_TRUE(waiter.wait_until(in_ms(5000))) << "needing one, a sample did not wake it";
}

// The mission of run `nonce` once it is in (5 s at most).
std::optional<dds::MissionAnnouncement> take_mission(dds::MissionReader& reader, std::uint64_t nonce) {
  std::ostringstream said;
  dds::RefusalLog refusals("test", said);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < deadline) {
    if (auto m = reader.take(nonce, refusals)) return m;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return std::nullopt;
}

dds::MissionAnnouncement mixed_announcement(std::uint64_t nonce) {
  dds::MissionAnnouncement a;
  a.run_nonce = nonce;
  a.robots = 12;
  a.mission.behaviour = "paper";
  a.mission.params = {{"shape_heading", 0.0}};
  Mission walkers = a.mission;
  walkers.behaviour = "random_walk";
  walkers.params = {{"k_turn", 2.0}};
  a.groups = {{0, 8, a.mission}, {8, 4, walkers}};
  return a;
}

TEST(WireEndpoints, AMixedSwarmsMissionCarriesItsGroupsAndEachAgentTakesItsOwn) {
  const dds::Participant participant(world_on_loopback());
  dds::MissionWriter writer(participant);
  dds::MissionReader reader(participant);
  writer.publish(mixed_announcement(77));
  auto a = take_mission(reader, 77);
  ASSERT_TRUE(a.has_value());
  ASSERT_EQ(a->groups.size(), 2u);
  EXPECT_EQ(a->groups[1].first_id, 8u);
  EXPECT_EQ(a->groups[1].count, 4u);
  dds::MissionAnnouncement agent9 = *a, agent3 = *a;
  dds::take_own_group(agent9, 9);
  EXPECT_EQ(agent9.mission.behaviour, "random_walk");
  EXPECT_EQ(agent9.mission.params, (std::map<std::string, double>{{"k_turn", 2.0}}));
  dds::take_own_group(agent3, 3);
  EXPECT_EQ(agent3.mission.behaviour, "paper");
  EXPECT_EQ(agent3.mission.params, (std::map<std::string, double>{{"shape_heading", 0.0}}));
  // A run without groups: the mission as it is, for every id.
  dds::MissionAnnouncement plain = mixed_announcement(78);
  plain.groups.clear();
  writer.publish(plain);
  auto p = take_mission(reader, 78);
  ASSERT_TRUE(p.has_value());
  EXPECT_TRUE(p->groups.empty());
  dds::take_own_group(*p, 11);
  EXPECT_EQ(p->mission.behaviour, "paper");
}

TEST(WireEndpoints, AMissionWhoseGroupsDoNotTileTheRunIsRefused) {
  const dds::Participant participant(world_on_loopback());
  dds::MissionWriter writer(participant);
  dds::MissionReader reader(participant);
  dds::MissionAnnouncement gap = mixed_announcement(90);
  gap.groups[1].first_id = 9;  // id 8 in no group
  writer.publish(gap);
  try {
    take_mission(reader, 90);
    ADD_FAILURE() << "a mission with a gap between its groups was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("robot group 1 starts at id 9 with 4 robots; expected id 8"),
              std::string::npos)
        << e.what();
  }
  dds::MissionAnnouncement short_of = mixed_announcement(91);
  short_of.robots = 20;
  writer.publish(short_of);
  try {
    take_mission(reader, 91);
    ADD_FAILURE() << "a mission whose groups hold fewer robots than the run was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the robot groups hold 12 robots, the run 20"), std::string::npos)
        << e.what();
  }
}

}  // namespace
