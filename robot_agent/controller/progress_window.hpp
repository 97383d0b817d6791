// Pinned detection (motion_phase.hpp, "Pinned"): over each window of kPinnedTicks a robot moved less than
// kProgressShare of the way its desired motion asked for (and that was at least kMinAsked). Judged against
// what it asked for, not a fixed speed, so a follower of a leader that slows down is not pinned. The motion
// phase starts a boundary episode on it when an obstacle is remembered near.
#pragma once

#include "common/types.hpp"

namespace swarmform::controller::motion {

class ProgressWindow {
 public:
  static constexpr Tick kPinnedTicks = 20;
  static constexpr double kProgressShare = 0.25;  // of the way asked for
  static constexpr double kMinAsked = 0.05;       // m asked for over the window

  // A new window from here and now (Ready's start, the end of a boundary episode).
  void restart(Vec2 position, Tick tick) {
    anchor_ = position;
    anchor_tick_ = tick;
    asked_ = 0.0;
  }
  // Adds this tick's ask (`desired_speed` m/s for one tick). At a window's end: whether the robot was pinned
  // over it, and a new window starts; otherwise false.
  bool update(Vec2 position, double desired_speed, Tick tick, double tick_rate);

 private:
  Vec2 anchor_;  // where this window started, and when
  Tick anchor_tick_ = 0;
  double asked_ = 0.0;  // m the desired motion asked for since then
};

}  // namespace swarmform::controller::motion
