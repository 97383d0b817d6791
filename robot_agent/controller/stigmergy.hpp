// Virtual stigmergy with Buzz semantics (Pinciroli & Beltrame): a key-value table replicated on every robot
// and carried by the neighbour messages, multi-hop.
//
// - Each entry: key (u32), value (i64), version (u32), writer (the id that put it).
// - put(): the local robot writes; the version becomes (the version it holds for that key) + 1.
// - merge(): a received entry replaces the local one when it is newer: a higher version wins; on an equal
//   version the higher writer id wins, then the higher value. The rule is a total order on (version, writer,
//   value), so every robot that has seen the same entries holds the same one, whatever the order they came
//   in: conflicts resolve the same way everywhere.
// - Flooding: an entry that changed locally (put, or a merge that took a newer entry) is sent in the next
//   kResendCount messages, the longest-waiting first (a queue, so none starves when more changed than a
//   message carries); the rest of each message's quota goes round-robin over the whole table, so every
//   entry keeps propagating even when copies are lost. A robot whose live neighbours all sent its own
//   table's digest sends no entries at all (paper_controller.cpp: neighbours_hold_our_table).
//
// - Digest: an order-independent 64-bit hash of the whole table (the sum of a hash of each entry), kept up
//   to date on every change and sent in each message. Two tables with the same digest are taken to be the
//   same table, so merging one into the other would change nothing: the receiver skips the entries
//   (paper_controller.cpp). A false match needs a 64-bit collision; a missed one only costs the merge.
//
// Key layout: namespace in the high 16 bits, index (a robot id or a label, < 65536) in the low 16.
//   1 Barrier   index = robot id   value = the label it holds when it passed Reached (barrier.hpp)
//   2 Labels    index = label      value = holder id (>= 0), or kLabelFreedBase - tick when freed (allotment)
//   3 Boundary  index = robot id   the motion phases' boundary roles (boundary.hpp)
//   4 Parents   index = robot id   the motion phases' parents table (parent_tree.hpp)
//   5 Leader    index = 0..        the motion phases' leader entries (leader_election.hpp); index 1:
//                                  the shape's turn after a goal move, in microradians (shape_turn.hpp)
//   6 Blocked   index = robot id   after a goal move: the torque (mm) with which the push off the surface
//                                  its place lies beyond turns the shape (0 free) (shape_turn.hpp)
//   7..15       reserved for the motion phases
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/message.hpp"

namespace swarmform::controller {

namespace stig {
enum class Ns : std::uint32_t { Barrier = 1, Labels = 2, Boundary = 3, Parents = 4, Leader = 5 };
inline constexpr std::uint32_t kMaxIndex = 0xFFFF;
inline constexpr std::uint32_t key(Ns ns, std::uint32_t index) {
  return (static_cast<std::uint32_t>(ns) << 16) | (index & kMaxIndex);
}
inline constexpr std::uint32_t key(std::uint32_t ns, std::uint32_t index) {
  return (ns << 16) | (index & kMaxIndex);
}
inline constexpr std::uint32_t ns_of(std::uint32_t key) {
  return key >> 16;
}
inline constexpr std::uint32_t index_of(std::uint32_t key) {
  return key & kMaxIndex;
}
}  // namespace stig

// True when `a` wins over `b` (the merge rule above). Inline: it runs for every entry a robot hears.
inline bool stigmergy_newer(const StigmergyEntry& a, const StigmergyEntry& b) {
  if (a.version != b.version) return a.version > b.version;
  if (a.writer != b.writer) return a.writer > b.writer;
  return a.value > b.value;
}

// One entry's share of Stigmergy::digest().
std::uint64_t stigmergy_entry_hash(const StigmergyEntry& e);

class Stigmergy {
 public:
  // How many of its next messages carry an entry after it changed.
  static constexpr int kResendCount = 3;

  explicit Stigmergy(RobotId self = 0) : self_(self) {}

  // Buzz's stigmergy.put.
  void put(std::uint32_t key, std::int64_t value);
  std::optional<std::int64_t> get(std::uint32_t key) const;
  const StigmergyEntry* entry(std::uint32_t key) const;

  // Takes a received entry if it is newer; returns true when the table changed.
  bool merge(const StigmergyEntry& e);
  void merge_all(std::span<const StigmergyEntry> entries);

  // The entries for the next message, at most `max_entries`: changed ones first, then round-robin.
  std::vector<StigmergyEntry> outgoing(std::size_t max_entries);

  // All entries of one namespace, by index.
  std::map<std::uint32_t, StigmergyEntry> in_namespace(std::uint32_t ns) const;
  std::map<std::uint32_t, StigmergyEntry> in_namespace(stig::Ns ns) const {
    return in_namespace(static_cast<std::uint32_t>(ns));
  }
  // Every entry, in key order.
  const std::vector<StigmergyEntry>& entries() const { return table_; }
  std::size_t size() const { return table_.size(); }
  // The table's digest (see above); 0 for an empty table.
  std::uint64_t digest() const { return digest_; }

