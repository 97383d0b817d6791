#include "robot_agent/controller/motion_inputs_watch.hpp"

#include <span>

#include "robot_agent/controller/motion_phase.hpp"

namespace swarmform::controller {

MotionInputsWatch::MotionInputsWatch(std::initializer_list<stig::Ns> namespaces) {
  for (const stig::Ns ns : namespaces) watched_ |= 1u << static_cast<std::uint32_t>(ns);
}

bool MotionInputsWatch::changed(const Stigmergy& stigmergy) {
  const auto parents = static_cast<std::uint32_t>(stig::Ns::Parents);
  std::span<const std::uint32_t> keys;
  if (!stigmergy.changes_since(cursor_, keys)) {
    dead_.clear();
    for (const auto& [index, e] : stigmergy.in_namespace(stig::Ns::Parents)) {
      if (e.value == motion::kDeadMark) dead_.insert(static_cast<RobotId>(index));
    }
    return true;
  }
  bool any = false;
  for (const std::uint32_t key : keys) {
    const std::uint32_t ns = stig::ns_of(key);
    if (ns < 32 && (watched_ >> ns & 1u)) any = true;
    if (ns != parents) continue;
    const auto id = static_cast<RobotId>(stig::index_of(key));
    const bool dead = stigmergy.get(key) == motion::kDeadMark;
    if (dead == (dead_.count(id) != 0)) continue;
    if (dead) {
      dead_.insert(id);
    } else {
      dead_.erase(id);
    }
    any = true;
  }
  return any;
}

}  // namespace swarmform::controller
