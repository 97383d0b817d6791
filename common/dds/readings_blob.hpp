// The messages a robot heard in one tick, packed into one byte blob for SensorPacket.readings. Cyclone
// serialised a sequence<RabReading>, each with its own sequence<octet>, element by element through its
// generic op-code interpreter; one octet sequence is a single memcpy. Plain C++: no DDS here, so the format
// is unit-tested on its own (tests/integration/readings_blob_test.cpp).
//
// Layout (little-endian whatever the host, no padding; doubles as their IEEE-754 bits):
//   u32 count
//   count times: u32 sender, f64 range, f64 bearing, u32 length, `length` bytes of data
// The length is u32, not u16: a scenario may allow messages of 65536 bytes (max_message_bytes).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/types.hpp"

namespace swarmform::dds {

// Bytes of a reading's fixed part (sender, range, bearing, length) and of the count in front.
inline constexpr std::size_t kReadingsCountBytes = 4;
inline constexpr std::size_t kReadingHeaderBytes = 4 + 8 + 8 + 4;

// Writes `readings` into `blob`, replacing its contents. Reuses the blob's capacity: no allocation once it
// has held the largest tick's readings.
void encode_readings(const std::vector<RabReading>& readings, std::vector<std::uint8_t>& blob);

// Reads a blob written by encode_readings into `out`, reusing the capacity of `out` and of its readings'
// data. Returns an empty string on success; otherwise what is wrong with the blob (truncated, a count or a
// length past its end, trailing bytes), and `out` is left untouched. Never reads outside `blob`.
[[nodiscard]] std::string decode_readings(std::span<const std::uint8_t> blob, std::vector<RabReading>& out);

}  // namespace swarmform::dds
