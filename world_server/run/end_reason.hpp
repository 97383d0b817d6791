// Why a run stopped: summary.json's `end_reason` (docs/recording-format.md), the same words for both front
// ends (world_server and swarm_inprocess).
#pragma once

#include <cerrno>
#include <stdexcept>
#include <string>
#include <string_view>

namespace swarmform::world {

enum class EndReason {
  Completed,        // arrived at the goal (and the settle ticks after it were recorded)
  MaxTicks,         // the scenario's max_ticks used up
  Interrupted,      // SIGINT/SIGTERM
  WorldFailed,      // the world could not go on (a failed write other than a full disk, a DDS failure)
  DiskFull,         // a write of the recording failed with ENOSPC or EDQUOT
  NoAgents,         // not every agent connected within --connect-timeout
  BehaviourFailed,  // in-process: a robot's controller threw or returned a non-finite wheel speed
  AgentsStalled,    // lockstep: agents whose processes live but are silent (stopped, starved) past the wait's
                    // bound
};

constexpr std::string_view to_string(EndReason r) {
  switch (r) {
    case EndReason::Completed:
      return "completed";
    case EndReason::MaxTicks:
      return "max_ticks";
    case EndReason::Interrupted:
      return "interrupted";
    case EndReason::WorldFailed:
      return "world_failed";
    case EndReason::DiskFull:
      return "disk_full";
    case EndReason::NoAgents:
      return "no_agents";
    case EndReason::BehaviourFailed:
      return "behaviour_failed";
    case EndReason::AgentsStalled:
      return "agents_stalled";
  }
  return "unknown";
}

// A write of the run directory failed (the recorder throws it): `error` is the errno of the failure.
class RecordingError : public std::runtime_error {
 public:
  RecordingError(const std::string& what, int error) : std::runtime_error(what), error_(error) {}
  int error() const { return error_; }
  bool disk_full() const { return error_ == ENOSPC || error_ == EDQUOT; }
  EndReason reason() const { return disk_full() ? EndReason::DiskFull : EndReason::WorldFailed; }

 private:
  int error_;
};

}  // namespace swarmform::world
