// libFuzzer target: the scenario loader (world_server/world/scenario.cpp with yaml-cpp) on any text. Every
// rejection must be an InputError (file:line: what); anything else escaping, a crash or a sanitizer report is
// a bug; so is an accepted scenario with no robots, no shape or a coordinate past the format's bounds. The
// text is loaded as if it were a file in scenarios/, so `shape: triangle.txt` and the like resolve to the
// repository's shapes (SWARMFORM_FUZZ_SCENARIO_ORIGIN, set by CMakeLists.txt).
#include <cmath>
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
    // Every coordinate is bounded (centres and poses within 10 km, the arena at most 10 km across).
    auto bounded = [](double v) { return std::isfinite(v) && std::abs(v) <= 20000.0; };
    for (const auto& p : s.robots) FUZZ_CHECK(bounded(p.x) && bounded(p.y) && std::isfinite(p.theta));
    for (const auto& o : s.obstacles) FUZZ_CHECK(bounded(o.centre.x) && bounded(o.centre.y));
  } catch (const swarmform::InputError&) {
  }
  return 0;
}
