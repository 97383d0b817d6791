// The controller's states as integers, shared by the controller (which reports them in Telemetry::state) and
// the world's recorder and metrics (which read them). Paper section III.C, Fig. 2, plus the motion phases.
#pragma once

#include <cstdint>
#include <string_view>

namespace swarmform {

enum class RobotState : std::int32_t {
  Idle = 0,       // no mission yet, or a behaviour without states (random walk)
  Searching = 1,  // no label; listening for free labels (spares stay here)
  Moving = 2,     // has a label, going to its place relative to its parent label's robot
  Reached = 3,    // at its place; orienting, then writing its id into the stigmergy barrier
  Ready = 4,      // barrier passed: boundary, leader and parent tree; reference forces recorded (eq. 2)
  Motion = 5,     // formation motion to the goal (eq. 3-7)
  Arrived = 6,    // within the goal radius: forces are zero
};

constexpr std::string_view to_string(RobotState s) {
  switch (s) {
    case RobotState::Idle:
      return "idle";
    case RobotState::Searching:
      return "searching";
    case RobotState::Moving:
      return "moving";
    case RobotState::Reached:
      return "reached";
    case RobotState::Ready:
      return "ready";
    case RobotState::Motion:
      return "motion";
    case RobotState::Arrived:
      return "arrived";
  }
  return "unknown";
}

}  // namespace swarmform
