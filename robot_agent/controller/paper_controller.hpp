// The paper's controller (mission.behaviour = "paper"): the state machine of Fig. 2.
//
//   Searching --(seed elected, or a free label taken)--> Moving --(at its place)--> Reached
//   Reached --(turned to the common heading, id in the barrier, barrier full)--> Ready -> Motion -> Arrived
//   Moving/Reached --(label lost to a higher id)--> Searching
//
// One tick (step): hear (neighbour table, stigmergy merge) -> keep the label (conflicts, freeing dead
// holders' labels) -> the state's behaviour (allotment.hpp, collision_avoidance.hpp, barrier.hpp, or the
// motion phases through motion_hooks.hpp) -> wheels (drive.hpp) -> broadcast (message.hpp) -> telemetry.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "behaviour/controller.hpp"
#include "robot_agent/controller/allotment.hpp"
#include "robot_agent/controller/barrier.hpp"
#include "robot_agent/controller/collision_avoidance.hpp"
#include "robot_agent/controller/motion_hooks.hpp"
#include "robot_agent/controller/motion_inputs_watch.hpp"
#include "robot_agent/controller/neighbours.hpp"
#include "robot_agent/controller/params.hpp"
#include "robot_agent/controller/shape_table.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {

class PaperController final : public Controller {
 public:
  // Ticks a Moving robot waits in front of a place held by an unexplained obstacle (a dead robot's body
  // standing on it) before it takes the spot where it stands as reached.
  static constexpr int kBlockedPlaceTicks = 30;

  // `motion`: the motion phases; null = make_motion_phases(params).
  explicit PaperController(std::unique_ptr<MotionPhases> motion = nullptr);

  void init(const Mission& mission, RobotId self) override;
  Command step(const Perception& perception) override;
  void reset() override;

  // For tests and the in-process harness.
  RobotState state() const { return state_; }
  int label() const { return label_; }
  bool has_origin() const { return has_origin_; }
  Vec2 origin() const { return origin_; }
  const Stigmergy& stigmergy() const { return stigmergy_; }
  const NeighbourTable& neighbours() const { return neighbours_; }
  const ShapeTable& table() const { return table_; }
  const FormationParams& params() const { return params_; }

 private:
  Vec2 searching_step(const Perception& p);
  Vec2 reserve_step(const Perception& p);
  Vec2 moving_step(const Perception& p);
  std::optional<WheelSpeeds> reached_step(const Perception& p);
  void keep_label();
  void free_dead_labels();
  void free_seed_label();
  void track_holders();
  void disown_stale_claims();
  // Ticks between two re-puts of our labels entry while in Moving/Reached: a third of label_timeout.
  int heartbeat_period() const { return std::max(1, params_.label_timeout / 3); }
  void take_label(int label, int parent_label, Vec2 origin, const std::string& why);
  void lose_label(const std::string& why);
  void enter_ready();
  // The motion phases' context, updated in place (ctx_): the members and places are L entries each, copied
  // only when they change, not every tick.
  const FormationContext& context(const Perception& p);
  // The shape's places about origin_ (by label), recomputed only when origin_ moves.
  const std::vector<Vec2>& places();
  // The neighbours heard this tick, as range and azimuth; refilled on each call (valid until the next).
  const std::vector<NeighbourPosition>& fresh_neighbour_positions();
  // The same plus the unexplained ultrasonic echoes nearer than `max_echo` (collision_avoidance.hpp).
  const std::vector<NeighbourPosition>& with_echoes(const Perception& p, double max_echo);
  // The reading under which an echo enters collision avoidance's band.
  double echo_range() const;
  RightOfWay right_of_way(RobotId other, RobotState other_state) const;
  void event(std::string text) { events_.push_back(std::move(text)); }
  RobotMessage compose_message(const Perception& p, const std::vector<std::uint8_t>& motion);
  // True when every live neighbour's last message carried our table's digest (compose_message).
  bool neighbours_hold_our_table() const;
  std::int32_t parent_id() const;

