// When the world offers its viewer a frame (world_server/viewer_control.hpp offer_frame): on a schedule of
// slots a period apart, each due from half a period before it. The rule "a period since the last frame"
// skipped every tick that came a moment early when the tick rate equals the frame rate (realtime, 10 ticks/s,
// 10 frames/s): the next frame then went a period late, 6 frames/s with gaps of 200 ms. Slots never start
// before the last frame, so a pause or a slow stretch makes no burst of frames after it.
#pragma once

#include <algorithm>
#include <cstdint>

namespace swarmform::server {

class FrameSchedule {
 public:
  // `now`, `period`: ns (dds_time()).
  bool due(std::int64_t now, std::int64_t period) const { return now >= next_ - period / 2; }
  void sent(std::int64_t now, std::int64_t period) { next_ = std::max(next_, now) + period; }

 private:
  std::int64_t next_ = 0;  // the next frame's slot
};

}  // namespace swarmform::server