  // Exact change detection for readers that derive something from the table (a count, a tree) and want to
  // redo it only when the table changed: two calls return the same value only when this very object's table
  // did not change in between. Unlike the digest, no collision: every change counts, and a copy of the
  // table starts a new series (its changes are not this object's).
  std::pair<std::uint64_t, std::uint64_t> revision() const { return {revision_.series, revision_.changes}; }

  // The change log, for readers that follow the table incrementally (paper_controller.cpp's label holders,
  // barrier_watch.hpp): each reader keeps a ChangeCursor and asks for the keys changed since it last asked,
  // in the order they changed (a key may repeat). Returns false when the reader must rescan the whole table
  // instead: its first call, a cursor from another table (a copy), or more changes since its last call than
  // the log keeps (it stays bounded: about twice the table's size).
  struct ChangeCursor {
    std::uint64_t series = 0;
    std::uint64_t next = 0;  // the sequence number of the first change not read
  };
  bool changes_since(ChangeCursor& cursor, std::span<const std::uint32_t>& keys) const;

  // How many entries of namespace `ns` hold a value >= 0 (e.g. labels held, allotment.hpp), kept up to date
  // on every change: O(1), not a scan of the namespace.
  std::size_t non_negative_in(stig::Ns ns) const {
    const auto i = static_cast<std::size_t>(ns);
    return i < non_negative_.size() ? non_negative_[i] : 0;
  }
  // The entries of namespace `ns` whose index is `from` or more, in key order (a contiguous run of the
  // table).
  std::span<const StigmergyEntry> in_namespace_from(stig::Ns ns, std::uint32_t from) const;

  void clear();

 private:
  void mark_changed(std::size_t position);
  void count_value(const StigmergyEntry& e, int sign);
  void log_change(std::uint32_t key);

  // revision(): `series` is drawn afresh for every new or copied table, `changes` counts its changes.
  static std::uint64_t next_series() {
    static std::atomic<std::uint64_t> series{0};
    return series.fetch_add(1, std::memory_order_relaxed) + 1;
  }
  struct Revision {
    std::uint64_t series = next_series();
    std::uint64_t changes = 0;
    Revision() = default;
    Revision(const Revision&) {}
    Revision& operator=(const Revision&) {
      series = next_series();
      changes = 0;
      return *this;
    }
  };
  // Writes `e` over the entry at `it` (same key) or inserts it there, keeping the digest; marks it changed.
  void store(std::vector<StigmergyEntry>::iterator it, const StigmergyEntry& e);

  RobotId self_;
  // Sorted by key. A flat table, not a std::map: a robot merges ~24 entries from each of up to ~73
  // neighbours every tick, almost all of them lookups that change nothing, and a binary search over a
  // contiguous array of tens of entries is several times cheaper than walking tree nodes; inserts (a key
  // seen for the first time) are rare.
  std::vector<StigmergyEntry> table_;
  // Where each key stands in table_ (position + 1; 0: absent), by namespace and index, for the keys of
  // namespaces below 16 with an index below kMaxSlotIndex (the others are searched): a lookup is two loads,
  // not a binary search over a table of thousands of entries (a 1024-label shape), and merge() is most of a
  // robot's tick while a large shape forms. Kept on every insert (the entries after it move on).
  static constexpr std::uint32_t kMaxSlotIndex = 8192;
  std::array<std::vector<std::uint32_t>, 16> slot_;
  std::vector<StigmergyEntry>::iterator find_slot(std::uint32_t key);  // entry's place or lower bound
  std::vector<StigmergyEntry>::const_iterator find_slot(std::uint32_t key) const;
  void index_from(std::size_t position);
  // Changed entries still to send: the sends left of each entry, beside table_ (0: not pending), and the
  // queue they go out in, oldest first (each pending key is in it exactly once). Not trees: while a large
  // shape's heartbeats flood, every merge that takes an entry marks it, and a std::map insert and erase per
  // entry was a fifth of a robot's tick (bench/inprocess/README.md).
  std::vector<std::uint8_t> sends_left_;
  std::deque<std::uint32_t> queue_;
  std::uint64_t digest_ = 0;
  std::uint32_t cursor_ = 0;  // round-robin: the next key to send is the first >= cursor_
  Revision revision_;
  std::vector<std::uint32_t> log_;  // changes_since(): the last changes' keys, log_[0] is change log_first_
  std::uint64_t log_first_ = 0;
  std::array<std::uint32_t, 16> non_negative_{};  // by namespace (keys of namespaces >= 16 are not counted)
};

}  // namespace swarmform::controller
