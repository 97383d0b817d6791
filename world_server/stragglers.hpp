// Lockstep's slow agents. In lockstep slowness is never death: an owner whose liveliness is lost while its
// process is still there (stopped, starved, swapped out) is a straggler, not a death. The world keeps its
// robot, keeps awaiting its command for the round (the lockstep deadline does not pass it by) and takes it
// back as it was (same controller, same trajectory) when its liveliness or a sample of it comes back. A
// straggler becomes a death when its process goes. Waiting is bounded: when the oldest straggler has been
// waited for kLimit of the world's awake time, the run ends (`agents_stalled`). Pure bookkeeping.
#pragma once

#include <cstddef>
#include <optional>
#include <unordered_map>

#include "common/dds/identity.hpp"
#include "common/dds/qos.hpp"
#include "common/types.hpp"

namespace swarmform::server {

class Stragglers {
 public:
  // Longer than the agents' own 10 s timeout for packets: an agent stopped that long cannot resume anyway.
  static constexpr dds_duration_t kLimit = DDS_SECS(30);
  // How often a straggler's process is looked at (its exit makes it a death).
  static constexpr dds_duration_t kRecheck = DDS_MSECS(100);

  // `writer` (owner of `id`) was lost at awake time `awake`. False if it already was a straggler.
  bool add(dds::PublicationHandle writer, RobotId id, dds_time_t awake);
  // It came back or died: the robot it owned, if it was a straggler.
  std::optional<RobotId> remove(dds::PublicationHandle writer);
  bool contains(dds::PublicationHandle writer) const { return by_writer_.count(writer) != 0; }
  bool holds(RobotId id) const;
  bool empty() const { return by_writer_.empty(); }
  std::size_t size() const { return by_writer_.size(); }
  // Waited for longer than kLimit at awake time `awake`.
  bool overdue(dds_time_t awake) const;
  // Time to look at their processes again (at most every kRecheck of real time `now`).
  bool recheck_due(dds_time_t now);

  template <typename F>
  void for_each(F&& f) const {
    for (const auto& [writer, s] : by_writer_) f(writer, s.id);
  }

  std::size_t total() const { return total_; }          // stragglers in all
  std::size_t came_back() const { return came_back_; }  // of them, back (not deaths)
  void note_came_back() { ++came_back_; }

 private:
  struct Straggler {
    RobotId id = 0;
    dds_time_t since = 0;
  };
  std::unordered_map<dds::PublicationHandle, Straggler> by_writer_;
  dds_time_t next_check_ = 0;
  std::size_t total_ = 0;
  std::size_t came_back_ = 0;
};

}  // namespace swarmform::server
