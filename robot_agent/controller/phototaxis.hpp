// A built-in that goes to the light (mission.behaviour = "phototaxis"), after ARGoS's classic phototaxis
// example on the Khepera IV's optional sensors: it steers towards the light sensors' weighted direction
// (Perception::light), turns on the spot away from what the infrared ring sees ahead (ir_avoid_turn), and
// stops once its battery (Perception::battery) is under kReserve, so that it has charge left to be found.
// Without light it spins slowly to look for one. It declares light, proximity and battery, and broadcasts its
// id (a RobotMessage in state Idle) like the random walk. No randomness: its motion depends on its readings
// alone, so a wrong reading on any path (the wire, the --exec protocol) changes the run's trajectory.
#pragma once

#include "behaviour/controller.hpp"

namespace swarmform::controller {

class Phototaxis final : public Controller {
 public:
  static constexpr double kTurnThreshold = 0.1;  // proximity reading that turns the robot away
  static constexpr double kReserve = 0.05;       // battery charge under which it stops

  void init(const Mission& mission, RobotId self) override;
  Command step(const Perception& perception) override;
  void reset() override {}

 private:
  Mission mission_;
  RobotId self_ = 0;
};

}  // namespace swarmform::controller
