// SensorPacket.readings (common/dds/readings_blob.hpp): the round trip, the byte layout the IDL documents,
// the refusal of every malformed blob without touching the destination, and the reuse of buffers.
#include "common/dds/readings_blob.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

namespace {

using swarmform::RabReading;
using swarmform::dds::decode_readings;
using swarmform::dds::encode_readings;
using Bytes = std::vector<std::uint8_t>;

// Bit for bit: a range or bearing must come back exactly (the determinism tests compare runs bit for bit).
void expect_same(const std::vector<RabReading>& a, const std::vector<RabReading>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].sender, b[k].sender) << k;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a[k].range), std::bit_cast<std::uint64_t>(b[k].range)) << k;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a[k].bearing), std::bit_cast<std::uint64_t>(b[k].bearing)) << k;
    EXPECT_EQ(a[k].data, b[k].data) << k;
  }
}

std::vector<RabReading> round_trip(const std::vector<RabReading>& in) {
  Bytes blob;
  encode_readings(in, blob);
  std::vector<RabReading> out;
  const std::string error = decode_readings(blob, out);
  EXPECT_EQ(error, "");
  return out;
}

std::vector<RabReading> many() {
  std::vector<RabReading> v;
  for (std::uint32_t k = 0; k < 40; ++k) {
    Bytes data(k % 7, static_cast<std::uint8_t>(k * 31));
    v.push_back(RabReading{k * 1000003u, 0.1 * k, -3.14159 + 0.15 * k, data});
  }
  v.push_back(
      RabReading{std::numeric_limits<std::uint32_t>::max(), -0.0, std::nextafter(std::numbers::pi, 0.0), {}});
  return v;
}

// A blob assembled by hand, little-endian: the count, then one reading's header and its data.
Bytes le_blob(std::uint32_t count, std::uint32_t sender, std::uint32_t length, const Bytes& data) {
  Bytes b;
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  auto f64 = [&](double d) {
    const auto v = std::bit_cast<std::uint64_t>(d);
    for (int i = 0; i < 8; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  u32(count);
  u32(sender);
  f64(1.5);
  f64(-0.25);
  u32(length);
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

TEST(ReadingsBlob, RoundTripsNoneOneManyEmptyAndMaximumSizeData) {
  expect_same(round_trip({}), {});
  expect_same(round_trip({RabReading{7, 1.25, -0.5, {1, 2, 3, 4}}}),
              {RabReading{7, 1.25, -0.5, {1, 2, 3, 4}}});
  expect_same(round_trip(many()), many());
  expect_same(round_trip({RabReading{3, 0.5, 0.5, {}}}), {RabReading{3, 0.5, 0.5, {}}});
  // The largest message a scenario allows (max_message_bytes 65536: more than a u16 length holds).
  Bytes big(65536);
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<std::uint8_t>(i * 7 + 3);
  const std::vector<RabReading> with_big = {RabReading{1, 2.0, 0.1, big}, RabReading{2, 0.3, -0.1, {9}}};
  expect_same(round_trip(with_big), with_big);
}

TEST(ReadingsBlob, LayoutIsTheOneTheIdlDocuments) {
  Bytes blob;
  encode_readings({RabReading{0x01020304u, 1.5, -0.25, {0xAA, 0xBB}}}, blob);
  EXPECT_EQ(blob, le_blob(1, 0x01020304u, 2, {0xAA, 0xBB}));
  encode_readings({}, blob);
  EXPECT_EQ(blob, (Bytes{0, 0, 0, 0}));
}

// Each malformed blob is refused with a reason, and the destination keeps what it held.
void expect_refused(const Bytes& blob, const std::string& why) {
  const std::vector<RabReading> before = {RabReading{5, 1.0, 2.0, {1, 2}}};
  std::vector<RabReading> out = before;
  const std::string error = decode_readings(blob, out);
  EXPECT_NE(error.find(why), std::string::npos) << "error: '" << error << "', expected '" << why << "'";
  expect_same(out, before);
}

TEST(ReadingsBlob, MalformedBlobsAreRefusedAndLeaveTheDestinationAlone) {
  expect_refused({}, "shorter than its count");
  expect_refused({1, 0, 0}, "shorter than its count");
  expect_refused({1, 0, 0, 0}, "cannot hold its count of 1");
  expect_refused({0xFF, 0xFF, 0xFF, 0xFF}, "cannot hold its count of 4294967295");
  expect_refused(le_blob(2, 1, 0, {}), "cannot hold its count of 2");
  expect_refused(le_blob(1, 1, 3, {1, 2}), "has 3 bytes of data, past the end (2 left)");
  expect_refused(le_blob(1, 1, 0xFFFFFFFFu, {1, 2}), "past the end");
  expect_refused(le_blob(1, 1, 1, {1, 2}), "1 trailing bytes");
  expect_refused(le_blob(0, 1, 0, {}), "24 trailing bytes");
  // Room for two headers by the count's measure, but the first reading's 20 bytes leave 4 for the second.
  expect_refused(le_blob(2, 1, 20, Bytes(24, 0)), "truncated in the header of reading 1");
  // Every strict prefix of a good blob is refused; each is copied into storage of its exact size, so that a
  // read past its end is an error under valgrind or ASan.
  Bytes good;
  encode_readings(many(), good);
  for (std::size_t n = 0; n < good.size(); ++n) {
    const Bytes prefix(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
    std::vector<RabReading> out;
    EXPECT_NE(decode_readings(prefix, out), "") << n;
    EXPECT_TRUE(out.empty());
  }
}

TEST(ReadingsBlob, BuffersAreReused) {
  const std::vector<RabReading> in = many();
  Bytes blob;
  encode_readings(in, blob);
  const std::uint8_t* blob_storage = blob.data();
  encode_readings(in, blob);  // warm: the same storage
  EXPECT_EQ(blob.data(), blob_storage);

  std::vector<RabReading> out;
  ASSERT_EQ(decode_readings(blob, out), "");
  const RabReading* readings_storage = out.data();
  const std::uint8_t* data_storage = out[6].data.data();  // reading 6 carries 6 bytes
  ASSERT_EQ(decode_readings(blob, out), "");
  expect_same(out, in);
  EXPECT_EQ(out.data(), readings_storage);
  EXPECT_EQ(out[6].data.data(), data_storage);
  // Fewer readings then more again: the vector's capacity serves both.
  ASSERT_EQ(decode_readings(Bytes{0, 0, 0, 0}, out), "");
  EXPECT_TRUE(out.empty());
  ASSERT_EQ(decode_readings(blob, out), "");
  EXPECT_EQ(out.data(), readings_storage);
  expect_same(out, in);
}

}  // namespace
