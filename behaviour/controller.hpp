// The controller interface, after ARGoS's CCI_Controller: init, control step, reset. A controller is pure: it
// sees one tick's Perception and returns one Command; it knows nothing of DDS or Bullet, so every behaviour
// can be unit-tested in-process and the same object runs in a robot_agent process or in the in-process
// harness. Part of the installed behaviour API (docs/behaviour-api.md).
#pragma once

#include "common/mission.hpp"
#include "common/types.hpp"

namespace swarmform::controller {

class Controller {
 public:
  virtual ~Controller() = default;
  // Called once with the mission and the robot's own id, before the first step. Throw
  // swarmform::InputError for a mission this behaviour cannot run (the agent exits 2 naming it).
  virtual void init(const Mission& mission, RobotId self) = 0;
  // One control step: this tick's perception in, this tick's command out. Wheel speeds must be finite.
  virtual Command step(const Perception& perception) = 0;
  // Back to the state right after init (a robot restarted with the same id calls init again instead).
  virtual void reset() = 0;
};

}  // namespace swarmform::controller
