#include "common/dds/readings_blob.hpp"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>

#include "common/little_endian.hpp"

namespace swarmform::dds {

namespace {

// Doubles travel as their IEEE-754 bits (little_endian.hpp).
void put_f64(std::uint8_t* p, double d) {
  store_le(p, std::bit_cast<std::uint64_t>(d));
}
double get_f64(const std::uint8_t* p) {
  return std::bit_cast<double>(load_le<std::uint64_t>(p));
}

std::uint32_t checked_u32(std::size_t n, const char* what) {
  if (n > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error(std::string("readings blob: ") + what + " does not fit in 32 bits");
  }
  return static_cast<std::uint32_t>(n);
}

}  // namespace

void encode_readings(const std::vector<RabReading>& readings, std::vector<std::uint8_t>& blob) {
  std::size_t total = kReadingsCountBytes;
  for (const RabReading& r : readings) total += kReadingHeaderBytes + r.data.size();
  // resize, not clear + resize: only bytes beyond the old size are zero-filled, and all are overwritten.
  blob.resize(total);
  std::uint8_t* p = blob.data();
  store_le<std::uint32_t>(p, checked_u32(readings.size(), "the count"));
  p += kReadingsCountBytes;
  for (const RabReading& r : readings) {
    store_le<std::uint32_t>(p, r.sender);
    put_f64(p + 4, r.range);
    put_f64(p + 12, r.bearing);
    store_le<std::uint32_t>(p + 20, checked_u32(r.data.size(), "a message's length"));
    p += kReadingHeaderBytes;
    if (!r.data.empty()) std::copy(r.data.begin(), r.data.end(), p);
    p += r.data.size();
  }
}

std::string decode_readings(std::span<const std::uint8_t> blob, std::vector<RabReading>& out) {
  const std::size_t size = blob.size();
  const std::uint8_t* b = blob.data();
  if (size < kReadingsCountBytes) {
    return "readings blob of " + std::to_string(size) + " bytes is shorter than its count";
  }
  const std::uint32_t count = load_le<std::uint32_t>(b);
  // Every reading takes at least its header: a count beyond that is refused before anything is sized by it.
  if (count > (size - kReadingsCountBytes) / kReadingHeaderBytes) {
    return "readings blob of " + std::to_string(size) + " bytes cannot hold its count of " +
           std::to_string(count) + " readings";
  }
  // First pass: check every length, so that `out` is only touched for a well-formed blob.
  std::size_t pos = kReadingsCountBytes;
  for (std::uint32_t k = 0; k < count; ++k) {
    if (size - pos < kReadingHeaderBytes) {
      return "readings blob truncated in the header of reading " + std::to_string(k);
    }
    const std::uint32_t length = load_le<std::uint32_t>(b + pos + 20);
    pos += kReadingHeaderBytes;
    if (length > size - pos) {
      return "readings blob: reading " + std::to_string(k) + " has " + std::to_string(length) +
             " bytes of data, past the end (" + std::to_string(size - pos) + " left)";
    }
    pos += length;
  }
  if (pos != size) {
    return "readings blob has " + std::to_string(size - pos) + " trailing bytes after " +
           std::to_string(count) + " readings";
  }
  // Second pass: copy. resize and assign keep the capacity of the readings and of their data.
  out.resize(count);
  pos = kReadingsCountBytes;
  for (RabReading& r : out) {
    const std::uint8_t* h = b + pos;
    r.sender = load_le<std::uint32_t>(h);
    r.range = get_f64(h + 4);
    r.bearing = get_f64(h + 12);
    const std::uint32_t length = load_le<std::uint32_t>(h + 20);
    pos += kReadingHeaderBytes;
    r.data.assign(b + pos, b + pos + length);
    pos += length;
  }
  return {};
}

}  // namespace swarmform::dds
