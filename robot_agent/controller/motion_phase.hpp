// The motion phases behind motion_hooks.hpp (paper III.C 'Ready' to III.E):
//
//   Ready    boundary role from the neighbours' azimuths -> stigmergy (boundary.hpp); leader elected from the
//            shared entries (leader_election.hpp); parent from the shared shortest-path tree
//            (parent_tree.hpp) -> parents table; after `ready_timeout` ticks the reference vectors to every
//            neighbour are recorded, eq. (2), and the robot moves on to Motion.
//   Motion   leader: F_goal (eq. 3, the live shape's centroid to the goal, at up to the speed limit) +
//            obstacles (eq. 6-7) + collision avoidance (eq. 1); others: F_net (eq. 4-5) plus the parent's
//            broadcast velocity + obstacles + collision avoidance; a small obstacle ahead -> wall-following.
//            Pinned (moved under a quarter of the way asked for over 20 ticks, an obstacle remembered near)
//            -> boundary following (wall_follow.hpp). A follower whose parent is unheard, or that the tree
//            cannot reach, takes its own place to the goal as the leader does (its piece re-joins there).
//   Arrived  leader: the shape's centroid, as its place puts it, lies inside the goal's radius by its margins
//            (leader_stop_distance); followers: their parent has arrived
//            and |F_net| is small. Formation and obstacle forces are zero (collision avoidance stays on). A
//            changed target or parent puts an arrived robot back into Motion.
//            The leader waits for the shape: its cruise is multiplied by
//            clamp(1 - (strain - 1.5 v_max) / strain_scale, 0.3, 1), where the strain is the largest lag
//            (F_net towards the goal) of the tree, passed up from child to parent in the motion section;
//            a robot held by an obstacle reports its lag only beyond about a grid spacing
//            (robot_agent/README.md, "Pace").
//   Failures a member silent for `neighbour_timeout` ticks (last heard well inside radio range) is marked
//            dead in the parents table (value kDeadMark) by whoever noticed; a live robot that finds itself
//            marked rewrites its own entry. So is a member never heard since the shape's Ready whose place
//            lies well inside radio range of ours, neighbour_timeout ticks after it: every member stood at
//            its place when the barrier passed, so a live one would have been heard (it died at its place
//            too shortly before the barrier passed for its label to be freed, and the barrier counted it).
//            Leader and tree are recomputed from the shared table every tick, so a dead parent's children
//            re-parent and a dead leader's successor is elected by the same rule, and takes the goal (every
//            robot holds the mission's goal).
#pragma once

#include <map>
#include <optional>
#include <vector>

#include "robot_agent/controller/approach_stage.hpp"
#include "robot_agent/controller/boundary_episode.hpp"
#include "robot_agent/controller/desired_motion.hpp"
#include "robot_agent/controller/leader_election.hpp"
#include "robot_agent/controller/motion_hooks.hpp"
#include "robot_agent/controller/motion_inputs_watch.hpp"
#include "robot_agent/controller/motion_params.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/obstacle_response.hpp"
#include "robot_agent/controller/obstacle_view.hpp"
#include "robot_agent/controller/parent_tree.hpp"
#include "robot_agent/controller/place_watch.hpp"
#include "robot_agent/controller/progress_window.hpp"
#include "robot_agent/controller/shape_turn.hpp"
#include "robot_agent/controller/vec2_math.hpp"
#include "robot_agent/controller/wall_follow.hpp"

namespace swarmform::controller::motion {

// Parents-table value of a robot found dead (ids are >= 0 and -1 means "no parent").
inline constexpr std::int64_t kDeadMark = -2;

class PaperMotion final : public MotionPhases {
 public:
  explicit PaperMotion(const FormationParams& params);
  void on_ready(const FormationContext& ctx) override;
  MotionStep step(const FormationContext& ctx) override;

  // For tests: what this robot believes.
  std::optional<RobotId> leader() const { return leader_; }
  std::optional<RobotId> parent() const { return parent_; }

 private:
  struct Shared;  // this tick's reading of the stigmergy
  void judge_boundary(const FormationContext& ctx);
  void watch_for_the_dead(const FormationContext& ctx);
  void mark_members_unheard_since_ready(const FormationContext& ctx);
  void choose_leader_and_parent(const FormationContext& ctx, MotionStep& out);
  void read_leader_and_parent(const FormationContext& ctx);
  void record_references(const FormationContext& ctx);
  Vec2 reference_to(const FormationContext& ctx, RobotId id) const;
  Vec2 motion_velocity(const FormationContext& ctx, MotionStep& out);
  Desire desired_motion(const FormationContext& ctx);
  void arrive(const FormationContext& ctx, Arrival arrival, MotionStep& out);
  std::optional<Vec2> go_round_small_obstacle(const FormationContext& ctx, Vec2 desired,
                                              const ObstacleSense& sense);
  Vec2 own_target(const FormationContext& ctx) const;
  double leader_stop_distance() const;
  bool parent_lost(const FormationContext& ctx) const;
  bool should_resume(const FormationContext& ctx) const;
  bool off_place(const FormationContext& ctx);

