#include "common/sensor_readings.hpp"

#include <algorithm>

namespace swarmform {

std::size_t sensor_readings_count(std::uint32_t equipped) {
  std::size_t n = 0;
  for (const SensorReadingsLayout& s : kSensorReadings) n += (equipped & s.bit) ? s.count : 0;
  return n;
}

void pack_sensor_readings(const Perception& p, std::uint32_t& equipped, std::vector<double>& readings) {
  equipped = 0;
  readings.clear();
  auto put = [&](std::uint32_t bit, const auto& values) {
    equipped |= bit;
    readings.insert(readings.end(), values.begin(), values.end());
  };
  if (p.proximity) put(behaviour::kProximity, *p.proximity);
  if (p.light) put(behaviour::kLight, *p.light);
  if (p.ground) put(behaviour::kGround, *p.ground);
  if (!p.lidar.empty()) {
    const auto nearest =
        std::min_element(p.lidar.begin(), p.lidar.end(),
                         [](const LidarRay& a, const LidarRay& b) { return a.range < b.range; });
    put(behaviour::kLidar,
        std::array<double, 3>{static_cast<double>(p.lidar.size()), nearest->angle, nearest->range});
  }
  if (p.battery) put(behaviour::kBattery, std::array<double, 1>{*p.battery});
}

std::vector<std::string> sensor_reading_columns(std::uint32_t equipped) {
  std::vector<std::string> out;
  for (const SensorReadingsLayout& s : kSensorReadings) {
    if ((equipped & s.bit) == 0) continue;
    if (s.bit == behaviour::kLidar) {
      for (const char* c : {"lidar_rays", "lidar_nearest_angle", "lidar_nearest_range"}) out.emplace_back(c);
    } else if (s.count == 1) {
      out.emplace_back(s.name);
    } else {
      for (std::size_t k = 0; k < s.count; ++k) out.push_back(s.name + std::to_string(k));
    }
  }
  return out;
}

}  // namespace swarmform
