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

// read_barrier's verdict for one robot, followed as the stigmergy changes (its change log) instead of read
// over every label and entry each tick: a robot in Reached asks every tick, and a 1024-label shape made that
// thousands of lookups per robot per tick. passed_with() is exactly
//   read_barrier(stigmergy, label_count, now, label_timeout).passed() && ...members.contains(self)
// (tested against it): per label, whether its holder's barrier entry names it (the valid entries) and when
// it was freed; the abandoned labels are counted at `now` over the freed ones only.
class BarrierWatch {
 public:
  bool passed_with(const Stigmergy& stigmergy, RobotId self, int label_count, Tick now, int label_timeout);

 private:
  void rescan(const Stigmergy& stigmergy, int label_count);
  void update_label(const Stigmergy& stigmergy, int label);
  void update_barrier_entry(const Stigmergy& stigmergy, RobotId id);

  Stigmergy::ChangeCursor cursor_;
  int label_count_ = -1;
  std::vector<char> valid_;  // by label: held, and its holder's barrier entry names it
  int valid_count_ = 0;
  std::vector<char> freed_;  // by label: its labels entry says freed (at freed_at_)
  std::vector<Tick> freed_at_;
  std::vector<int> freed_labels_;   // the labels with freed_ set, in no order
  std::vector<int> barrier_label_;  // by robot id: the label its barrier entry named when last read
};

}  // namespace swarmform::controller
