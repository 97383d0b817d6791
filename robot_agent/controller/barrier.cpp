#include "robot_agent/controller/barrier.hpp"

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

}  // namespace swarmform::controller
