#include "robot_agent/controller/progress_window.hpp"

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

bool ProgressWindow::update(Vec2 position, double desired_speed, Tick tick, double tick_rate) {
  asked_ += desired_speed / tick_rate;
  if (tick < anchor_tick_ + kPinnedTicks) return false;
  const bool pinned = asked_ > kMinAsked && vnorm(vsub(position, anchor_)) < kProgressShare * asked_;
  restart(position, tick);
  return pinned;
}

}  // namespace swarmform::controller::motion
