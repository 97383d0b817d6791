// Unit tests of who may take a robot's id: the claim token and proof (common/dds/claim_proof.hpp) and the
// registry's policy for claims the run's starter did not issue (world_server/agent_registry.hpp).
#include "common/dds/claim_proof.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "world_server/agent_registry.hpp"

namespace {

using swarmform::dds::ClaimProof;
using swarmform::dds::RunSecret;
using swarmform::dds::WriterGuid;
using swarmform::server::AgentRegistry;
using swarmform::server::ClaimCredentials;
using swarmform::server::ClaimOutcome;
using swarmform::server::ClaimPolicy;

RunSecret counting_secret() {
  RunSecret s{};
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = static_cast<std::uint8_t>(i);
  return s;
}

WriterGuid guid_from(std::uint8_t first) {
  WriterGuid g{};
  for (std::size_t i = 0; i < g.size(); ++i) g[i] = static_cast<std::uint8_t>(first + i);
  return g;
}

constexpr std::uint64_t kRun = 0x0123456789abcdefULL;
constexpr std::uint64_t kNonce = 0x1122334455667788ULL;

// The values Python's hmac module gives for the same bytes (scripts/swarmform/claims.py derives the tokens
// the launcher hands out; tests/scripts/test_claims.py pins the same token): the two sides agree byte for
// byte.
TEST(ClaimProof, TokenAndProofAreTheDocumentedHmacs) {
  const auto token = swarmform::dds::claim_token(counting_secret(), kRun, 8);
  EXPECT_EQ(swarmform::to_hex(token), "17d8631642b43b963d394221fc28b59e10616eb74fe6b726e4c7b4d1e555296c");
  const ClaimProof proof = swarmform::dds::claim_proof(token, kRun, 8, kNonce, guid_from(0x10));
  EXPECT_EQ(swarmform::to_hex(proof), "4de520b7074d5d8537cac76ffff0ee1c4cba58c2757a9bb1cfce393278f38f81");
}

TEST(ClaimProof, AProofHoldsOnlyForItsRunIdNonceAndWriter) {
  const RunSecret secret = counting_secret();
  const WriterGuid writer = guid_from(0x10);
  const ClaimProof proof =
      swarmform::dds::claim_proof(swarmform::dds::claim_token(secret, kRun, 8), kRun, 8, kNonce, writer);
  EXPECT_TRUE(swarmform::dds::proof_valid(secret, kRun, 8, kNonce, writer, proof));
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun, 7, kNonce, writer, proof));      // another id
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun + 1, 8, kNonce, writer, proof));  // another run
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun, 8, kNonce + 1, writer, proof));  // another attempt
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun, 8, kNonce, guid_from(0x11), proof));  // replayed
  RunSecret other = secret;
  other[0] ^= 1;
  EXPECT_FALSE(swarmform::dds::proof_valid(other, kRun, 8, kNonce, writer, proof));  // another run's secret
  ClaimProof flipped = proof;
  flipped[31] ^= 0x80;
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun, 8, kNonce, writer, flipped));
  const std::vector<std::uint8_t> none;
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun, 8, kNonce, writer, none));
  const std::vector<std::uint8_t> shorter(proof.begin(), proof.end() - 1);
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun, 8, kNonce, writer, shorter));
  // The token is not the secret, and another id's token proves nothing for this one.
  const ClaimProof from_7 =
      swarmform::dds::claim_proof(swarmform::dds::claim_token(secret, kRun, 7), kRun, 8, kNonce, writer);
  EXPECT_FALSE(swarmform::dds::proof_valid(secret, kRun, 8, kNonce, writer, from_7));
}

