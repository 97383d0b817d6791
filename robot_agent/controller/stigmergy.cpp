#include "robot_agent/controller/stigmergy.hpp"

#include <algorithm>

namespace swarmform::controller {

namespace {
// splitmix64's finaliser: every input bit moves about half the output bits.
std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}
}  // namespace

std::uint64_t stigmergy_entry_hash(const StigmergyEntry& e) {
  const std::uint64_t kv = mix((static_cast<std::uint64_t>(e.key) << 32) | e.version);
  const std::uint64_t wv = mix(kv ^ ((static_cast<std::uint64_t>(e.writer) << 32) | 0x5354u));
  return mix(wv ^ static_cast<std::uint64_t>(e.value));
}

std::vector<StigmergyEntry>::iterator Stigmergy::lower_bound(std::uint32_t key) {
  return std::lower_bound(table_.begin(), table_.end(), key,
                          [](const StigmergyEntry& e, std::uint32_t k) { return e.key < k; });
}

std::vector<StigmergyEntry>::const_iterator Stigmergy::lower_bound(std::uint32_t key) const {
  return std::lower_bound(table_.begin(), table_.end(), key,
                          [](const StigmergyEntry& e, std::uint32_t k) { return e.key < k; });
}

void Stigmergy::put(std::uint32_t key, std::int64_t value) {
  auto it = lower_bound(key);
  StigmergyEntry e;
  e.key = key;
  e.value = value;
  e.writer = self_;
  if (it != table_.end() && it->key == key) {
    e.version = it->version + 1u;
    digest_ -= stigmergy_entry_hash(*it);
    *it = e;
  } else {
    e.version = 1u;
    table_.insert(it, e);
  }
  digest_ += stigmergy_entry_hash(e);
  mark_changed(key);
}

std::optional<std::int64_t> Stigmergy::get(std::uint32_t key) const {
  const StigmergyEntry* e = entry(key);
  if (e == nullptr) return std::nullopt;
  return e->value;
}

const StigmergyEntry* Stigmergy::entry(std::uint32_t key) const {
  auto it = lower_bound(key);
  return it != table_.end() && it->key == key ? &*it : nullptr;
}

bool Stigmergy::merge(const StigmergyEntry& e) {
  auto it = lower_bound(e.key);
  if (it != table_.end() && it->key == e.key) {
    if (!stigmergy_newer(e, *it)) return false;
    digest_ -= stigmergy_entry_hash(*it);
    *it = e;
  } else {
    table_.insert(it, e);
  }
  digest_ += stigmergy_entry_hash(e);
  mark_changed(e.key);
  return true;
}

void Stigmergy::merge_all(const std::vector<StigmergyEntry>& entries) {
  for (const auto& e : entries) merge(e);
}

void Stigmergy::mark_changed(std::uint32_t key) {
  pending_[key] = kResendCount;
}

std::vector<StigmergyEntry> Stigmergy::outgoing(std::size_t max_entries) {
  std::vector<StigmergyEntry> out;
  out.reserve(std::min(max_entries, table_.size()));
  for (auto it = pending_.begin(); it != pending_.end() && out.size() < max_entries;) {
    out.push_back(*entry(it->first));
    if (--it->second <= 0) {
      it = pending_.erase(it);
    } else {
      ++it;
    }
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
    auto it = lower_bound(cursor_);
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
  for (auto it = lower_bound(stig::key(ns, 0)); it != table_.end() && stig::ns_of(it->key) == ns; ++it) {
    out.emplace(stig::index_of(it->key), *it);
  }
  return out;
}

void Stigmergy::clear() {
  table_.clear();
  pending_.clear();
  digest_ = 0;
  cursor_ = 0;
}

}  // namespace swarmform::controller
