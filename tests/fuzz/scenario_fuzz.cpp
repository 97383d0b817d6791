// libFuzzer target: the scenario loader (world_server/world/scenario.cpp with yaml-cpp) on any text. Every
// rejection must be an InputError (file:line: what); anything else escaping, a crash or a sanitizer report is
// a bug. The text is loaded as if it were a file in scenarios/, so `shape: triangle.txt` and the like resolve
// to the repository's shapes (SWARMFORM_FUZZ_SCENARIO_ORIGIN, set by CMakeLists.txt).
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/input_error.hpp"
#include "tests/fuzz/fuzz_check.hpp"
#include "world_server/world/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const swarmform::world::Scenario s =
        swarmform::world::parse_scenario_text(text, SWARMFORM_FUZZ_SCENARIO_ORIGIN);
    FUZZ_CHECK(!s.robots.empty());
    FUZZ_CHECK(s.mission.shape.label_count() > 0);
  } catch (const swarmform::InputError&) {
  }
  return 0;
}
