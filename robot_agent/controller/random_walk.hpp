// A simple wandering behaviour, kept as a selectable one (mission.behaviour = "random_walk"): drive
// forward at the speed limit with a random turn rate redrawn every few seconds, turn away on the spot from
// anything the ultrasonic sensors see closer than the avoidance distance, and broadcast the robot's id (a
// RobotMessage in state Idle, so any listener decodes it with the one codec). Randomness: a generator
// seeded from mission.seed ^ id, so a run is reproducible and robots differ.
#pragma once

#include <cstdint>
#include <random>

#include "behaviour/controller.hpp"

namespace swarmform::controller {

class RandomWalk final : public Controller {
 public:
  // Ultrasonic readings under this make the robot turn away, m.
  static constexpr double kAvoidDistance = 0.5;

  void init(const Mission& mission, RobotId self) override;
  Command step(const Perception& perception) override;
  void reset() override;

 private:
  void draw_leg();

  Mission mission_;
  RobotId self_ = 0;
  std::mt19937_64 rng_;
  double turn_rate_ = 0.0;  // rad/s of the current leg
  int leg_ticks_left_ = 0;
  int avoid_sign_ = 0;  // +1 turn left, -1 turn right, 0 not avoiding
};

}  // namespace swarmform::controller
