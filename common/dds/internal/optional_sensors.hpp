// The optional sensors of a Perception (common/types.hpp) to and from a SensorPacket: `equipped` holds the
// Sensor bits (behaviour/descriptor.hpp) of the readings present; a reading not present travels as zeros (the
// lidar: no values) and comes back empty (not equipped). Doubles are copied, so a reading arrives bit for
// bit.
#pragma once

#include <algorithm>
#include <array>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "behaviour/descriptor.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/types.hpp"

namespace swarmform::dds::internal {

template <std::size_t N>
void put_array(const std::optional<std::array<double, N>>& from, double (&to)[N], std::uint32_t bit,
               std::uint32_t& equipped) {
  if (from) {
    std::copy(from->begin(), from->end(), to);
    equipped |= bit;
  } else {
    std::fill(std::begin(to), std::end(to), 0.0);
  }
}

template <std::size_t N>
void take_array(const double (&from)[N], std::optional<std::array<double, N>>& to, std::uint32_t bit,
                std::uint32_t equipped) {
  if (equipped & bit) {
    to.emplace();
    std::copy(std::begin(from), std::end(from), to->begin());
  } else {
    to.reset();
  }
}

// `lidar` holds the packet's lidar values (angle, range per ray) until the sample is written.
inline void put_optional_sensors(const Perception& p, sfdds_SensorPacket& s, std::vector<double>& lidar) {
  std::uint32_t equipped = 0;
  put_array(p.proximity, s.proximity, behaviour::kProximity, equipped);
  put_array(p.light, s.light, behaviour::kLight, equipped);
  put_array(p.ground, s.ground, behaviour::kGround, equipped);
  s.battery = p.battery.value_or(0.0);
  if (p.battery) equipped |= behaviour::kBattery;
  lidar.clear();
  for (const LidarRay& r : p.lidar) {
    lidar.push_back(r.angle);
    lidar.push_back(r.range);
  }
  if (!p.lidar.empty()) equipped |= behaviour::kLidar;
  s.lidar._buffer = lidar.data();
  s.lidar._length = s.lidar._maximum = static_cast<std::uint32_t>(lidar.size());
  s.lidar._release = false;
  s.equipped = equipped;
}

inline void take_optional_sensors(const sfdds_SensorPacket& s, Perception& p) {
  take_array(s.proximity, p.proximity, behaviour::kProximity, s.equipped);
  take_array(s.light, p.light, behaviour::kLight, s.equipped);
  take_array(s.ground, p.ground, behaviour::kGround, s.equipped);
  p.battery = (s.equipped & behaviour::kBattery) ? std::optional<double>(s.battery) : std::nullopt;
  p.lidar.clear();
  if (s.equipped & behaviour::kLidar) {
    for (std::uint32_t k = 0; k + 1 < s.lidar._length; k += 2)
      p.lidar.push_back(LidarRay{s.lidar._buffer[k], s.lidar._buffer[k + 1]});
  }
}

// Why the packet's optional sensors cannot be read (empty: they can): the lidar's values come in pairs.
inline std::string optional_sensors_problem(const sfdds_SensorPacket& s) {
  if (s.lidar._length % 2 != 0)
    return "lidar: " + std::to_string(s.lidar._length) + " values, not an (angle, range) pair per ray";
  return {};
}

}  // namespace swarmform::dds::internal
