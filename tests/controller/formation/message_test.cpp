// The broadcast codec: round trip, bounds, and garbage never crashes.
#include <gtest/gtest.h>

#include <random>

#include "robot_agent/controller/message.hpp"

namespace swarmform::controller {
namespace {

RobotMessage full_message(std::size_t entries) {
  RobotMessage m;
  m.sender = 4242;
  m.state = RobotState::Reached;
  m.label = 29;
  m.pose = {1.25, -3.5, 0.75};
  m.has_origin = true;
  m.origin = {0.5, -0.25};
  m.seed_candidate = 7;
  m.seed_distance = 0.125;
  m.seed_age = 3;
  m.table_digest = 0xF00DCAFE12345678ULL;
  m.free_labels = {1, 2, 3, 27, 28, 0, 5, 6};
  for (std::size_t i = 0; i < entries; ++i) {
    m.entries.push_back({static_cast<std::uint32_t>(0x20000 + i),
                         -1000000000000LL + static_cast<std::int64_t>(i), static_cast<std::uint32_t>(i * 3),
                         static_cast<RobotId>(i + 100)});
  }
  m.motion = {1, 2, 3, 250, 0};
  return m;
}

TEST(MessageCodec, RoundTrips) {
  const RobotMessage m = full_message(kMaxEntriesPerMessage);
  const auto bytes = encode_message(m);
  const auto back = decode_message(bytes);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->sender, m.sender);
  EXPECT_EQ(back->state, m.state);
  EXPECT_EQ(back->label, m.label);
  EXPECT_EQ(back->pose.x, m.pose.x);  // these values are exact in f32
  EXPECT_EQ(back->pose.y, m.pose.y);
  EXPECT_EQ(back->pose.theta, m.pose.theta);
  EXPECT_TRUE(back->has_origin);
  EXPECT_EQ(back->origin.x, m.origin.x);
  EXPECT_EQ(back->seed_candidate, 7u);
  EXPECT_EQ(back->seed_distance, 0.125);
  EXPECT_EQ(back->seed_age, 3);
  EXPECT_EQ(back->table_digest, m.table_digest);
  EXPECT_EQ(back->free_labels, m.free_labels);
  EXPECT_EQ(back->entries, m.entries);
  EXPECT_EQ(back->motion, m.motion);
}

TEST(MessageCodec, FitsTheWorldsLimitForThirtyLabels) {
  const auto bytes = encode_message(full_message(kMaxEntriesPerMessage));
  EXPECT_LE(bytes.size(), 1024u - 400u);  // leaves the motion section 400 bytes
  EXPECT_EQ(bytes.size(), kMessageFixedBytes + 2u * 8u + 20u * kMaxEntriesPerMessage + 5u);
}

TEST(MessageCodec, TruncatesOverlongSectionsInsteadOfWritingWhatDecodeRefuses) {
  RobotMessage m = full_message(kMaxEntriesPerMessage + 10);
  m.free_labels.resize(20, 1);
  const auto back = decode_message(encode_message(m));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->entries.size(), kMaxEntriesPerMessage);
  EXPECT_EQ(back->free_labels.size(), kMaxFreeLabels);
}

TEST(MessageCodec, RejectsEveryTruncationAndTrailingBytes) {
  const auto bytes = encode_message(full_message(5));
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_FALSE(decode_message(std::span(bytes.data(), n)).has_value()) << n;
  }
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_FALSE(decode_message(longer).has_value());
}

TEST(MessageCodec, RejectsBadMagicVersionStateAndNonFiniteNumbers) {
  const auto good = encode_message(full_message(1));
  auto bad = good;
  bad[0] ^= 0xFF;
  EXPECT_FALSE(decode_message(bad));
  bad = good;
  bad[1] = kMessageVersion + 1;
  EXPECT_FALSE(decode_message(bad));
  bad = good;
  bad[6] = 200;  // state
  EXPECT_FALSE(decode_message(bad));
  bad = good;
  // x (bytes 9..12, little-endian) = 0x7FC00000, a quiet NaN.
  bad[9] = 0x00;
  bad[10] = 0x00;
  bad[11] = 0xC0;
  bad[12] = 0x7F;
  EXPECT_FALSE(decode_message(bad));
}

TEST(MessageCodec, DecodingIntoAReusedMessageLeavesNothingOfThePreviousOne) {
  RobotMessage reused;
  ASSERT_TRUE(decode_message_into(encode_message(full_message(kMaxEntriesPerMessage)), reused));
  RobotMessage small;
  small.sender = 9;
  small.entries = {{0x20001, 5, 1, 9}};
  ASSERT_TRUE(decode_message_into(encode_message(small), reused));
  EXPECT_EQ(reused.sender, 9u);
  EXPECT_TRUE(reused.free_labels.empty());
  EXPECT_EQ(reused.entries, small.entries);
  EXPECT_TRUE(reused.motion.empty());
  EXPECT_EQ(reused.table_digest, 0u);
}

TEST(MessageCodec, SkipsTheEntriesOfATableWithTheGivenDigestButStillChecksTheirLength) {
  const RobotMessage m = full_message(5);
  const auto bytes = encode_message(m);
  RobotMessage out;
  ASSERT_TRUE(decode_message_into(bytes, out, m.table_digest));
  EXPECT_TRUE(out.entries.empty());
  EXPECT_EQ(out.motion, m.motion);  // what follows the entries is still read
  ASSERT_TRUE(decode_message_into(bytes, out, m.table_digest + 1));
  EXPECT_EQ(out.entries, m.entries);
  auto truncated = bytes;
  truncated.resize(kMessageFixedBytes + 2 * m.free_labels.size() + 20 * 3);  // inside the entries
  EXPECT_FALSE(decode_message_into(truncated, out, m.table_digest));
}

TEST(MessageCodec, AppendsTheEntriesToTheCallersBufferWhenGivenOne) {
  const RobotMessage a = full_message(3);
  RobotMessage b = full_message(2);
  b.sender = 8;
  b.entries[0].value = 99;  // entries of its own, not a's
  b.entries[1].key = 0x30001;
  std::vector<StigmergyEntry> heard = {{1, 2, 3, 4}};
  MessageBody out;
  ASSERT_TRUE(decode_message_into(encode_message(a), out, 0, heard));
  ASSERT_TRUE(decode_message_into(encode_message(b), out, 0, heard));
  EXPECT_EQ(out.sender, 8u);
  std::vector<StigmergyEntry> expected = {{1, 2, 3, 4}};
  expected.insert(expected.end(), a.entries.begin(), a.entries.end());
  expected.insert(expected.end(), b.entries.begin(), b.entries.end());
  EXPECT_EQ(heard, expected);
  ASSERT_TRUE(decode_message_into(encode_message(a), out, a.table_digest, heard));  // skipped: nothing added
  EXPECT_EQ(heard.size(), expected.size());
}

TEST(MessageCodec, RandomGarbageNeverCrashes) {
  std::mt19937 rng(1);
  const auto good = encode_message(full_message(3));
  int accepted = 0;
  for (int i = 0; i < 20000; ++i) {
    std::vector<std::uint8_t> bytes;
    if (i % 2 == 0) {
      bytes.resize(rng() % 700);
      for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    } else {
      bytes = good;  // a valid message with a few bytes flipped
      for (int k = 0; k < 3; ++k) bytes[rng() % bytes.size()] = static_cast<std::uint8_t>(rng());
    }
    if (decode_message(bytes)) ++accepted;
  }
  EXPECT_LT(accepted, 20000);
}

}  // namespace
}  // namespace swarmform::controller
