#include "robot_agent/controller/neighbours.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "robot_agent/controller/sorted_search.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller {

namespace {
// How many readings ahead update() prefetches a neighbour's entry: enough to hide a miss to memory behind
// the decoding of the readings in between (~50 ns each), few enough to stay within the core's fill buffers.
constexpr std::size_t kPrefetchAhead = 6;

void prefetch_for_write(const void* p, std::size_t bytes) {
  const auto* first = static_cast<const char*>(p);
  for (std::size_t offset = 0; offset < bytes; offset += 64) __builtin_prefetch(first + offset, 1, 3);
  __builtin_prefetch(first + bytes - 1, 1, 3);
}
}  // namespace

void IdTicks::set(RobotId id, Tick tick) {
  if (2 * (size_ + 1) > slots_.size()) {
    // Grow to twice the size (16 slots at first) and put every id back.
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(old.empty() ? 16 : 2 * old.size(), Slot{});
    size_ = 0;
    for (const Slot& s : old) {
      if (s.used) set(s.id, s.tick);
    }
  }
  for (std::size_t i = home(id);; i = (i + 1) & (slots_.size() - 1)) {
    Slot& s = slots_[i];
    if (!s.used) {
      s = {id, 1, tick};
      ++size_;
      return;
    }
    if (s.id == id) {
      s.tick = tick;
      return;
    }
  }
}

void NeighbourTable::update(const Perception& perception, RobotId self, std::uint64_t own_digest) {
  now_ = perception.tick;
  const auto& readings = perception.messages;
  // Where each reading's entry is. A new sender (a few a tick) gets its entry now, before the pass below,
  // and the indices of the entries after it move up by one.
  where_.clear();
  heard_entries_.clear();
  newcomers_.clear();
  for (std::size_t k = 0; k < readings.size(); ++k) {
    const RobotId sender = readings[k].sender;
    const std::uint32_t at = sender == self ? kNoEntry : index_of(sender);
    where_.push_back(at);
    if (sender != self && at == kNoEntry) newcomers_.push_back(k);
  }
  for (std::size_t k : newcomers_) {
    const RobotId sender = readings[k].sender;
    const std::uint32_t at = insert_position(sender);
    if (at < ids_.size() && ids_[at] == sender) {  // the same new sender twice in one tick
      where_[k] = at;
      continue;
    }
    for (std::uint32_t& w : where_) {
      if (w != kNoEntry && w >= at) ++w;
    }
    ids_.insert(ids_.begin() + at, sender);
    live_.insert(live_.begin() + at, {sender, Neighbour{}});
    where_[k] = at;
  }
  status_.assign(live_.size(), kKnown);
  for (std::size_t k : newcomers_) status_[where_[k]] = kNew;

  for (std::size_t k = 0; k < readings.size(); ++k) {
    // Each message is decoded straight into the neighbour's own message (its stigmergy entries into
    // heard_entries_): the vectors keep their capacity from tick to tick, so a tick of ~73 messages
    // allocates nothing once they have grown, and nothing is copied or swapped. The neighbours' entries in
    // live_ are in no order the readings follow, hence the prefetch.
    if (k + kPrefetchAhead < where_.size() && where_[k + kPrefetchAhead] != kNoEntry) {
      prefetch_for_write(&live_[where_[k + kPrefetchAhead]], sizeof(NeighbourList::value_type));
    }
    if (where_[k] == kNoEntry) continue;
    const auto& reading = readings[k];
    Neighbour& n = live_[where_[k]].second;
    // An undecodable message, or one whose inner sender is not the one the medium saw (a forgery or a bug),
    // is dropped, and so is its sender: its last good message was overwritten. It is remembered as last
    // heard at its last good tick, as if it had expired then (a newcomer, never heard well, is not).
    const std::size_t entries_begin = heard_entries_.size();
    if (!decode_message_into(reading.data, n.message, own_digest, heard_entries_) ||
        n.message.sender != reading.sender) {
      heard_entries_.resize(entries_begin);
      ++dropped_;
      if (status_[where_[k]] == kKnown) expired_.set(reading.sender, n.last_heard);
      status_[where_[k]] = kDropped;
      continue;
    }
    if (status_[where_[k]] == kDropped) status_[where_[k]] = kKnown;  // a later good copy in the same tick
    if (status_[where_[k]] == kKnown) learn_gap(reading.sender, n, reading.range);
    n.id = reading.sender;
    n.range = reading.range;
    n.bearing = reading.bearing;
    n.azimuth = wrap_angle(perception.pose.theta + reading.bearing);
    n.last_heard = now_;
    n.entries_begin = static_cast<std::uint32_t>(entries_begin);
    n.entries_count = static_cast<std::uint32_t>(heard_entries_.size() - entries_begin);
  }
  remove_dropped_and_expired();
}

