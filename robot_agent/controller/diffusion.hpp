// A built-in that reads the Khepera IV's optional sensors (mission.behaviour = "diffusion"), after ARGoS's
// classic diffusion example: drive straight at the speed limit; when the infrared ring
// (Perception::proximity) sees something ahead, turn on the spot towards the side where the lidar sees more
// room (when the scenario's lidar sees any difference; else away from the side the ring sees more); drive
// slower on a dark floor (the ground sensors' mean grey g: speed limit x (0.25 + 0.75 g)). It declares the
// three sensors, so the world computes them; it broadcasts its id (a RobotMessage in state Idle) like the
// random walk. It has no randomness: what it does depends on its readings alone, so a wrong or missing
// reading on any path (the wire, the --exec protocol) changes the run's trajectory.
#pragma once

#include <array>
#include <vector>

#include "behaviour/controller.hpp"

namespace swarmform::controller {

// Which way to turn on the spot away from what the front half of the infrared ring sees above `threshold`:
// +1 counter-clockwise (left), -1 clockwise, 0 nothing ahead. The side that sees more is turned away from.
int ir_avoid_turn(const std::array<double, kProximityCount>& proximity, double threshold);

// Which side the lidar's scan sees more room on: +1 left (the sum of range x sin(angle) over the rays is
// positive), -1 right, 0 neither (or no scan).
int lidar_open_side(const std::vector<LidarRay>& scan);

class Diffusion final : public Controller {
 public:
  // A front-half proximity reading above this turns the robot (4.14 exp(-33 d) - 0.085 = 0.1: d ~ 0.11 m).
  static constexpr double kTurnThreshold = 0.1;

  void init(const Mission& mission, RobotId self) override;
  Command step(const Perception& perception) override;
  void reset() override {}

 private:
  Mission mission_;
  RobotId self_ = 0;
};

}  // namespace swarmform::controller
