// When the world offers its viewer a frame (world_server/viewer_control.hpp offer_frame): on a schedule of
// slots a period apart, each due from half a period before it. The rule "a period since the last frame"
// skipped every tick that came a moment early when the tick rate equals the frame rate (realtime, 10 ticks/s,
// 10 frames/s): the next frame then went a period late, 6 frames/s with gaps of 200 ms.
//
// A frame within half a period of its slot, early or late, fills that slot and the next slot stays a period
// after it: a frame that came late (a round whose packets took long on a busy host) does not make the next
// tick, on time, look early (slots that restarted at each late frame skipped that tick: 256 robots on 2
// cores lost 5-7 frames in 200). A frame further from its slot (the first, one after a pause or a stall)
// starts the slots again from itself, so a pause or a slow stretch leaves no backlog of slots to make a
// burst of frames after it.
#pragma once

#include <cstdint>

namespace swarmform::server {

class FrameSchedule {
 public:
  // `now`, `period`: ns (dds_time()).
  bool due(std::int64_t now, std::int64_t period) const { return now >= next_ - period / 2; }
  void sent(std::int64_t now, std::int64_t period) {
    next_ = now - next_ < period / 2 ? next_ + period : now + period;
  }

 private:
  std::int64_t next_ = 0;  // the next frame's slot
};

}  // namespace swarmform::server