TEST(ClaimProof, KeysAreSixtyFourHexDigitsTakenOutOfTheEnvironment) {
  EXPECT_FALSE(swarmform::dds::parse_key_hex("00").has_value());
  EXPECT_FALSE(swarmform::dds::parse_key_hex(std::string(63, 'a') + "g").has_value());
  const auto key = swarmform::dds::parse_key_hex(swarmform::to_hex(counting_secret()));
  ASSERT_TRUE(key.has_value());
  EXPECT_EQ(*key, counting_secret());

  const char* name = "SWARMFORM_TEST_CLAIM_KEY";
  ::unsetenv(name);
  EXPECT_FALSE(swarmform::dds::take_key_from_env(name).has_value());
  ::setenv(name, swarmform::to_hex(counting_secret()).c_str(), 1);
  EXPECT_EQ(swarmform::dds::take_key_from_env(name), counting_secret());
  EXPECT_EQ(std::getenv(name), nullptr);  // no child inherits it
  ::setenv(name, "not hex", 1);
  try {
    (void)swarmform::dds::take_key_from_env(name);
    ADD_FAILURE() << "a bad key must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::getenv(name), nullptr);
}

ClaimCredentials unissued(std::uint8_t guid) {
  return ClaimCredentials{.guid = guid_from(guid), .issued = false};
}
ClaimCredentials issued(std::uint8_t guid) {
  return ClaimCredentials{.guid = guid_from(guid), .issued = true};
}

TEST(AgentRegistry, UnissuedClaimsTakeOnlyNeverOwnedIdsBeforeTheRun) {
  AgentRegistry r(3, ClaimPolicy::FirstClaimsOpen);
  EXPECT_EQ(r.claim(0, 100, 11, 1, unissued(0x10)).outcome, ClaimOutcome::Accepted);  // a start by hand
  ASSERT_EQ(r.lose(100), std::optional<swarmform::RobotId>(0));
  // Before the run, the owner gone: a stranger may not take its id, the launcher's restarted agent may.
  const auto stranger = r.claim(0, 200, 22, 2, unissued(0x20));
  EXPECT_EQ(stranger.outcome, ClaimOutcome::Unproven);
  EXPECT_NE(stranger.reason.find("id 0 had an owner"), std::string::npos) << stranger.reason;
  EXPECT_NE(stranger.reason.find("--open-rejoin"), std::string::npos) << stranger.reason;
  EXPECT_FALSE(r.connected(0));
  EXPECT_EQ(r.claim(0, 300, 33, 3, issued(0x30)).outcome, ClaimOutcome::TakenOver);
  EXPECT_TRUE(r.owns(0, 300));
  r.start_run();
  const auto late = r.claim(1, 400, 44, 4, unissued(0x40));
  EXPECT_EQ(late.outcome, ClaimOutcome::Unproven);
  EXPECT_NE(late.reason.find("the run is under way"), std::string::npos) << late.reason;
  EXPECT_EQ(r.claim(1, 400, 44, 4, issued(0x40)).outcome, ClaimOutcome::Accepted);
}

TEST(AgentRegistry, ADeadOwnersIdGoesOnlyToAnIssuedClaimOrItsOwnWriter) {
  AgentRegistry r(2, ClaimPolicy::FirstClaimsOpen);
  ASSERT_EQ(r.claim(1, 100, 11, 5, unissued(0x10)).outcome, ClaimOutcome::Accepted);
  r.start_run();
  ASSERT_EQ(r.lose(100), std::optional<swarmform::RobotId>(1));
  EXPECT_EQ(r.claim(1, 200, 22, 6, unissued(0x20)).outcome, ClaimOutcome::Unproven);
  EXPECT_EQ(r.claim(1, 200, 22, 6, ClaimCredentials{}).outcome, ClaimOutcome::Unproven);  // GUID unknown
  EXPECT_FALSE(r.connected(1));
  // The dead owner's own writer, rediscovered under a new handle, re-claims: it is the owner, not a stranger.
  EXPECT_EQ(r.claim(1, 101, 11, 5, unissued(0x10)).outcome, ClaimOutcome::TakenOver);
  EXPECT_TRUE(r.owns(1, 101));
  // A live owner's attempt (nonce and pid, both on the wire) replayed from another writer does not rebind,
  // nor take over an owner whose liveliness lapsed.
  EXPECT_EQ(r.claim(1, 300, 11, 5, unissued(0x30)).outcome, ClaimOutcome::Unproven);
  ASSERT_EQ(r.lapse(101), std::optional<swarmform::RobotId>(1));
  EXPECT_EQ(r.claim(1, 300, 11, 5, unissued(0x30)).outcome, ClaimOutcome::Unproven);
  EXPECT_TRUE(r.owns(1, 101));
}

TEST(AgentRegistry, AWorldHoldingTheRunsSecretTakesOnlyIssuedClaims) {
  AgentRegistry r(2, ClaimPolicy::IssuedOnly);
  const auto stranger = r.claim(0, 100, 11, 5, unissued(0x10));  // before the run, a never-owned id
  EXPECT_EQ(stranger.outcome, ClaimOutcome::Unproven);
  EXPECT_NE(stranger.reason.find("only to agents its starter issued"), std::string::npos) << stranger.reason;
  EXPECT_EQ(r.claim(0, 200, 22, 6, issued(0x20)).outcome, ClaimOutcome::Accepted);
  EXPECT_EQ(r.claim(0, 200, 22, 6, unissued(0x20)).outcome, ClaimOutcome::Repeated);  // its own re-sent claim
  r.start_run();
  ASSERT_TRUE(r.lose(200).has_value());
  EXPECT_EQ(r.claim(0, 100, 11, 5, unissued(0x10)).outcome, ClaimOutcome::Unproven);
  EXPECT_EQ(r.claim(0, 300, 33, 7, issued(0x30)).outcome, ClaimOutcome::TakenOver);  // the restarted agent
}

TEST(AgentRegistry, OpenRejoinLetsAnyClaimantTakeADeadOwnersId) {
  AgentRegistry r(2, ClaimPolicy::Open);
  ASSERT_EQ(r.claim(1, 100, 11, 5, unissued(0x10)).outcome, ClaimOutcome::Accepted);
  r.start_run();
  ASSERT_TRUE(r.lose(100).has_value());
  EXPECT_EQ(r.claim(1, 200, 22, 6, unissued(0x20)).outcome, ClaimOutcome::TakenOver);
  EXPECT_EQ(r.claim(0, 300, 33, 7, unissued(0x30)).outcome, ClaimOutcome::Accepted);
}

}  // namespace
