// libFuzzer target: the sensor packet's readings blob (common/dds/readings_blob.cpp), the part of an agent's
// packet decoding that needs no DDS. decode never reads outside the blob, leaves its output untouched on a
// refusal, and what it accepts re-encodes to the same bytes.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/dds/readings_blob.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace sd = swarmform::dds;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<swarmform::RabReading> out(1);
  out[0].sender = 77;
  out[0].data = {1, 2, 3};
  const std::vector<swarmform::RabReading> before = out;
  const std::string bad = sd::decode_readings(std::span<const std::uint8_t>(data, size), out);
  if (!bad.empty()) {
    FUZZ_CHECK(out.size() == 1 && out[0].sender == 77 && out[0].data == before[0].data);
    return 0;
  }
  std::vector<std::uint8_t> again;
  sd::encode_readings(out, again);
  FUZZ_CHECK(again.size() == size && std::equal(again.begin(), again.end(), data));
  return 0;
}
