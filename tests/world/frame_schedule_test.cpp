// world_server/frame_schedule.hpp: the frames the world offers its viewer, with a clock made by the test.
#include "world_server/frame_schedule.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace {

using swarmform::server::FrameSchedule;
constexpr std::int64_t kMs = 1000000;
constexpr std::int64_t kPeriod = 100 * kMs;  // 10 frames a second

// Ticks at the given times (ns); a frame is offered at each tick when due. Returns the times of the frames
// sent.
std::vector<std::int64_t> frames_at(const std::vector<std::int64_t>& ticks) {
  FrameSchedule s;
  std::vector<std::int64_t> sent;
  for (const std::int64_t t : ticks) {
    if (!s.due(t, kPeriod)) continue;
    s.sent(t, kPeriod);
    sent.push_back(t);
  }
  return sent;
}

TEST(FrameSchedule, TicksAtTheFrameRateEachMakeAFrameThoughSomeComeEarly) {
  // Realtime at 10 ticks/s: ticks 100 ms apart, every other one a millisecond early (the old rule, "a period
  // since the last frame", skipped those: 6 frames a second).
  std::vector<std::int64_t> ticks;
  for (std::int64_t k = 0; k < 100; ++k) ticks.push_back(1000 * kMs + k * kPeriod - (k % 2 == 1 ? kMs : 0));
  EXPECT_EQ(frames_at(ticks).size(), ticks.size());
}

TEST(FrameSchedule, ALateFrameDoesNotMakeTheNextTickLookEarly) {
  // Realtime at 10 ticks/s on a busy host: each third tick's frame 40 ms late, the tick after it 40 ms early
  // (a round's packets took long, then short), so those two frames are 20 ms apart. Each is near its own
  // slot: every tick is a frame. (Slots that restarted at the late frame took the early one for too soon.)
  std::vector<std::int64_t> ticks;
  for (std::int64_t k = 0; k < 99; ++k) {
    const std::int64_t wobble = k % 3 == 1 ? 40 * kMs : k % 3 == 2 ? -40 * kMs : 0;
    ticks.push_back(1000 * kMs + k * kPeriod + wobble);
  }
  EXPECT_EQ(frames_at(ticks).size(), ticks.size());
}

TEST(FrameSchedule, FastTicksMakeTheFrameRateAndNoMore) {
  // Lockstep uncapped: a tick every millisecond for 10 s: 100 frames, 100 ms apart.
  std::vector<std::int64_t> ticks;
  for (std::int64_t k = 0; k < 10000; ++k) ticks.push_back(5000 * kMs + k * kMs);
  const std::vector<std::int64_t> sent = frames_at(ticks);
  ASSERT_GE(sent.size(), 100u);
  EXPECT_LE(sent.size(), 101u);
  for (std::size_t i = 1; i < sent.size(); ++i) EXPECT_GE(sent[i] - sent[i - 1], kPeriod / 2);
}

TEST(FrameSchedule, APauseMakesNoBurstAfterIt) {
  // Fast ticks, a 5 s gap, fast ticks for 1 s again: the slots the gap missed are not caught up on (a
  // schedule kept from before the gap would send a frame at every tick until it had caught up 50 slots).
  std::vector<std::int64_t> ticks;
  for (std::int64_t k = 0; k < 1000; ++k) ticks.push_back(k * kMs);
  for (std::int64_t k = 0; k < 1000; ++k) ticks.push_back(6000 * kMs + k * kMs);
  const std::vector<std::int64_t> sent = frames_at(ticks);
  int after = 0;
  for (std::size_t i = 0; i < sent.size(); ++i) {
    if (sent[i] < 6000 * kMs) continue;
    ++after;
    if (i > 0) {
      EXPECT_GE(sent[i] - sent[i - 1], kPeriod / 2) << "frame " << i;
    }
  }
  EXPECT_GE(after, 10);
  EXPECT_LE(after, 11);
}

}  // namespace
