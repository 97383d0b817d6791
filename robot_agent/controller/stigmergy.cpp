#include "robot_agent/controller/stigmergy.hpp"

#include <algorithm>

#include "common/splitmix64.hpp"

namespace swarmform::controller {

std::uint64_t stigmergy_entry_hash(const StigmergyEntry& e) {
  const std::uint64_t kv = splitmix64((static_cast<std::uint64_t>(e.key) << 32) | e.version);
  const std::uint64_t wv = splitmix64(kv ^ ((static_cast<std::uint64_t>(e.writer) << 32) | 0x5354u));
  return splitmix64(wv ^ static_cast<std::uint64_t>(e.value));
}

namespace {
// The entry of the key-sorted `table` with `key`, or where it would be inserted (const or not).
template <class Table>
auto first_not_below(Table& table, std::uint32_t key) {
  return std::lower_bound(table.begin(), table.end(), key,
                          [](const StigmergyEntry& e, std::uint32_t k) { return e.key < k; });
}
}  // namespace

void Stigmergy::count_value(const StigmergyEntry& e, int sign) {
  const std::uint32_t ns = stig::ns_of(e.key);
  if (e.value >= 0 && ns < non_negative_.size()) non_negative_[ns] += static_cast<std::uint32_t>(sign);
}

std::vector<StigmergyEntry>::iterator Stigmergy::find_slot(std::uint32_t key) {
  const std::uint32_t ns = stig::ns_of(key), index = stig::index_of(key);
  if (ns < slot_.size() && index < slot_[ns].size() && slot_[ns][index] != 0)
    return table_.begin() + (slot_[ns][index] - 1);
  return first_not_below(table_, key);
}

std::vector<StigmergyEntry>::const_iterator Stigmergy::find_slot(std::uint32_t key) const {
  return const_cast<Stigmergy*>(this)->find_slot(key);
}

void Stigmergy::index_from(std::size_t position) {
  for (std::size_t i = position; i < table_.size(); ++i) {
    const std::uint32_t ns = stig::ns_of(table_[i].key), index = stig::index_of(table_[i].key);
    if (ns >= slot_.size() || index >= kMaxSlotIndex) continue;
    if (index >= slot_[ns].size()) slot_[ns].resize(index + 1, 0);
    slot_[ns][index] = static_cast<std::uint32_t>(i + 1);
  }
}

void Stigmergy::store(std::vector<StigmergyEntry>::iterator it, const StigmergyEntry& e) {
  const auto position = static_cast<std::size_t>(it - table_.begin());
  if (it != table_.end() && it->key == e.key) {
    digest_ -= stigmergy_entry_hash(*it);
    count_value(*it, -1);
    *it = e;
  } else {
    table_.insert(it, e);
    sends_left_.insert(sends_left_.begin() + static_cast<std::ptrdiff_t>(position), 0);
    index_from(position);  // the entries after it moved one place on
  }
  digest_ += stigmergy_entry_hash(e);
  count_value(e, +1);
  log_change(e.key);
  mark_changed(position);
}

void Stigmergy::log_change(std::uint32_t key) {
  ++revision_.changes;
  // Keep the last table-size-and-more changes: a reader that reads every tick finds all of its own.
  const std::size_t keep = table_.size() + 64;
  if (log_.size() >= 2 * keep) {
    const std::size_t drop = log_.size() - keep;
    log_.erase(log_.begin(), log_.begin() + static_cast<std::ptrdiff_t>(drop));
    log_first_ += drop;
  }
  log_.push_back(key);
}

bool Stigmergy::changes_since(ChangeCursor& cursor, std::span<const std::uint32_t>& keys) const {
  const std::uint64_t end = log_first_ + log_.size();
  const bool whole = cursor.series == revision_.series && cursor.next >= log_first_ && cursor.next <= end;
  keys =
      whole ? std::span<const std::uint32_t>(log_).subspan(static_cast<std::size_t>(cursor.next - log_first_))
            : std::span<const std::uint32_t>();
  cursor.series = revision_.series;
  cursor.next = end;
  return whole;
}

std::span<const StigmergyEntry> Stigmergy::in_namespace_from(stig::Ns ns, std::uint32_t from) const {
  const auto begin = first_not_below(table_, stig::key(ns, from));
  const auto end = first_not_below(table_, stig::key(static_cast<std::uint32_t>(ns) + 1u, 0));
  return {begin, end};
}

void Stigmergy::put(std::uint32_t key, std::int64_t value) {
  auto it = find_slot(key);
  const bool held = it != table_.end() && it->key == key;
  store(it, StigmergyEntry{key, value, held ? it->version + 1u : 1u, self_});
}

std::optional<std::int64_t> Stigmergy::get(std::uint32_t key) const {
  const StigmergyEntry* e = entry(key);
  if (e == nullptr) return std::nullopt;
  return e->value;
}

const StigmergyEntry* Stigmergy::entry(std::uint32_t key) const {
  auto it = find_slot(key);
  return it != table_.end() && it->key == key ? &*it : nullptr;
}

bool Stigmergy::merge(const StigmergyEntry& e) {
  auto it = find_slot(e.key);
  if (it != table_.end() && it->key == e.key && !stigmergy_newer(e, *it)) return false;
  store(it, e);
  return true;
}

void Stigmergy::merge_all(std::span<const StigmergyEntry> entries) {
  for (const auto& e : entries) merge(e);
}

void Stigmergy::mark_changed(std::size_t position) {
  // Changed again while waiting: it keeps its place in the queue, with its sends counted afresh.
  if (sends_left_[position] == 0) queue_.push_back(table_[position].key);
  sends_left_[position] = static_cast<std::uint8_t>(kResendCount);
}

std::vector<StigmergyEntry> Stigmergy::outgoing(std::size_t max_entries) {
  std::vector<StigmergyEntry> out;
  out.reserve(std::min(max_entries, table_.size()));
  // Changed entries, the longest-waiting first; one sent with sends left goes to the back of the queue. So
  // when more entries changed than a message carries (hundreds of labels' heartbeats), every one of them
  // still goes out in turn: in key order, the low keys took every message and the high ones starved.
  const std::size_t waiting = queue_.size();
  for (std::size_t i = 0; i < waiting && out.size() < max_entries; ++i) {
    const std::uint32_t key = queue_.front();
    queue_.pop_front();
    const auto position = static_cast<std::size_t>(find_slot(key) - table_.begin());
    out.push_back(table_[position]);
    if (--sends_left_[position] > 0) queue_.push_back(key);
  }
  const std::size_t n_changed = out.size();
  const auto chosen = [&](std::uint32_t key) {
    for (std::size_t i = 0; i < n_changed; ++i) {
      if (out[i].key == key) return true;
    }
    return false;
  };
  // Round-robin over the table from the cursor, wrapping once.
  if (!table_.empty() && out.size() < max_entries) {
    auto it = first_not_below(table_, cursor_);
    for (std::size_t visited = 0; visited < table_.size() && out.size() < max_entries; ++visited) {
      if (it == table_.end()) it = table_.begin();
      if (!chosen(it->key)) out.push_back(*it);
      ++it;
    }
    cursor_ = it == table_.end() ? 0u : it->key;
  }
  return out;
}

std::map<std::uint32_t, StigmergyEntry> Stigmergy::in_namespace(std::uint32_t ns) const {
  std::map<std::uint32_t, StigmergyEntry> out;
  for (auto it = first_not_below(table_, stig::key(ns, 0)); it != table_.end() && stig::ns_of(it->key) == ns;
       ++it) {
    out.emplace(stig::index_of(it->key), *it);
  }
  return out;
}

void Stigmergy::clear() {
  table_.clear();
  for (auto& slots : slot_) slots.clear();
  non_negative_.fill(0);
  // Readers rescan (an empty table): the log restarts past everything they have read.
  log_first_ += log_.size() + 1;
  log_.clear();
  ++revision_.changes;
  sends_left_.clear();
  queue_.clear();
  digest_ = 0;
  cursor_ = 0;
}

}  // namespace swarmform::controller
