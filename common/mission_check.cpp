#include "common/mission_check.hpp"

#include <cmath>

#include "common/input_error.hpp"
#include "common/shape.hpp"

namespace swarmform {

namespace {

void positive(double v, const char* name, const std::string& origin) {
  if (!std::isfinite(v) || v <= 0.0) {
    throw InputError(origin, 0, std::string(name) + " " + std::to_string(v) + " is not a finite number > 0");
  }
}

}  // namespace

void check_mission(const Mission& m, const std::string& origin) {
  for (const int c : m.shape.cells) {
    if (c < -1) throw InputError(origin, 0, "shape cell " + std::to_string(c) + " below -1");
  }
  // No shape at all (0 x 0) is a behaviour that forms none; the registry refuses it to one that needs a
  // shape.
  if (m.shape.rows != 0 || m.shape.cols != 0 || !m.shape.cells.empty()) check_shape(m.shape, origin);
  positive(m.grid_spacing, "grid_spacing", origin);
  positive(m.max_speed, "max_speed", origin);
  positive(m.tick_rate, "tick_rate", origin);
  positive(m.comm_range, "comm_range", origin);
  if (!std::isfinite(m.goal.x) || !std::isfinite(m.goal.y)) throw InputError(origin, 0, "goal is not finite");
  if (!std::isfinite(m.goal_radius) || m.goal_radius < 0.0) {
    throw InputError(origin, 0,
                     "goal_radius " + std::to_string(m.goal_radius) + " is not a finite number >= 0");
  }
  for (const auto& [name, value] : m.params) {
    if (name.empty()) throw InputError(origin, 0, "a controller parameter without a name");
    if (!std::isfinite(value)) throw InputError(origin, 0, "controller parameter " + name + " is not finite");
  }
}

}  // namespace swarmform
