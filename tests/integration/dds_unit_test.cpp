// Unit tests (no processes, no network) of the DDS front end's pure parts: the identity registry and the
// generated Cyclone configuration.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "common/dds/cyclone_config.hpp"
#include "common/dds/robot_block.hpp"
#include "tests/support/test_domain.hpp"
#include "world_server/agent_registry.hpp"

namespace {

using swarmform::dds::cyclone_config_xml;
using swarmform::dds::DdsSettings;
using swarmform::dds::Role;
using swarmform::server::AgentRegistry;
using swarmform::server::ClaimOutcome;

TEST(AgentRegistry, FirstClaimantOwnsTheIdAndASecondIsRefused) {
  AgentRegistry r(4);
  EXPECT_EQ(r.claim(2, 100, 11).outcome, ClaimOutcome::Accepted);
  EXPECT_EQ(r.claim(2, 100, 11).outcome, ClaimOutcome::Repeated);
  const auto refused = r.claim(2, 200, 22);
  EXPECT_EQ(refused.outcome, ClaimOutcome::Refused);
  EXPECT_NE(refused.reason.find("already owned by a live agent (pid 11)"), std::string::npos);
  EXPECT_TRUE(r.owns(2, 100));
  EXPECT_FALSE(r.owns(2, 200));
  EXPECT_FALSE(r.owns(1, 100));
  EXPECT_EQ(r.connected_count(), 1u);
  EXPECT_EQ(r.missing(), (std::vector<swarmform::RobotId>{0, 1, 3}));
}

TEST(AgentRegistry, TheOwnerSeenThroughANewWriterHandleKeepsItsIdThere) {
  // DDS forgot the owner's participant (its lease ran out on a starved machine) and discovered it again: the
  // same process and claim attempt, a new publication handle.
  AgentRegistry r(4);
  ASSERT_EQ(r.claim(2, 100, 11, 77).outcome, ClaimOutcome::Accepted);
  EXPECT_EQ(r.claim(2, 200, 11, 77).outcome, ClaimOutcome::Rebound);
  EXPECT_TRUE(r.owns(2, 200));
  EXPECT_FALSE(r.owns(2, 100));
  EXPECT_FALSE(r.lose(100).has_value());  // the old handle's loss, reported late, is nobody's
  EXPECT_TRUE(r.connected(2));
  EXPECT_EQ(r.claim(2, 300, 11, 78).outcome, ClaimOutcome::Refused);  // another attempt: another agent
  EXPECT_EQ(r.claim(2, 300, 22, 77).outcome, ClaimOutcome::Refused);  // another process
  EXPECT_EQ(r.claim(2, 300, 11, 0).outcome, ClaimOutcome::Refused);   // no nonce: nothing to match
  EXPECT_EQ(r.lose(200), std::optional<swarmform::RobotId>(2));
}

TEST(AgentRegistry, AnOwnerWhoseLivelinessLapsedBeforeTheRunStaysConnectedButCanBeTakenOver) {
  AgentRegistry r(3);
  ASSERT_EQ(r.claim(1, 100, 11, 5).outcome, ClaimOutcome::Accepted);
  EXPECT_FALSE(r.lapse(999).has_value());  // a writer that owns nothing
  EXPECT_EQ(r.lapse(100), std::optional<swarmform::RobotId>(1));
  EXPECT_TRUE(r.connected(1));  // still counted: the world waits for no one who is there
  EXPECT_EQ(r.connected_count(), 1u);
  EXPECT_TRUE(r.owns(1, 100));
  EXPECT_FALSE(r.regain(100).has_value());                           // back: nothing changed hands
  EXPECT_EQ(r.claim(1, 200, 22, 6).outcome, ClaimOutcome::Refused);  // alive again: a second agent is refused
  ASSERT_EQ(r.lapse(100), std::optional<swarmform::RobotId>(1));
  EXPECT_EQ(r.claim(1, 100, 11, 5).outcome, ClaimOutcome::Repeated);  // its own re-sent claim: proof of life
  EXPECT_EQ(r.claim(1, 200, 22, 6).outcome, ClaimOutcome::Refused);
  ASSERT_EQ(r.lapse(100), std::optional<swarmform::RobotId>(1));
  EXPECT_EQ(r.claim(1, 200, 22, 6).outcome, ClaimOutcome::TakenOver);  // a restarted agent need not wait
  EXPECT_TRUE(r.owns(1, 200));
  EXPECT_FALSE(r.owner_of(100).has_value());
  EXPECT_FALSE(r.lose(100).has_value());  // the old writer going away later is nobody's
  ASSERT_EQ(r.lapse(200), std::optional<swarmform::RobotId>(1));
  EXPECT_EQ(r.lose(200), std::optional<swarmform::RobotId>(1));  // then gone for good: no longer connected
  EXPECT_FALSE(r.connected(1));
}

TEST(AgentRegistry, ALostOwnerFreesTheIdForATakeOver) {
  AgentRegistry r(3);
  ASSERT_EQ(r.claim(1, 100, 11).outcome, ClaimOutcome::Accepted);
  EXPECT_FALSE(r.lose(999).has_value());  // a writer that owns nothing
  EXPECT_EQ(r.lose(100), std::optional<swarmform::RobotId>(1));
  EXPECT_FALSE(r.connected(1));
  EXPECT_FALSE(r.owns(1, 100));
  EXPECT_FALSE(r.lose(100).has_value());  // reported once
  EXPECT_EQ(r.claim(1, 300, 33).outcome, ClaimOutcome::TakenOver);
  EXPECT_TRUE(r.owns(1, 300));
}

TEST(AgentRegistry, AStalledOwnerWhoseLivelinessComesBackOwnsItsIdAgain) {
  AgentRegistry r(3);
  ASSERT_EQ(r.claim(0, 100, 11).outcome, ClaimOutcome::Accepted);
  ASSERT_EQ(r.claim(1, 200, 22).outcome, ClaimOutcome::Accepted);
  EXPECT_FALSE(r.regain(100).has_value());  // never lost: nothing to regain
  ASSERT_TRUE(r.lose(100).has_value());
  EXPECT_EQ(r.regain(100), std::optional<swarmform::RobotId>(0));
  EXPECT_TRUE(r.owns(0, 100));
  // Once the id is taken over by another writer, the old one coming back gets nothing.
  ASSERT_TRUE(r.lose(200).has_value());
  ASSERT_EQ(r.claim(1, 300, 33).outcome, ClaimOutcome::TakenOver);
  EXPECT_FALSE(r.regain(200).has_value());
  EXPECT_TRUE(r.owns(1, 300));
}

TEST(AgentRegistry, AnIdOutsideTheRunIsRefused) {
  AgentRegistry r(3);
  const auto res = r.claim(3, 100, 11);
  EXPECT_EQ(res.outcome, ClaimOutcome::OutOfRange);
  EXPECT_NE(res.reason.find("no robot 3"), std::string::npos);
}

TEST(CycloneConfig, WorldTakesIndexZeroAndAgentsPeerOnlyWithIt) {
  DdsSettings world;
  world.domain = 7;
  world.role = Role::World;
  const std::string w = cyclone_config_xml(world);
  EXPECT_NE(w.find("<ParticipantIndex>0</ParticipantIndex>"), std::string::npos);
  EXPECT_EQ(w.find("<Peer "), std::string::npos);
  EXPECT_NE(w.find("<NetworkInterface address=\"127.0.0.1\"/>"), std::string::npos);
  // Participant leases are long on every process (a starved participant forgotten by DDS stays undiscovered
  // for a while); deaths are told by the writers' liveliness.
  EXPECT_NE(w.find("<LeaseDuration>30s</LeaseDuration>"), std::string::npos);
  EXPECT_NE(w.find("<SharedMemory><Enable>false</Enable></SharedMemory>"), std::string::npos);

  DdsSettings agent;
  agent.domain = 7;
  const std::string a = cyclone_config_xml(agent);
  EXPECT_NE(a.find("<ParticipantIndex>none</ParticipantIndex>"), std::string::npos);
  EXPECT_NE(a.find("<LeaseDuration>30s</LeaseDuration>"), std::string::npos);  // no death is told by it
  EXPECT_NE(a.find("<SPDPInterval>2s</SPDPInterval>"), std::string::npos);     // an idle agent's largest cost
  EXPECT_NE(a.find("<Peer address=\"127.0.0.1:" + std::to_string(7400 + 100 * 7 + 10) + "\"/>"),
            std::string::npos);

  agent.world_host = "10.0.0.5";  // another host: no loopback pinning, that host as the peer
  const std::string remote = cyclone_config_xml(agent);
  EXPECT_EQ(remote.find("127.0.0.1"), std::string::npos);
  EXPECT_NE(remote.find("10.0.0.5:8110"), std::string::npos);
}

// Faces (docs/wire.md "Faces"): blocks of 64 ids, face f at ParticipantIndex f on the run's domain (its own
// local domain id in the world's process), agent K peering with face K/64 only.
TEST(CycloneConfig, FacesSplitTheRobotsInBlocksOf64AndAgentsPeerWithTheirOwn) {
  using swarmform::dds::face_count;
  using swarmform::dds::face_of;
  using swarmform::dds::kMaxFaces;
  using swarmform::dds::local_domain_id;
  EXPECT_EQ(face_of(0), 0u);
  EXPECT_EQ(face_of(63), 0u);
  EXPECT_EQ(face_of(64), 1u);
  EXPECT_EQ(face_of(1023), 15u);
  EXPECT_EQ(face_of(100000), kMaxFaces - 1);  // past the last face: the last one
  EXPECT_EQ(face_count(1), 1u);
  EXPECT_EQ(face_count(64), 1u);
  EXPECT_EQ(face_count(65), 2u);
  EXPECT_EQ(face_count(1024), 16u);
  EXPECT_EQ(face_count(2048), 32u);
  // Every face's ports stay inside its domain's 100.
  EXPECT_LT(swarmform::dds::face_discovery_port(7, kMaxFaces - 1) + 1, 7400 + 100 * 8);

  DdsSettings world;
  world.domain = 7;
  world.role = Role::World;
  world.face = 3;
  const std::string w = cyclone_config_xml(world);
  EXPECT_NE(w.find("<ParticipantIndex>3</ParticipantIndex>"), std::string::npos) << w;
  EXPECT_NE(w.find("<ExternalDomainId>7</ExternalDomainId>"), std::string::npos) << w;
  std::vector<std::uint32_t> ids;
  for (std::uint32_t f = 0; f < kMaxFaces; ++f) {
    world.face = f;
    ids.push_back(local_domain_id(world));
    EXPECT_LE(ids.back(), 230u);  // DDS Security's range
  }
  EXPECT_EQ(ids.front(), 7u);
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(std::adjacent_find(ids.begin(), ids.end()), ids.end()) << "two faces share a local domain id";
  world.face = kMaxFaces;
  EXPECT_THROW(cyclone_config_xml(world), std::invalid_argument);

  DdsSettings agent;
  agent.domain = 7;
  agent.face = face_of(130);
  EXPECT_NE(cyclone_config_xml(agent).find(
                "<Peer address=\"127.0.0.1:" + std::to_string(7400 + 100 * 7 + 10 + 4) + "\"/>"),
            std::string::npos);
}

TEST(CycloneConfig, TheWorldsReceiveBufferIsSizedWithinWhatTheHostAllows) {
  using swarmform::dds::world_receive_buffer;
  EXPECT_EQ(world_receive_buffer(212992), 0u);  // Debian's default rmem_max: Cyclone's own default
  EXPECT_EQ(world_receive_buffer(2u << 20), 2u << 20);
  EXPECT_EQ(world_receive_buffer(64u << 20), swarmform::dds::kWorldReceiveBufferBytes);
}

TEST(RobotBlock, IdsMustFitIn32Bits) {
  using swarmform::dds::block_ids_fit;
  EXPECT_TRUE(block_ids_fit(0, swarmform::dds::kMaxRobotBlock));
  EXPECT_TRUE(block_ids_fit(UINT32_MAX, 1));
  EXPECT_TRUE(block_ids_fit(UINT32_MAX - 3, 4));
  EXPECT_FALSE(block_ids_fit(UINT32_MAX - 3, 5));
  EXPECT_FALSE(block_ids_fit(UINT32_MAX, 2));
  EXPECT_FALSE(block_ids_fit(5, 0));
}

TEST(CycloneConfig, RetransmissionsArePackedIntoFullSizeMessagesOnEveryProcess) {
  for (const Role role : {Role::World, Role::Agent}) {
    DdsSettings s;
    s.role = role;
    EXPECT_NE(cyclone_config_xml(s).find("<MaxRexmitMessageSize>14720B</MaxRexmitMessageSize>"),
              std::string::npos);
  }
}

TEST(CycloneConfig, EveryDomainsFixedPortsStayBelowTheEphemeralRange) {
  EXPECT_LT(swarmform::dds::world_discovery_port(swarmform::dds::kMaxDomain) + 2, 32768);
  EXPECT_NE(cyclone_config_xml(DdsSettings{}).find("<DomainGain>100</DomainGain>"), std::string::npos);
}

TEST(CycloneConfig, BadDomainOrAddressIsRefused) {
  DdsSettings s;
  s.domain = 233;
  EXPECT_THROW(cyclone_config_xml(s), std::invalid_argument);
  s.domain = 0;
  s.world_host = "host\"/><x";
  EXPECT_THROW(cyclone_config_xml(s), std::invalid_argument);
}

// The domain base comes from the environment and a bad one fails the test loudly instead of colliding.
TEST(TestDomain, BaseComesFromTheEnvironmentAndABadOneIsRefused) {
  using swarmform::testing::test_domain;
  const char* old = std::getenv("SWARMFORM_TEST_DOMAIN_BASE");
  const std::string saved = old != nullptr ? old : "";
  setenv("SWARMFORM_TEST_DOMAIN_BASE", "140", 1);
  EXPECT_EQ(test_domain(3), 143);
  for (const char* bad : {"abc", "12x", "-1", "186"}) {
    setenv("SWARMFORM_TEST_DOMAIN_BASE", bad, 1);
    EXPECT_THROW(test_domain(0), std::invalid_argument) << bad;
  }
  unsetenv("SWARMFORM_TEST_DOMAIN_BASE");
  EXPECT_EQ(test_domain(3), 103);
  if (old != nullptr) setenv("SWARMFORM_TEST_DOMAIN_BASE", saved.c_str(), 1);
}

}  // namespace