  Mission mission_;
  FormationParams params_;
  RobotId self_ = 0;
  ShapeTable table_;
  std::unique_ptr<MotionPhases> motion_;
  std::mt19937_64 rng_;

  RobotState state_ = RobotState::Searching;
  int label_ = -1;
  int parent_label_ = -1;  // the label whose robot offered ours
  bool has_origin_ = false;
  Vec2 origin_;
  Tick tick_ = 0;
  Tick backoff_until_ = 0;       // no new claim before this tick (after losing a conflict)
  Tick last_offer_tick_ = 0;     // last tick an offer was heard
  int blocked_ticks_ = 0;        // Moving: ticks in front of a blocked place
  bool may_reverse_ = true;      // this tick's drive may go backwards (drive.hpp)
  double best_distance_ = 1e18;  // Moving: nearest it has been to its place
  Tick progress_tick_ = 0;       // Moving: when it last came kProgress nearer
  int go_round_side_ = 0;        // collision_avoidance.hpp's side: 0 the goal's, +-1 committed when stuck
  std::optional<Vec2> detour_;   // Moving, stuck with a side committed: a random point to go to first
  Tick detour_until_ = 0;
  Tick ready_tick_ = 0;
  Tick reached_tick_ = 0;    // the tick it last entered Reached
  LabelTicks holder_since_;  // label -> tick its labels entry last changed here (claim, heartbeat)
  // label -> that entry's version, -1 before it is first seen. Indexed, not a map: track_holders() looks up
  // every label every tick, and a tree's nodes were cold misses each (BENCHMARKS.md, P3).
  std::vector<std::int64_t> holder_version_;
  Tick last_heartbeat_ = 0;     // last re-put of our own label entry
  Tick last_member_heard_ = 0;  // Searching: last tick a robot with a label was heard

  NeighbourTable neighbours_;
  Stigmergy stigmergy_;
  SeedElection election_;
  BarrierView barrier_at_ready_;
  BarrierWatch barrier_watch_;  // Reached: has the barrier passed with us in it
  // A spare that knows the shape is in its motion phases (reserve.hpp), and the last tick it heard one of
  // the shape's robots (its origin_ follows the shape from then on).
  bool reserve_ = false;
  Tick last_shape_heard_ = 0;
  double shape_radius_ = 0.0;  // m: the largest distance of a place from the shape's centroid
  // The motion phases' members (reserve.hpp's motion_members, in ctx_.members), recomputed when what they are
  // made of changes: the barrier and labels entries, and who is marked dead.
  bool members_stale_ = true;
  std::vector<std::pair<RobotId, int>> member_extras_;  // motion_member_extras when ctx_.members was made
  MotionInputsWatch members_inputs_{stig::Ns::Barrier, stig::Ns::Labels};
  FormationContext ctx_;
  // places(): the places about places_origin_ (valid when has_places_).
  std::vector<Vec2> places_;
  Vec2 places_origin_;
  bool has_places_ = false;
  std::uint64_t places_version_ = 0;        // bumped on each recompute (ctx_.places_version)
  Stigmergy::ChangeCursor holders_cursor_;  // track_holders: the stigmergy changes read so far
  // free_dead_labels: no watched label (allotment.hpp) can be freed before free_from_ (the earliest, over
  // the watched labels held by another robot, of the tick its entry last changed + label_timeout: the rule
  // counts the silence from no earlier than that). Valid while no entry of free_watched_ (the labels watched
  // from free_label_, which also decide what is watched) changed (free_stale_ is set when one did) and we
  // still hold free_label_; the rule runs only from free_from_ on.
  bool free_stale_ = true;
  int free_label_ = -1;
  Tick free_from_ = 0;
  std::vector<int> free_watched_;
  // Labels whose entry, changed this tick, names this robot although it does not hold them: an earlier run of
  // this robot's id (killed, restarted) held them (disown_stale_claims).
  std::vector<int> stale_claims_;
  std::vector<std::string> events_;
  MotionStep last_motion_;
  std::vector<NeighbourPosition> positions_;  // fresh_neighbour_positions
};

}  // namespace swarmform::controller
