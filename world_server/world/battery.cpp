#include "world_server/world/battery.hpp"

#include <cmath>

#include "world_server/world/geometry.hpp"

namespace swarmform::world {

double wheel_travel(const Pose2D& a, const Pose2D& b) {
  const double turn = wrap_angle(b.theta - a.theta);
  const double mid = a.theta + turn / 2.0;
  const double advance = (b.x - a.x) * std::cos(mid) + (b.y - a.y) * std::sin(mid);
  const double half = turn * kWheelSpacing / 2.0;
  return (std::abs(advance - half) + std::abs(advance + half)) / 2.0;
}

Batteries::Batteries(const BatterySpec& spec, std::size_t robots, double tick_rate)
    : spec_(spec), idle_per_tick_(spec.idle / tick_rate), charge_(robots, spec.capacity * spec.start) {}

bool Batteries::drain(std::size_t i, const Pose2D& before, const Pose2D& after) {
  if (charge_[i] <= 0.0) return false;
  charge_[i] -= idle_per_tick_ + spec_.moving * wheel_travel(before, after);
  if (charge_[i] > 0.0) return false;
  charge_[i] = 0.0;
  return true;
}

}  // namespace swarmform::world
