// The motion phases' factory: the paper's Ready, Motion and Arrived phases (motion_phase.hpp).
#include "robot_agent/controller/motion_hooks.hpp"
#include "robot_agent/controller/motion_phase.hpp"

namespace swarmform::controller {

std::unique_ptr<MotionPhases> make_motion_phases(const FormationParams& params) {
  return std::make_unique<motion::PaperMotion>(params);
}

}  // namespace swarmform::controller
