// Differential drive for controllers (docs/behaviour-api.md, "Driving"): a linear speed and a turn rate to
// the Khepera IV's two wheel speeds, scaled down together to the speed limit, so a turn keeps its radius at
// full speed and the world never has to clamp a command (which it counts). Part of the installed behaviour
// API.
#pragma once

#include <algorithm>
#include <cmath>

#include "common/types.hpp"

namespace swarmform::behaviour {

// v m/s ahead, w rad/s counter-clockwise, max_speed m/s (the mission's): sets c.left_speed and c.right_speed.
inline void drive(double v, double w, double max_speed, Command& c) {
  double l = v - w * kWheelSpacing / 2.0;
  double r = v + w * kWheelSpacing / 2.0;
  const double top = std::max(std::abs(l), std::abs(r));
  if (top > max_speed) {
    l *= max_speed / top;
    r *= max_speed / top;
  }
  // The scaling can land a rounding error above the limit, which the world would clamp and count.
  c.left_speed = std::clamp(l, -max_speed, max_speed);
  c.right_speed = std::clamp(r, -max_speed, max_speed);
}

}  // namespace swarmform::behaviour
