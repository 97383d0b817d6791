// libFuzzer target: the scenario loader (world_server/world/scenario.cpp with yaml-cpp) on any text. Every
// rejection must be an InputError (file:line: what); anything else escaping, a crash or a sanitizer report is
// a bug; so is an accepted scenario with no robots, no shape or a coordinate past the format's bounds. The
// text is loaded as if it were a file in scenarios/, so `shape: triangle.txt` and the like resolve to the
// repository's shapes (SWARMFORM_FUZZ_SCENARIO_ORIGIN, set by CMakeLists.txt). The behaviours are stand-ins
// with the built-ins' names and tables (the loader only reads descriptors), so no controller is compiled.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include <array>
#include <memory>

#include "behaviour/registry.hpp"
#include "common/input_error.hpp"
#include "robot_agent/controller/paper_params.hpp"
#include "tests/fuzz/fuzz_check.hpp"
#include "world_server/world/scenario.hpp"

namespace {

std::unique_ptr<swarmform::controller::Controller> no_controller() {
  return nullptr;
}

swarmform::behaviour::Registry& stand_ins() {
  using swarmform::behaviour::Descriptor;
  static const Descriptor paper{.name = "paper",
                                .summary = "",
                                .params = swarmform::controller::kPaperParams,
                                .states = {},
                                .telemetry = {},
                                .needs_shape = true,
                                .needs_goal = true,
                                .make = &no_controller,
                                .sensors = 0,
                                .experiment = {}};
  static const Descriptor walk{.name = "random_walk",
                               .summary = "",
                               .params = {},
                               .states = {},
                               .telemetry = {},
                               .needs_shape = false,
                               .needs_goal = false,
                               .make = &no_controller,
                               .sensors = 0,
                               .experiment = {}};
  static swarmform::behaviour::Registry registry = [] {
    swarmform::behaviour::Registry r;
    r.add(paper);
    r.add(walk);
    return r;
  }();
  return registry;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const swarmform::world::Scenario s =
        swarmform::world::parse_scenario_text(text, SWARMFORM_FUZZ_SCENARIO_ORIGIN, {}, stand_ins());
    FUZZ_CHECK(!s.robots.empty());
    FUZZ_CHECK(s.behaviour != nullptr);
    FUZZ_CHECK(!s.behaviour->needs_shape || s.mission.shape.label_count() > 0);
    // Every coordinate is bounded (centres and poses within 10 km, the arena at most 10 km across).
    auto bounded = [](double v) { return std::isfinite(v) && std::abs(v) <= 20000.0; };
    for (const auto& p : s.robots) FUZZ_CHECK(bounded(p.x) && bounded(p.y) && std::isfinite(p.theta));
    for (const auto& o : s.obstacles) FUZZ_CHECK(bounded(o.centre.x) && bounded(o.centre.y));
  } catch (const swarmform::InputError&) {
  }
  return 0;
}
