// libFuzzer target: the robots' message codec (robot_agent/controller/message.cpp) on any bytes. decode never
// crashes; what it accepts re-encodes to the very same bytes (the codec has one encoding per message), and
// the receiver's path that skips the stigmergy entries (same digest) accepts exactly the same inputs. The
// motion phases' section inside (motion_section.cpp) is decoded too, with the same round trip.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/motion_section.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace sc = swarmform::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  const auto m = sc::decode_message(bytes);
  // A receiver decodes into a reused message: garbage left by a failed decode must not matter.
  sc::MessageBody body;
  body.free_labels.assign(3, 7);
  body.motion.assign(5, 1);
  std::vector<sc::StigmergyEntry> entries(2);
  const std::uint64_t digest = m ? m->table_digest : 1;
  const bool skipped_ok = sc::decode_message_into(bytes, body, digest, entries);
  FUZZ_CHECK(skipped_ok == m.has_value());
  if (!m) return 0;
  FUZZ_CHECK(m->free_labels.size() <= sc::kMaxFreeLabels);
  FUZZ_CHECK(m->entries.size() <= sc::kMaxEntriesPerMessage);
  FUZZ_CHECK(m->motion.size() <= sc::kMaxMotionBytes);
  const std::vector<std::uint8_t> again = sc::encode_message(*m);
  FUZZ_CHECK(again.size() == size && std::equal(again.begin(), again.end(), data));
  if (digest != 0) FUZZ_CHECK(entries.size() == 2);  // skipped: nothing appended
  FUZZ_CHECK(body.motion == m->motion && body.free_labels == m->free_labels);
  if (const auto section = sc::motion::decode_motion_section(m->motion)) {
    FUZZ_CHECK(sc::motion::encode_motion_section(*section) == m->motion);
  }
  return 0;
}
