// The neighbours a robot hears, as Buzz's `neighbors` structure: id -> last range, bearing, decoded message
// and the tick it was last heard. A neighbour silent for its silence limit is dropped (taken for gone or
// dead): `neighbour_timeout` ticks, or twice the longest loss its link has come back from (learn_loss_gaps,
// silence_limit). The tick each id was last heard is kept after expiry too: the label-freeing rule needs to
// know that a robot was heard once and then fell silent (allotment.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/message.hpp"

namespace swarmform::controller {

// x the radio range: a neighbour last heard this near that is not heard now is lost or dead, not out of range
// (the motion's death rules, and the loss gaps a link learns from).
inline constexpr double kWellInsideRange = 0.8;

struct Neighbour {
  RobotId id = 0;
  double range = 0.0;    // m, as last heard
  double bearing = 0.0;  // rad, receiver's frame, as last heard
  double azimuth = 0.0;  // rad, arena frame: own heading at that tick + bearing
  MessageBody message;   // the last message decoded from it, but its stigmergy entries (below)
  Tick last_heard = 0;
  // Its stigmergy entries of this tick, in the table's entries_heard() (kept apart: see there).
  std::uint32_t entries_begin = 0;
  std::uint32_t entries_count = 0;
};

// id -> tick, an open-addressing hash table (linear probing, at most half full): one probe is one cache line,
// where a std::unordered_map lookup was a division and a chain of nodes, cold misses each. NeighbourTable
// keeps the tick each expired neighbour was last heard in one, and the label-freeing rule asks it for every
// grid label's holder that is not in radio range, every tick (a 1024-label shape: hundreds of expired ids).
class IdTicks {
 public:
  std::optional<Tick> find(RobotId id) const {
    if (slots_.empty()) return std::nullopt;
    for (std::size_t i = home(id);; i = (i + 1) & (slots_.size() - 1)) {
      const Slot& s = slots_[i];
      if (!s.used) return std::nullopt;
      if (s.id == id) return s.tick;
    }
  }
  void set(RobotId id, Tick tick);
  std::size_t size() const { return size_; }
  void clear() {
    slots_.clear();
    size_ = 0;
  }

 private:
  struct Slot {
    RobotId id = 0;
    std::uint32_t used = 0;
    Tick tick = 0;
  };
  std::size_t home(RobotId id) const {
    return static_cast<std::size_t>((static_cast<std::uint64_t>(id) * 0x9E3779B97F4A7C15ull) >> 32) &
           (slots_.size() - 1);
  }
  std::vector<Slot> slots_;  // a power of two long, or empty
  std::size_t size_ = 0;
};

// Sorted by id (iterates like a std::map<RobotId, Neighbour>). A flat array, not a tree: every message heard
// is one lookup (~73 a tick in a crowd) and every tick walks the whole table to expire the silent, where
// tree nodes cost a pointer chase each; new neighbours, the only inserts, are few per tick.
using NeighbourList = std::vector<std::pair<RobotId, Neighbour>>;

class NeighbourTable {
 public:
  explicit NeighbourTable(int timeout_ticks = 20) : timeout_(timeout_ticks) {}
  // A table that learns each link's losses (learn_loss_gaps) where its neighbour cannot have left radio range
  // meanwhile: heard before and after well inside it, and back sooner than two robots, each at `max_speed`,
  // could have opened the rest of the range between them and closed it again.
  static NeighbourTable learning_losses(int timeout_ticks, double comm_range, double max_speed,
                                        double tick_rate);

  // Takes this tick's readings: decodes each message (our own id is skipped; an undecodable or forged one
  // is dropped and counted, and its sender with it, remembered as last heard at its last good tick), then
  // expires the neighbours silent for the timeout. `own_digest`: the receiver's stigmergy
  // digest before it merges this tick's entries; a message whose table has that digest keeps no entries
  // (decode_message_into: every entry it carries is already in the receiver's table, or older, so merging
  // it after the others' newer entries still changes nothing). 0 keeps every message's entries.
  void update(const Perception& perception, RobotId self, std::uint64_t own_digest = 0);

