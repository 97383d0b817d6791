// Lockstep's slow agents. In lockstep slowness is never death: an owner whose liveliness is lost while its
// process is still there (stopped, starved, swapped out) is a straggler, not a death. The world keeps its
// robot, keeps awaiting its command for the round (the lockstep deadline does not pass it by) and takes it
// back as it was (same controller, same trajectory) when its liveliness or a sample of it comes back. A
// straggler becomes a death when its process goes. Waiting is bounded as every lockstep wait is: by the
// scenario's lockstep_deadline (Server::collect_lockstep). Pure bookkeeping.
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
  // How often a straggler's process is looked at (its exit makes it a death).
  static constexpr dds_duration_t kRecheck = DDS_MSECS(100);

  // `writer` (owner of `id`) was lost. False if it already was a straggler.
  bool add(dds::PublicationHandle writer, RobotId id);
  // It came back or died: the robot it owned, if it was a straggler.
  std::optional<RobotId> remove(dds::PublicationHandle writer);
  bool contains(dds::PublicationHandle writer) const { return by_writer_.count(writer) != 0; }
  bool empty() const { return by_writer_.empty(); }
  std::size_t size() const { return by_writer_.size(); }
  // Time to look at their processes again (at most every kRecheck of real time `now`).
  bool recheck_due(dds_time_t now);

  template <typename F>
  void for_each(F&& f) const {
    for (const auto& [writer, id] : by_writer_) f(writer, id);
  }

  std::size_t total() const { return total_; }          // stragglers in all
  std::size_t came_back() const { return came_back_; }  // of them, back (not deaths)
  void note_came_back() { ++came_back_; }

 private:
  std::unordered_map<dds::PublicationHandle, RobotId> by_writer_;
  dds_time_t next_check_ = 0;
  std::size_t total_ = 0;
  std::size_t came_back_ = 0;
};

}  // namespace swarmform::server
