// Label allotment (paper III.C, states 'searching' and 'moving'), as pure functions over what a robot knows:
// its own pose, its neighbour table and its stigmergy. PaperController strings them together.
//
// - Seed: the robot closest to the arena origin, found by local interaction only: every searching robot
//   broadcasts the best (distance, id) it knows -- its own or a neighbour's, whichever is smaller -- so the
//   minimum floods the connected swarm one hop a tick. A robot whose candidate is itself and has stayed
//   unchanged for `seed_settle` ticks, with no shape heard of, takes label 0 where it stands: that place is
//   the shape's origin. Reports age one hop a relay and die past `seed_settle` hops (SeedElection), so a dead
//   candidate's minimum does not circulate for ever. A seed dead before anyone joined is freed by searchers
//   that hear no member (PaperController) and re-elected by distance to label 0's known place.
// - Offers: a robot in the shape broadcasts the free labels of its 3x3 grid (Table II's row of its label):
//   those the labels stigmergy does not give to a holder and no neighbour reports as its own. It also
//   broadcasts the shape's origin, from which every label's place follows (shape_table.hpp).
// - Taking a label: a searching robot pools the offers it hears and pairs offered places with the searching
//   robots it hears (and itself) greedily, closest pair first; it takes the label paired with itself and
//   puts itself as that label's holder in the stigmergy. (The paper takes "the last non-negative label" of
//   its list; pairing by distance makes simultaneous claims rarer and trips shorter. Claims can still
//   collide, since views differ: the conflict rule settles them.)
// - Conflicts (paper: "the bot with a higher ID gets the label while the other bots go back to searching"):
//   keeps_label(). Through the stigmergy an equal-version tie also goes to the higher writer id, so the
//   table agrees with the rule; a holder that sees a lower id in its label's entry re-puts itself.
// - A dead holder: a holder in Moving or Reached re-puts its labels entry every label_timeout / 3 ticks (a
//   heartbeat that floods multi-hop, so a holder out of radio range is still known alive). A robot of the
//   shape whose own label is in the 3x3 grid of label L frees L when L's holder has neither been heard nor
//   refreshed its entry for `label_timeout` ticks: it puts kLabelFreedBase - tick. L is then offered again.
//   A holder that is alive and sees its label freed re-puts itself. A freed label nobody takes within
//   another `label_timeout` ticks is abandoned: the barrier no longer waits for it (barrier.hpp). A label
//   that never had a holder (its robot died first, or never spoke) is freed by labels_left_untaken(). A
//   freed label passes its watch on: its grid is watched by whoever watches it (watched_labels()).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/shape_table.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {

// Labels namespace values: a holder id (>= 0), or kLabelFreedBase - tick for a label freed at that tick.
inline constexpr std::int64_t kLabelFreedBase = -2;

struct LabelStatus {
  enum class Kind { Unclaimed, Held, Freed };
  Kind kind = Kind::Unclaimed;
  RobotId holder = 0;  // Held
  Tick freed_at = 0;   // Freed
};
LabelStatus label_status(const Stigmergy& stigmergy, int label);
void put_label_holder(Stigmergy& stigmergy, int label, RobotId holder);
void put_label_freed(Stigmergy& stigmergy, int label, Tick now);

// The paper's conflict rule: of two robots with the same label, the higher id keeps it.
constexpr bool keeps_label(RobotId self, RobotId other) {
  return self > other;
}

// label -> a tick (PaperController: the tick it last saw the label's entry change), or none. Indexed by
// label, not a tree: the label-freeing rule looks up its grid's labels every tick in every robot of the
// shape, and with a 1024-label shape each std::map lookup was ten cold nodes (bench/inprocess/README.md).
class LabelTicks {
 public:
  LabelTicks() = default;
  LabelTicks(std::initializer_list<std::pair<int, Tick>> ticks) {
    for (const auto& [label, tick] : ticks) set(label, tick);
  }
  std::optional<Tick> find(int label) const {
    if (label < 0 || static_cast<std::size_t>(label) >= ticks_.size()) return std::nullopt;
    const Tick t = ticks_[static_cast<std::size_t>(label)];
    return t == kNone ? std::nullopt : std::optional<Tick>(t);
  }
  void set(int label, Tick tick);
  void clear() { ticks_.clear(); }

 private:
  static constexpr Tick kNone = std::numeric_limits<Tick>::max();
  std::vector<Tick> ticks_;
};

