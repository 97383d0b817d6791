// The optional sensors' readings (Perception's proximity, light, ground, lidar, battery) as one flat list of
// numbers, in one layout shared by everything that carries them outside the world: the viewers' frames
// (observe_wire.hpp) and the recording's readings.csv (docs/recording-format.md). One layout, so that the
// replay shows exactly what the live view shows.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "behaviour/descriptor.hpp"
#include "common/types.hpp"

namespace swarmform {

struct SensorReadingsLayout {
  std::uint32_t bit;  // behaviour::Sensor
  std::size_t count;  // values it takes
  const char* name;   // the frames' key and the recording's column prefix
};

// In bit order. The lidar takes 3 values: its ray count, then the angle (rad, robot frame) and the range (m)
// of its nearest ray. Its whole scan (682 rays by default) would cost a frame up to 11 KB a robot and
// readings.csv ~25 KB a robot a tick; a run is reproducible from its scenario and seed when the rays are
// wanted.
inline constexpr std::array<SensorReadingsLayout, 5> kSensorReadings = {{
    {behaviour::kProximity, kProximityCount, "proximity"},
    {behaviour::kLight, kLightCount, "light"},
    {behaviour::kGround, kGroundCount, "ground"},
    {behaviour::kLidar, 3, "lidar"},
    {behaviour::kBattery, 1, "battery"},
}};

// The values `equipped` (Sensor bits) takes in all.
std::size_t sensor_readings_count(std::uint32_t equipped);

// A perception's optional sensors into `equipped` and `readings` (kSensorReadings), storage reused.
void pack_sensor_readings(const Perception& p, std::uint32_t& equipped, std::vector<double>& readings);

// readings.csv's columns for the sensors `equipped`, in the layout's order: proximity0..proximity7,
// light0..light7, ground0..ground3, lidar_rays, lidar_nearest_angle, lidar_nearest_range, battery.
std::vector<std::string> sensor_reading_columns(std::uint32_t equipped);

}  // namespace swarmform
