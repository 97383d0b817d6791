// Spares once the shape has passed its barrier: the reserve. The paper has no spares in motion; here a spare
// that learns the shape is moving (a robot heard in Ready, Motion or Arrived, or a leader entry in the
// stigmergy) follows it, and takes the place of a member that dies on the way. Without it, spares left
// where the shape formed aged its labels out, elected a seed among themselves and formed a second shape that
// marched to the same goal, while the first one arrived with a hole (spares.yaml, unseen seeds 61-70: 4 of
// 10 runs ended not_formed).
//
// - A vacancy: a label L whose barrier entries (barrier.hpp: id -> label) are all marked dead by the motion
//   phases (motion_phase.hpp's parents table), and whose labels entry names one of them, or a claimant
//   whose entry has not changed for label_timeout ticks (a claimant heartbeats it while Moving or Reached,
//   so a silent one died on its way). A label that no barrier entry names was abandoned when the barrier
//   passed (its robot died before taking it, or came back too late: paper_controller's disown rule) and is
//   vacant too.
// - A reserve takes the vacancy whose place is nearest, unless a searching robot heard is nearer to it, as
//   a Moving robot (allotment.hpp's labels entry; the conflict rule settles two claims). Its place moves with
//   the shape: label 0's place is estimated every tick from the shape's robots heard (moving_origin). At its
//   place it enters the barrier; the barrier counts it instead of the dead member (the labels entry names
//   it), so it passes for it at once and it enters Ready, then the motion phases.
// - The other members count it from then on (motion_members): a barrier entry (id, L) whose id the labels
//   namespace names as L's holder while every member of L at Ready is marked dead. A member marked dead by
//   mistake that rewrites its entry takes its label back (the reserve's claim no longer counts).
// - A reserve with no vacancy trails the shape: it keeps a grid spacing and a half beyond the shape's
//   radius, on the side away from the goal while the shape travels (on its own side once the shape is
//   there), and makes for the goal when it hears none of the shape's robots (standing off, it stayed out of
//   radio range of a shape that had arrived, and never learnt of a death there).
#pragma once

#include <map>
#include <optional>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/allotment.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/shape_table.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {

// True when the motion phases have marked `id` dead (motion_phase.hpp: kDeadMark in the parents table).
bool marked_dead_in_motion(const Stigmergy& stigmergy, RobotId id);

// True when the shape is in its motion phases as far as the stigmergy tells (a leader entry exists).
bool shape_in_motion(const Stigmergy& stigmergy);

// The motion phases' members: `at_ready` (the barrier as it passed, dead members included) plus each reserve
// that took a dead member's place (see above).
std::map<RobotId, int> motion_members(const Stigmergy& stigmergy, const std::map<RobotId, int>& at_ready);
// What motion_members adds to `at_ready`, in id order: usually nothing. Cheap to recompute whenever the
// stigmergy changes (no copy of `at_ready`, which holds every label of a 1024-label shape).
std::vector<std::pair<RobotId, int>> motion_member_extras(const Stigmergy& stigmergy,
                                                          const std::map<RobotId, int>& at_ready);
// The members from `at_ready` and the extras motion_member_extras found.
std::map<RobotId, int> motion_members(const std::map<RobotId, int>& at_ready,
                                      const std::vector<std::pair<RobotId, int>>& extras);

// The labels a reserve may take now (see above). `holder_since`: label -> tick its labels entry last changed.
std::vector<int> vacant_labels(const Stigmergy& stigmergy, int label_count, const LabelTicks& holder_since,
                               Tick now, int label_timeout);

// The robot, other than `self`, whose barrier entry gives it `label` and that is not marked dead (the lowest
// id): the member was marked dead by mistake and has rewritten its entry, or another reserve reached the
// place first. A reserve that took `label` gives it back to that robot then. (A robot that loses its label
// withdraws its barrier entry, value -1, so a former claimant's entry never counts here.)
std::optional<RobotId> live_member_of(const Stigmergy& stigmergy, int label, RobotId self);

// Label 0's place now, from the shape's robots heard this tick (Ready, Motion or Arrived, with a label):
// the mean over them of their position (own pose + range and bearing) minus their label's offset. nullopt
// when none is heard.
std::optional<Vec2> moving_origin(const NeighbourTable& neighbours, const Pose2D& self,
                                  const ShapeTable& table, double shape_heading);

// Where a reserve with no vacancy goes: `centre` is the shape's centroid now (or the goal, when no robot of
// the shape is heard), `radius` the largest distance of a place from the centroid.
Vec2 trailing_point(Vec2 centre, double radius, Vec2 goal, Vec2 self, double spacing);

}  // namespace swarmform::controller
