// Whether the stigmergy entries a motion-phase reading depends on changed since it was last made.
//
// In the motion phases the stigmergy changes nearly every tick somewhere in a large shape (a parent entry
// here, a dead mark there), so "the table's revision changed" made every robot redo its O(L) readings every
// tick: the members (reserve.hpp's motion_members) and the leader/parent choice (motion_phase.cpp). Those
// depend only on some namespaces and on which ids are marked dead (a parents entry equal to kDeadMark), not
// on which parent a live robot names. This watch follows the table's change log (Stigmergy::changes_since)
// and says "changed" only for those; the readings made from the table are the same as before, only made less
// often.
#pragma once

#include <initializer_list>
#include <set>

#include "common/types.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {

class MotionInputsWatch {
 public:
  // `namespaces`: any change in them counts. A parents entry counts when it becomes or stops being a dead
  // mark.
  explicit MotionInputsWatch(std::initializer_list<stig::Ns> namespaces);
  // True when something watched changed since the last call (and on the first call, after a copy of the table
  // or when more changed than the log keeps). Reads the log up to now: call it every time the reading is due.
  bool changed(const Stigmergy& stigmergy);

 private:
  std::uint32_t watched_ = 0;  // bit per namespace number
  Stigmergy::ChangeCursor cursor_;
  std::set<RobotId> dead_;  // ids whose parents entry was a dead mark when last read
};

}  // namespace swarmform::controller
