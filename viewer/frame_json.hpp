// The page's messages (viewer/README.md "The page's protocol"), as JSON: a frame of sf_observe and the
// behaviour description of a recording.
#pragma once

#include <nlohmann/json.hpp>

#include "common/dds/observe_wire.hpp"

namespace swarmform::viewer {

nlohmann::json frame_json(const dds::ObserveFrameData& frame);

// A robot's `leds` in a frame: its three LEDs as "#rrggbb", or null when all are off (the frame then has no
// `leds`: most robots of most behaviours never light them).
nlohmann::json leds_json(const std::array<Rgb, kLedCount>& leds);

}  // namespace swarmform::viewer
