// Realtime mode: where the time went when a command missed its tick (BENCHMARKS.md, P2). A robot counted
// missed at tick t is remembered with that round's start, the moment its packet was written and the round's
// deadline (the start of t+1). When its command for t turns up later, the wait splits into three parts:
//   written   the packet written this long into the round (the world's publish phase);
//   answered  the agent's command sent this long after its packet was written (the agent's wake-up, control
//             step and write; `sent` is the writer's source timestamp, the same clock on one host);
//   transit   the command taken by the world's main loop this long after it was sent: delivery, the world's
//             receive thread, and the main loop itself, which takes commands only between its phases (a
//             command that comes in while it writes the next round's packets waits for the end of that).
// Plain C++ without DDS, so that the arithmetic is unit-tested on its own.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"

namespace swarmform::server {

struct LateCommand {
  double written_ms = 0.0;
  double answered_ms = 0.0;
  double transit_ms = 0.0;
  double late_ms = 0.0;    // received after the deadline
  bool sent_late = false;  // sent after the deadline already
};

class LateCommands {
 public:
  explicit LateCommands(std::size_t robots) : open_(robots) {}

  // Times in ns on one clock (dds_time()). A later miss of the same robot replaces an open one.
  void missed(RobotId id, Tick tick, std::int64_t round_start, std::int64_t written, std::int64_t deadline);
  // A command of `id` for `tick`, sent and received at these times: the breakdown when it answers an open
  // miss (which it closes), else nullopt.
  std::optional<LateCommand> arrived(RobotId id, Tick tick, std::int64_t sent, std::int64_t received);

  std::size_t count() const { return late_.size(); }
  // "K late commands (S sent after the deadline): packet written M ms into the round (median; max X), ..."
  std::string summary() const;

 private:
  struct Open {
    bool open = false;
    Tick tick = 0;
    std::int64_t round_start = 0, written = 0, deadline = 0;
  };
  std::vector<Open> open_;
  std::vector<LateCommand> late_;
};

}  // namespace swarmform::server