  // A real radio loses packets in bursts: a link silent for longer than neighbour_timeout may be alive (a
  // Gilbert-Elliott link of 20 % loss in bursts of mean 5 ticks is silent 20 ticks or more about once in 70
  // bursts). Learn from each link what it has come back from: a silence that ended with the neighbour
  // heard again, both before and after it within `within_range` metres, and no longer than `max_gap` ticks
  // (the shortest time in which a neighbour that near could have left radio range and come back: a longer
  // one may have been out of range, not lost). 0 metres: learn nothing (every limit is the timeout).
  void learn_loss_gaps(double within_range, Tick max_gap) {
    learn_within_ = within_range;
    learn_max_gap_ = max_gap;
  }
  // How long `id` may stay silent before it is taken for gone: the timeout, or twice the longest loss its
  // link has come back from (the margin of a burst length's geometric tail).
  Tick silence_limit(RobotId id) const;

  // Neighbours heard within their silence limit.
  const NeighbourList& all() const { return live_; }
  // The stigmergy entries `n` sent this tick (none when it was not heard this tick, or when its table had
  // the receiver's digest). They are decoded into one buffer of the table's, not into each neighbour's
  // message: the buffer stays in cache from tick to tick, where ~73 neighbours' own vectors would be cold
  // lines written once and read once (BENCHMARKS.md, P3).
  std::span<const StigmergyEntry> entries_heard(const Neighbour& n) const {
    if (n.last_heard != now_) return {};
    return std::span<const StigmergyEntry>(heard_entries_).subspan(n.entries_begin, n.entries_count);
  }
  const Neighbour* find(RobotId id) const;
  // True when `id` was heard this very tick (its range and bearing are current).
  bool fresh(RobotId id) const;
  // The same for an entry of all() (no search: loops over all() call this for every neighbour).
  bool fresh(const Neighbour& n) const { return n.last_heard == now_; }
  // The tick `id` was last heard, also after it expired; nullopt if never heard.
  std::optional<Tick> last_heard(RobotId id) const;
  Tick now() const { return now_; }
  std::uint64_t dropped_messages() const { return dropped_; }

  void clear();

 private:
  // "No entry in live_": an id not in the table, or, in where_, a reading of our own.
  static constexpr std::uint32_t kNoEntry = 0xFFFFFFFF;
  std::uint32_t insert_position(RobotId id) const;  // the first index in ids_ not below `id`
  std::uint32_t index_of(RobotId id) const;         // the index of `id` in live_, or kNoEntry
  // Removes the entries flagged kDropped and the neighbours silent for the timeout, keeping ids_ beside
  // live_.
  void remove_dropped_and_expired();
  // learn_loss_gaps' rule, for a known neighbour heard again (`before`: its entry as it was).
  void learn_gap(RobotId id, const Neighbour& before, double range_now);

  int timeout_;
  Tick now_ = 0;
  NeighbourList live_;
  // live_'s ids on their own (ids_[i] == live_[i].first): a lookup searches 4-byte ids in a few cache lines
  // instead of loading a 208-byte entry per probe. At N = 1000 the tables of all robots (~15 MB) do not stay
  // in cache from one tick to the next, and each probe into live_ was a miss (BENCHMARKS.md, P3).
  std::vector<RobotId> ids_;
  // Scratch of update(), kept for its capacity: the readings from senders new this tick, the entry of each
  // reading, and each entry's status (one whose message was bad is removed once the pass is over, so that the
  // indices stay valid during it; a newcomer's bad message leaves no trace in expired_).
  enum Status : std::uint8_t { kKnown, kNew, kDropped };
  std::vector<std::size_t> newcomers_;  // the readings from new senders
  std::vector<std::uint32_t> where_;
  std::vector<Status> status_;
  std::vector<StigmergyEntry> heard_entries_;  // this tick's entries of all neighbours (entries_heard)
  // The tick each expired neighbour was last heard (a live one's is in live_): written only on expiry,
  // not for each message heard.
  IdTicks expired_;
  // id -> the longest silence learned from its link (learn_loss_gaps); kept after expiry.
  IdTicks loss_gaps_;
  double learn_within_ = 0.0;
  Tick learn_max_gap_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace swarmform::controller
