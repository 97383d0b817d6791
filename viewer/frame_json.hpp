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

// A robot's optional sensors' readings in a frame (common/sensor_readings.hpp: the Sensor bits `equipped`,
// then their values), each under its name: "proximity", "light", "ground" (lists), "lidar" ({rays,
// nearest_angle, nearest_range}), "battery". The live frames and the replay's both, so that the robot panel
// shows the same either way. Nothing when the values do not add up to what `equipped` says.
void add_readings(std::uint32_t equipped, const std::vector<double>& readings, nlohmann::json& robot);

}  // namespace swarmform::viewer
