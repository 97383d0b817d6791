// The Khepera IV's battery, after ARGoS's battery model (argos3 CBatteryEquippedEntity, "time_motion"
// discharge: a charge lost per tick and one per unit of motion): a capacity in joules, an idle draw (W) every
// tick a robot is alive and a moving draw (J per metre of wheel travel: the mean of the two wheels'
// distances, from the robot's true motion over the tick). The controller reads charge / capacity (0..1). A
// battery that reaches 0 stays at 0 and its robot's wheels stop for the rest of the run (it still senses and
// talks): an event, not a crash.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "common/types.hpp"

namespace swarmform::world {

struct BatterySpec {
  double capacity = 0.0;  // J, > 0
  double idle = 0.0;      // W
  double moving = 0.0;    // J per metre of wheel travel
  double start = 1.0;     // charge at tick 0, fraction of the capacity
};

// The mean distance the two wheels travelled when a robot moved from `a` to `b` (differential drive: the
// centre's advance along the mean heading, and the turn shared out over the wheel spacing).
double wheel_travel(const Pose2D& a, const Pose2D& b);

class Batteries {
 public:
  Batteries(const BatterySpec& spec, std::size_t robots, double tick_rate);

  // One tick of robot i, which moved from `before` to `after`; true when this tick emptied it.
  bool drain(std::size_t i, const Pose2D& before, const Pose2D& after);
  double level(std::size_t i) const { return charge_[i] / spec_.capacity; }  // 0..1
  bool empty(std::size_t i) const { return charge_[i] <= 0.0; }

 private:
  BatterySpec spec_;
  double idle_per_tick_;
  std::vector<double> charge_;  // J
};

}  // namespace swarmform::world
