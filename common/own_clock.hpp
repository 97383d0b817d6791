// A process's own clock of progress: wall time minus the time the process itself was not running (SIGSTOP, a
// swapped or overloaded host). Its loop promises to call observe() at least every `max_gap`; any longer gap
// between two calls was the process's own stall, and only `max_gap` of it counts as awake. Deadlines that
// judge others (an agent's lease at the world, the world's silence at an agent) are measured on this clock,
// so a process's own pause never makes it blame the others (docs/wire.md "Liveliness, stalls and deaths").
// Pure: no DDS.
#pragma once

#include <cstdint>
#include <limits>

namespace swarmform {

class OwnClock {
 public:
  // `max_gap_ns`: the longest interval between two observe() calls the owner's loop allows itself.
  explicit OwnClock(std::int64_t max_gap_ns) : max_gap_(max_gap_ns) {}

  // Called at every wake-up with the wall time (ns, monotonic); returns the awake time (ns).
  std::int64_t observe(std::int64_t now) {
    if (last_ != kNever && now - last_ > max_gap_) {
      stalled_ += now - last_ - max_gap_;
      ++stalls_;
      last_stall_end_ = now - stalled_;
    }
    last_ = now;
    return now - stalled_;
  }
  // The awake time as of the last observe().
  std::int64_t awake() const { return last_ == kNever ? 0 : last_ - stalled_; }
  // Awake time at which the last own stall ended (a very old time when there was none).
  std::int64_t last_stall_end() const { return last_stall_end_; }
  std::int64_t stalled_total() const { return stalled_; }
  std::uint64_t stalls() const { return stalls_; }

 private:
  static constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::min();
  std::int64_t max_gap_;
  std::int64_t last_ = kNever;
  std::int64_t stalled_ = 0;
  std::int64_t last_stall_end_ = kNever / 2;
  std::uint64_t stalls_ = 0;
};

}  // namespace swarmform
