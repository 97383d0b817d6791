// The wheel command: a desired velocity in the arena frame (what the force laws of the paper produce) turned
// into differential wheel speeds within the speed limit. Shared by every phase (formation and motion).
#pragma once

#include "common/types.hpp"

namespace swarmform::controller {

struct WheelSpeeds {
  double left = 0.0;   // m/s
  double right = 0.0;  // m/s
};

// Differential drive towards `velocity` (arena frame, m/s): the forward speed is the velocity's component
// along the heading (the robot drives backwards when the target is behind it, so small corrections do not
// need a half turn), the turn rate is proportional to the heading error. Both wheels stay within
// `max_speed`; the turn has priority over the forward speed when they compete. `may_reverse` false: always
// forwards, turning first (the ultrasonic sensors cover only the front half: a robot that must see where it
// goes faces it).
WheelSpeeds drive_velocity(Vec2 velocity, double heading, double max_speed, bool may_reverse = true);

// Turn in place towards `target_heading` (arena frame, rad), proportionally, within `max_speed`.
WheelSpeeds turn_towards(double target_heading, double heading, double max_speed);

// Clamps both wheels into [-max_speed, max_speed] keeping their ratio (so the curvature is kept).
WheelSpeeds clamp_wheels(WheelSpeeds w, double max_speed);

}  // namespace swarmform::controller