// The seed election with ageing. A report carries its age: 0 from the candidate itself, one more at each
// relay (the smallest age heard for that candidate, + 1). A report older than `max_age` hops is dropped.
// While the candidate lives, a robot k hops away holds age k; once it dies (or stops searching) nobody
// reports age 0 any more, the smallest age in its neighbourhood grows by one a tick, and after at most
// `max_age` ticks the minimum is gone everywhere: the next best candidate takes over (RIP's bounded hop
// count, applied to the flooded minimum). `max_age` must exceed the swarm's diameter in hops; PaperController
// uses seed_settle, the bound the settle period already assumes.
class SeedElection {
 public:
  // Folds in this tick's own distance to the origin and the candidates the neighbours report.
  void update(RobotId self, double own_distance, const NeighbourTable& neighbours, Tick now, int max_age);
  RobotId candidate() const { return candidate_; }
  double distance() const { return distance_; }
  std::uint8_t age() const { return age_; }
  // The candidate has not changed for `settle_ticks`.
  bool settled(Tick now, int settle_ticks) const;
  void reset() { *this = SeedElection{}; }

 private:
  bool started_ = false;
  RobotId candidate_ = 0;
  double distance_ = 0.0;
  std::uint8_t age_ = 0;
  Tick since_ = 0;
};

// Labels of `label`'s 3x3 grid that nobody holds, as the robot knows it.
std::vector<int> free_grid_labels(const ShapeTable& table, int label, const Stigmergy& stigmergy,
                                  const NeighbourTable& neighbours);

struct LabelOffer {
  int label = -1;
  RobotId advertiser = 0;
  int advertiser_label = -1;  // becomes the taker's parent label
  Vec2 origin;                // the advertiser's shape origin
  Vec2 place;                 // the label's place, arena frame
};

// The offers heard from the neighbours (robots with a label and an origin), minus labels the robot knows are
// held. One offer per label (from the lowest advertiser id).
std::vector<LabelOffer> collect_offers(const ShapeTable& table, double shape_heading,
                                       const NeighbourTable& neighbours, const Stigmergy& stigmergy);

struct Searcher {
  RobotId id = 0;
  Vec2 position;
};

// Greedy closest-pair matching of offered places and searching robots; the offer paired with `self`.
std::optional<LabelOffer> choose_offer(const std::vector<LabelOffer>& offers,
                                       const std::vector<Searcher>& searchers, RobotId self);

// The labels a robot answers for, for the two rules below: those of its own label's 3x3 grid and, through
// every one of them that is freed (its holder died, or nobody took it), that label's grid in turn, and so on.
// A freed label has nobody to watch its grid: a label whose only grid neighbours are freed or empty (the end
// of a V's arm, a ring's segment beside a dead robot) was held for ever by a dead robot, or left unclaimed,
// and the barrier waited for it for ever. Own grid first, in Table II's order, then outwards.
std::vector<int> watched_labels(const ShapeTable& table, int own_label, const Stigmergy& stigmergy);

// The rule that frees a dead holder's label: the watched labels (above; beyond the own grid only those whose
// holder is not in the barrier) whose holder has been
// silent for `label_timeout` ticks, counted from the later of the last time it was heard directly and
// `entry_changed[label]`, the tick this robot last saw that label's entry change (a claim or a heartbeat).
std::vector<int> labels_to_free(const ShapeTable& table, int own_label, const Stigmergy& stigmergy,
                                const NeighbourTable& neighbours, const LabelTicks& entry_changed,
                                RobotId self, Tick now, int label_timeout);
// The first tick at which labels_to_free could free anything while these entries stand (the silence is
// counted from no earlier than an entry's last change): the earliest entry change + label_timeout over the
// watched labels held by another robot; the largest Tick if there is none. Before it the rule can be skipped.
Tick earliest_label_free(const ShapeTable& table, int own_label, const Stigmergy& stigmergy,
                         const LabelTicks& entry_changed, RobotId self, int label_timeout);

// The rule that gives up on a label nobody takes (no robot left to take it: one died before taking a label,
// or never spoke): the watched labels (above) that are still unclaimed (nobody in the labels
// stigmergy, no neighbour reporting it) once this robot has stood at its place since `reached_at` for
// `label_timeout` ticks. They are marked freed (still offered; abandoned by the barrier label_timeout later).
std::vector<int> labels_left_untaken(const ShapeTable& table, int own_label, const Stigmergy& stigmergy,
                                     const NeighbourTable& neighbours, Tick reached_at, Tick now,
                                     int label_timeout);

}  // namespace swarmform::controller