NeighbourTable NeighbourTable::learning_losses(int timeout_ticks, double comm_range, double max_speed,
                                               double tick_rate) {
  NeighbourTable t(timeout_ticks);
  const double within = kWellInsideRange * comm_range;
  // Robots that cannot move cannot leave the range: every silence is a loss (bounded to stay a Tick).
  const double out_and_back_ticks = max_speed > 0.0 ? (comm_range - within) / max_speed * tick_rate
                                                    : std::numeric_limits<double>::infinity();
  t.learn_loss_gaps(within, static_cast<Tick>(std::min(out_and_back_ticks, 1e9)));
  return t;
}

void NeighbourTable::learn_gap(RobotId id, const Neighbour& before, double range_now) {
  if (learn_within_ <= 0.0 || before.last_heard + 1 >= now_) return;  // learning off, or heard last tick
  const Tick gap = now_ - before.last_heard - 1;
  if (gap > learn_max_gap_ || before.range > learn_within_ || range_now > learn_within_) return;
  if (gap > loss_gaps_.find(id).value_or(0)) loss_gaps_.set(id, gap);
}

Tick NeighbourTable::silence_limit(RobotId id) const {
  const Tick timeout = static_cast<Tick>(timeout_);
  if (loss_gaps_.size() == 0) return timeout;
  return std::max(timeout, 2 * loss_gaps_.find(id).value_or(0));
}

void NeighbourTable::remove_dropped_and_expired() {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < live_.size(); ++i) {
    auto& entry = live_[i];
    if (status_[i] == kDropped) continue;
    const Tick silence = now_ - entry.second.last_heard;
    if (silence >= static_cast<Tick>(timeout_) && silence >= silence_limit(entry.first)) {
      expired_.set(entry.first, entry.second.last_heard);
      continue;
    }
    if (kept != i) {
      live_[kept] = std::move(entry);
      ids_[kept] = ids_[i];
    }
    ++kept;
  }
  live_.resize(kept);
  ids_.resize(kept);
}

std::uint32_t NeighbourTable::insert_position(RobotId id) const {
  return static_cast<std::uint32_t>(
      controller::lower_bound_index(ids_.data(), ids_.size(), id, [](RobotId x) { return x; }));
}

std::uint32_t NeighbourTable::index_of(RobotId id) const {
  const std::uint32_t at = insert_position(id);
  return at < ids_.size() && ids_[at] == id ? at : kNoEntry;
}

const Neighbour* NeighbourTable::find(RobotId id) const {
  const std::uint32_t at = index_of(id);
  return at == kNoEntry ? nullptr : &live_[at].second;
}

bool NeighbourTable::fresh(RobotId id) const {
  const Neighbour* n = find(id);
  return n != nullptr && n->last_heard == now_;
}

std::optional<Tick> NeighbourTable::last_heard(RobotId id) const {
  if (const Neighbour* n = find(id)) return n->last_heard;
  return expired_.find(id);
}

void NeighbourTable::clear() {
  live_.clear();
  ids_.clear();
  heard_entries_.clear();
  expired_.clear();
  loss_gaps_.clear();
  now_ = 0;
  dropped_ = 0;
}

}  // namespace swarmform::controller
