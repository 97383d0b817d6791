// Realtime deaths that come together. A realtime run keeps its deadlines: an owner whose liveliness lapses is
// dead, whatever the reason. But when several lapse within one liveliness lease of each other, the likelier
// cause is one event of the host (load, a stopped process group, a suspended VM, a cut link), not that many
// independent deaths, and the run says so: one `mass_loss` event and a summary entry naming the robots, how
// close together they went and how many of their processes were still there (all: a stopped host; none: the
// agents exited together). Deaths the world caused (kills) or saw happen (an exit while it waited for a
// straggler) are not lapses and are never grouped. Pure bookkeeping on the world's awake clock.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "common/dds/qos.hpp"
#include "common/types.hpp"

namespace swarmform::server {

class MassLoss {
 public:
  // Deaths within one lease of a group's first belong to it: agents stopped together lapse within one assert
  // period of each other.
  static constexpr dds_duration_t kWindow = dds::kLivelinessLease;
  // A loss noticed right after the world's own stall (a loaded host) is only suspected, and recorded dead up
  // to StallGuard::kGrace later, with the time it was noticed: a group stays open that much longer, or one
  // host event whose lapses straddle a stall of the world's is split in two.
  static constexpr dds_duration_t kLate = DDS_MSECS(1500);

  struct Group {
    Tick tick = 0;         // the first death's tick
    dds_time_t first = 0;  // the earliest and latest losses' times
    dds_time_t last = 0;
    std::vector<RobotId> robots;
    std::size_t processes_present =
        0;  // of `robots`, processes seen still there when they were taken for dead
  };

  // `id`'s liveliness lapsed, noticed at `lost_at` (awake time; a suspected loss's suspicion), and it was
  // taken for dead at tick `tick`; `process_present`: its process was still there. Returns a group this death
  // closed (the next one began), if it was a mass loss.
  std::optional<Group> died(RobotId id, Tick tick, dds_time_t lost_at, bool process_present);
  // The open group, once `now` is past its window and kLate, if it was a mass loss (two robots or more). At
  // the end of the run pass the largest time there is.
  std::optional<Group> close(dds_time_t now);
  // The mass losses closed so far.
  const std::vector<Group>& groups() const { return closed_; }

 private:
  std::optional<Group> finish();
  std::optional<Group> open_;
  std::vector<Group> closed_;
};

}  // namespace swarmform::server
