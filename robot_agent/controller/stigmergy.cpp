#include "robot_agent/controller/stigmergy.hpp"

#include <set>
#include <tuple>

namespace swarmform::controller {

bool stigmergy_newer(const StigmergyEntry& a, const StigmergyEntry& b) {
  return std::tie(a.version, a.writer, a.value) > std::tie(b.version, b.writer, b.value);
}

void Stigmergy::put(std::uint32_t key, std::int64_t value) {
  auto it = table_.find(key);
  StigmergyEntry e;
  e.key = key;
  e.value = value;
  e.version = it == table_.end() ? 1u : it->second.version + 1u;
  e.writer = self_;
  table_[key] = e;
  mark_changed(key);
}

std::optional<std::int64_t> Stigmergy::get(std::uint32_t key) const {
  auto it = table_.find(key);
  if (it == table_.end()) return std::nullopt;
  return it->second.value;
}

const StigmergyEntry* Stigmergy::entry(std::uint32_t key) const {
  auto it = table_.find(key);
  return it == table_.end() ? nullptr : &it->second;
}

bool Stigmergy::merge(const StigmergyEntry& e) {
  auto it = table_.find(e.key);
  if (it != table_.end() && !stigmergy_newer(e, it->second)) return false;
  table_[e.key] = e;
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
  std::set<std::uint32_t> chosen;
  for (auto it = pending_.begin(); it != pending_.end() && out.size() < max_entries;) {
    out.push_back(table_.at(it->first));
    chosen.insert(it->first);
    if (--it->second <= 0) {
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  // Round-robin over the table from the cursor, wrapping once.
  if (!table_.empty() && out.size() < max_entries) {
    auto it = table_.lower_bound(cursor_);
    for (std::size_t visited = 0; visited < table_.size() && out.size() < max_entries; ++visited) {
      if (it == table_.end()) it = table_.begin();
      if (!chosen.contains(it->first)) out.push_back(it->second);
      ++it;
    }
    cursor_ = it == table_.end() ? 0u : it->first;
  }
  return out;
}

std::map<std::uint32_t, StigmergyEntry> Stigmergy::in_namespace(std::uint32_t ns) const {
  std::map<std::uint32_t, StigmergyEntry> out;
  for (auto it = table_.lower_bound(stig::key(ns, 0)); it != table_.end() && stig::ns_of(it->first) == ns;
       ++it) {
    out.emplace(stig::index_of(it->first), it->second);
  }
  return out;
}

void Stigmergy::clear() {
  table_.clear();
  pending_.clear();
  cursor_ = 0;
}

}  // namespace swarmform::controller