  MotionParams p_;
  ShapeTurn turn_;  // a moved goal: a place beyond a surface turns the shape (shape_turn.hpp)
  RobotState state_ = RobotState::Ready;
  bool started_ = false;  // on_ready has run
  Tick ready_tick_ = 0;   // FormationContext::ready_tick of this Ready phase
  bool boundary_written_ = false;
  std::optional<RobotId> leader_;
  std::optional<RobotId> parent_;
  Vec2 parent_reference_;               // eq. (2)'s r0 (cos a0, sin a0), arena frame
  std::map<RobotId, Vec2> references_;  // the same to every neighbour, recorded at the end of Ready
  std::map<RobotId, PointSum>
      ready_sums_;  // each member's vector as heard in every tick of Ready (eq. 2's r0)
  std::map<RobotId, Vec2> last_position_;  // each neighbour's arena position when last heard
  std::map<RobotId, Vec2> last_velocity_;  // and the velocity it said it had then
  double children_strain_ = 0.0;           // max strain the children reported (motion_section.hpp)
  std::map<RobotId, Tick> marked_dead_;    // id -> last_heard when we marked it (mark once per silence)
  bool unheard_members_checked_ = false;   // the members never heard since Ready judged, or not to be
  Vec2 to_parent_;                         // the last vector to the parent, arena frame (desired_motion.hpp)
  double net_force_ = 0.0;
  double lag_ = 0.0;    // the part of F_net towards the goal (>= 0): this robot's strain
  Vec2 live_centroid_;  // centroid of the places of the labels live members hold
  bool has_live_centroid_ = false;
  std::uint64_t seed_ = 1;
  std::optional<RobotId> arrived_parent_;  // the parent when it arrived
  bool arrived_alone_ = false;             // it arrived at its own target (no parent heard)
  PlaceWatch place_watch_;                 // an arrived follower's place, from its parent's recent readings
  // The stages of a tick in Motion, each with its own state (motion_velocity reads them in order).
  FollowerDesire follower_;         // 1. the desired motion: a follower's view of its resting parent
  LargeObstacleLatch large_latch_;  // 2. the obstacles seen: the size latch,
  EchoMemory trace_;                //    the echoes remembered longer (boundaries, the approach),
  ProgressWindow progress_;         //    and the window that judges a robot pinned
  ApproachStage approach_;          // 3. the last approach, and a cut-off robot's way
  BoundaryEpisode episode_;         // 4. a boundary episode, and the way round remembered
  WallFollower wall_;               // 5. a small obstacle gone round
  EchoMemory echoes_;               // 6. eq. (6)'s short memory of echoes,
  SlideState slide_;                //    and the slide's side
  ParentTreeCache tree_cache_;      // our label's parent in the shared tree, kept while its inputs stay
  // choose_leader_and_parent's reading of the members, the stigmergy and the tree (the elected leader, the
  // parent the tree gives, the live centroid), and the inputs it was made from: while none of them changes
  // (the common case once the shape moves) it is reused instead of going over every member again.
  struct Choice {
    bool valid = false;
    std::uint64_t members_version = 0, places_version = 0;
    double heading = 0.0;
    int label = -1;
    RobotId self = 0;
    std::optional<RobotId> leader;  // elect_leader's answer
    std::optional<RobotId> parent;  // the tree's parent for our label (before the cycle check)
    bool split = false;             // the leader's: the tree reaches not every label a live member holds
  };
  Choice choice_;
  // The stigmergy it reads: the members' boundary roles and dead marks (not the live robots' parent entries,
  // which change on their own all the time in a large shape).
  MotionInputsWatch choice_inputs_{stig::Ns::Boundary};
  // read_leader_and_parent's working space, kept so that a re-reading allocates nothing.
  std::vector<LeaderCandidate> candidates_;
  std::vector<bool> present_;
  std::vector<std::optional<RobotId>> holder_;
  // The largest distance of a live place from the live centroid (the turn's rate: shape_turn.hpp).
  double shape_radius_ = 0.0;
};

}  // namespace swarmform::controller::motion
