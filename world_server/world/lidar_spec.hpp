// The lidar's fan as the scenario gives it (scenario `lidar`, docs/scenario-format.md); what it measures:
// lidar.hpp.
#pragma once

#include <cstdint>

namespace swarmform::world {

// The scenario's `lidar` section; the defaults are ARGoS's Khepera IV's (lidar.hpp).
struct LidarSpec {
  std::uint32_t rays = 682;
  double fov = 3.6651914291880923;  // rad, 210 degrees
  double min_range = 0.02;          // m, from the body's edge
  double max_range = 4.0;           // m
};

}  // namespace swarmform::world
