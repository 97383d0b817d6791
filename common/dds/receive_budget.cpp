#include "common/dds/receive_budget.hpp"

#include <algorithm>

namespace swarmform::dds {

ReceiveBudget::ReceiveBudget(std::uint32_t per_window, std::uint32_t accept_ids)
    : per_window_(per_window), accept_ids_(accept_ids), instances_(accept_ids, 0) {}

bool ReceiveBudget::known(InstanceHandle instance) const {
  return std::find(instances_.begin(), instances_.end(), instance) != instances_.end();
}

void ReceiveBudget::prune(std::int64_t now_ns) {
  if (now_ns - pruned_at_ < kSecond) return;
  pruned_at_ = now_ns;
  std::erase_if(writers_, [&](const auto& kv) {
    return now_ns - kv.second.seen_at > kForgetAfter && kv.second.unreported == 0;
  });
}

bool ReceiveBudget::admit(PublicationHandle writer, InstanceHandle instance, std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  prune(now_ns);
  Writer& w = writers_[writer];
  w.seen_at = now_ns;
  if (w.banned && instance != 0 && !known(instance)) {
    ++out_of_range_;
    return false;
  }
  if (per_window_ == 0) return true;
  const std::int64_t second = now_ns / kSecond;
  if (w.window != window_ || w.second != second) {
    w.window = window_;
    w.second = second;
    w.count = 0;
  }
  if (++w.count <= per_window_) return true;
  ++over_budget_;
  if (w.unreported++ == 0) unreported_.push_back(writer);
  return false;
}

void ReceiveBudget::set_window(std::uint64_t window) {
  std::lock_guard lock(mutex_);
  window_ = window;
}

bool ReceiveBudget::taken(PublicationHandle writer, InstanceHandle instance, RobotId id) {
  std::lock_guard lock(mutex_);
  if (accept_ids_ == 0) return true;  // no id check asked
  if (id < accept_ids_) {
    if (instance != 0) instances_[id] = instance;  // an instance is freed and made anew: learned again
    return true;
  }
  ++out_of_range_;
  writers_[writer].banned = true;
  return false;
}

void ReceiveBudget::take_drops(std::vector<Drops>& out) {
  std::lock_guard lock(mutex_);
  for (const PublicationHandle writer : unreported_) {
    auto it = writers_.find(writer);
    if (it == writers_.end()) continue;
    out.push_back(Drops{writer, it->second.unreported});
    it->second.unreported = 0;
  }
  unreported_.clear();
}

std::uint64_t ReceiveBudget::out_of_range() const {
  std::lock_guard lock(mutex_);
  return out_of_range_;
}

std::uint64_t ReceiveBudget::over_budget() const {
  std::lock_guard lock(mutex_);
  return over_budget_;
}

std::size_t ReceiveBudget::writers_tracked() const {
  std::lock_guard lock(mutex_);
  return writers_.size();
}

}  // namespace swarmform::dds
