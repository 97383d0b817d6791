// What an agent does with a packet for a tick it answered already (docs/wire.md "Pace"). A lockstep world
// whose round waits long writes the awaited robots' packets again (world_server/README.md "A long lockstep
// round writes its packets again"): the first may never have arrived, or the answer to it may be what was
// lost. So a repeat is answered with the command sent for that tick, and the controller is never stepped
// twice for one tick: a second step would change its state (a random walker's leg, its draws) and the run
// would no longer be the undisturbed one. Pure: robot_agent/main.cpp holds one.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>

#include "common/types.hpp"

namespace swarmform::agent {

class AnswerMemory {
 public:
  enum class Verdict {
    Step,    // a tick not answered yet (or a new generation of the robot): step the controller
    Repeat,  // the tick answered last, again: send last() again
    Stale,   // an older tick of this generation: nothing
  };

  Verdict judge(Tick tick, std::uint32_t generation) const {
    if (!tick_ || generation != generation_) return Verdict::Step;
    if (tick == *tick_) return Verdict::Repeat;
    return tick < *tick_ ? Verdict::Stale : Verdict::Step;
  }

  void answered(Tick tick, std::uint32_t generation, Command command) {
    tick_ = tick;
    generation_ = generation;
    command_ = std::move(command);
  }

  const Command& last() const { return command_; }
  std::optional<Tick> last_tick() const { return tick_; }

 private:
  std::optional<Tick> tick_;
  std::uint32_t generation_ = 0;
  Command command_;
};

}  // namespace swarmform::agent
