// Reached and the barrier (paper III.C 'Reached', Algorithm 1 "Task completion consensus"): a robot at its
// place turns to the common heading, then puts its id into the virtual stigmergy (namespace Barrier, key =
// its id, value = its label). When the stigmergy holds the threshold of entries, it goes to 'ready'.
//
// What counts: a barrier entry (id, label) whose label the labels namespace still gives to that id -- a
// robot that died after entering and whose label was taken over no longer counts; its successor does.
// The threshold: n, minus the labels abandoned (freed after their holder died and taken by nobody within
// label_timeout; allotment.hpp). So with no spare the shape completes without the dead robot's label, and
// the barrier counts the live robots.
#pragma once

#include <map>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {

void barrier_enter(Stigmergy& stigmergy, RobotId self, int label);
bool barrier_contains(const Stigmergy& stigmergy, RobotId self);
// Withdraws `id`'s entry (value -1, counted by nobody): a robot that lost its label, or a dead holder whose
// label was freed (reserve.hpp: a stale entry would stand for a live member of that label).
void barrier_withdraw(Stigmergy& stigmergy, RobotId id);

struct BarrierView {
  int count = 0;                   // valid entries
  int threshold = 0;               // labels expected
  std::map<RobotId, int> members;  // valid entries: id -> label
  std::vector<int> abandoned;      // labels the barrier no longer waits for
  bool passed() const { return threshold > 0 && count >= threshold; }
};

BarrierView read_barrier(const Stigmergy& stigmergy, int label_count, Tick now, int label_timeout);

}  // namespace swarmform::controller
