#include "robot_agent/controller/barrier.hpp"

#include <algorithm>

#include "robot_agent/controller/allotment.hpp"

namespace swarmform::controller {

void barrier_enter(Stigmergy& stigmergy, RobotId self, int label) {
  stigmergy.put(stig::key(stig::Ns::Barrier, self), label);
}

bool barrier_contains(const Stigmergy& stigmergy, RobotId self) {
  return stigmergy.entry(stig::key(stig::Ns::Barrier, self)) != nullptr;
}

void barrier_withdraw(Stigmergy& stigmergy, RobotId id) {
  const auto key = stig::key(stig::Ns::Barrier, id);
  if (const auto entry = stigmergy.get(key); entry && *entry != -1) stigmergy.put(key, -1);
}

BarrierView read_barrier(const Stigmergy& stigmergy, int label_count, Tick now, int label_timeout) {
  BarrierView view;
  for (int label = 0; label < label_count; ++label) {
    const auto s = label_status(stigmergy, label);
    if (s.kind == LabelStatus::Kind::Freed && now >= s.freed_at + static_cast<Tick>(label_timeout)) {
      view.abandoned.push_back(label);
    }
  }
  view.threshold = label_count - static_cast<int>(view.abandoned.size());
  for (const auto& [id, e] : stigmergy.in_namespace(stig::Ns::Barrier)) {
    const int label = static_cast<int>(e.value);
    if (label < 0 || label >= label_count) continue;
    const auto s = label_status(stigmergy, label);
    if (s.kind != LabelStatus::Kind::Held || s.holder != id) continue;
    view.members[id] = label;
  }
  view.count = static_cast<int>(view.members.size());
  return view;
}

namespace {
constexpr int kNoLabel = -1;
}  // namespace

// Label `label` (< label_count_) again: valid (read_barrier's members: held by h whose barrier entry names
// it) and freed.
void BarrierWatch::update_label(const Stigmergy& stigmergy, int label) {
  const auto l = static_cast<std::size_t>(label);
  const auto s = label_status(stigmergy, label);
  bool valid = false;
  if (s.kind == LabelStatus::Kind::Held) {
    const StigmergyEntry* e = stigmergy.entry(stig::key(stig::Ns::Barrier, s.holder));
    // The holder's id as read_barrier finds it: the index of a barrier key (16 bits).
    valid = e != nullptr && stig::index_of(e->key) == s.holder && static_cast<int>(e->value) == label;
  }
  if (valid != static_cast<bool>(valid_[l])) {
    valid_[l] = valid ? 1 : 0;
    valid_count_ += valid ? 1 : -1;
  }
  const bool freed = s.kind == LabelStatus::Kind::Freed;
  if (freed) freed_at_[l] = s.freed_at;
  if (freed != static_cast<bool>(freed_[l])) {
    freed_[l] = freed ? 1 : 0;
    if (freed) {
      freed_labels_.push_back(label);
    } else {
      freed_labels_.erase(std::find(freed_labels_.begin(), freed_labels_.end(), label));
    }
  }
}

// Robot `id`'s barrier entry changed: the label it named before and the one it names now.
void BarrierWatch::update_barrier_entry(const Stigmergy& stigmergy, RobotId id) {
  if (id >= barrier_label_.size()) barrier_label_.resize(static_cast<std::size_t>(id) + 1, kNoLabel);
  const int before = barrier_label_[id];
  const auto now = stigmergy.get(stig::key(stig::Ns::Barrier, id));
  const int label = now ? static_cast<int>(*now) : kNoLabel;
  barrier_label_[id] = label;
  if (before >= 0 && before < label_count_) update_label(stigmergy, before);
  if (label >= 0 && label < label_count_ && label != before) update_label(stigmergy, label);
}

void BarrierWatch::rescan(const Stigmergy& stigmergy, int label_count) {
  label_count_ = label_count;
  const auto n = static_cast<std::size_t>(std::max(label_count, 0));
  valid_.assign(n, 0);
  valid_count_ = 0;
  freed_.assign(n, 0);
  freed_at_.assign(n, 0);
  freed_labels_.clear();
  barrier_label_.clear();
  for (const auto& e : stigmergy.in_namespace_from(stig::Ns::Barrier, 0)) {
    const RobotId id = stig::index_of(e.key);
    if (id >= barrier_label_.size()) barrier_label_.resize(static_cast<std::size_t>(id) + 1, kNoLabel);
    barrier_label_[id] = static_cast<int>(e.value);
  }
  for (int l = 0; l < label_count; ++l) update_label(stigmergy, l);
}

bool BarrierWatch::passed_with(const Stigmergy& stigmergy, RobotId self, int label_count, Tick now,
                               int label_timeout) {
  std::span<const std::uint32_t> changed;
  if (!stigmergy.changes_since(cursor_, changed) || label_count != label_count_) {
    rescan(stigmergy, label_count);
  } else {
    const auto labels = static_cast<std::uint32_t>(stig::Ns::Labels);
    const auto barrier = static_cast<std::uint32_t>(stig::Ns::Barrier);
    for (const std::uint32_t key : changed) {
      const std::uint32_t index = stig::index_of(key);
      if (stig::ns_of(key) == labels && index < static_cast<std::uint32_t>(label_count_)) {
        update_label(stigmergy, static_cast<int>(index));
      } else if (stig::ns_of(key) == barrier) {
        update_barrier_entry(stigmergy, index);
      }
    }
  }
  int abandoned = 0;
  for (const int l : freed_labels_) {
    if (now >= freed_at_[static_cast<std::size_t>(l)] + static_cast<Tick>(label_timeout)) ++abandoned;
  }
  const int threshold = label_count - abandoned;
  if (!(threshold > 0 && valid_count_ >= threshold)) return false;
  // Counted: its barrier entry names a label in range that the labels entry gives to it.
  const auto own = stigmergy.get(stig::key(stig::Ns::Barrier, self));
  if (!own) return false;
  const int label = static_cast<int>(*own);
  if (label < 0 || label >= label_count) return false;
  const auto s = label_status(stigmergy, label);
  return s.kind == LabelStatus::Kind::Held && s.holder == self;
}

}  // namespace swarmform::controller
