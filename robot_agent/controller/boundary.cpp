#include "robot_agent/controller/boundary.hpp"

#include <cmath>
#include <numbers>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

BoundaryRole classify_boundary(const std::vector<NeighbourAzimuth>& neighbours, double heading,
                               double max_range, double cone_half_angle) {
  constexpr double kHalfPi = std::numbers::pi / 2.0;
  BoundaryRole role{true, true};
  for (const auto& n : neighbours) {
    if (n.range > max_range) continue;  // beyond the 3x3 grid: not a shape neighbour
    const double relative = wrap_angle(n.azimuth - heading);
    if (std::abs(wrap_angle(relative - kHalfPi)) < cone_half_angle) role.left = false;
    if (std::abs(wrap_angle(relative + kHalfPi)) < cone_half_angle) role.right = false;
  }
  return role;
}

std::int64_t encode_boundary_entry(int label, BoundaryRole role) {
  return static_cast<std::int64_t>(label) * 4 + (role.left ? 1 : 0) + (role.right ? 2 : 0);
}

BoundaryEntry decode_boundary_entry(std::int64_t value) {
  if (value < 0) return {};
  BoundaryEntry e;
  e.label = static_cast<int>(value / 4);
  e.role.left = (value & 1) != 0;
  e.role.right = (value & 2) != 0;
  return e;
}

}  // namespace swarmform::controller::motion
