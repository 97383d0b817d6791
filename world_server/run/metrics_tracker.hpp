// Keeps the run's Metrics (metrics.hpp) up to date, one recorded tick at a time, from the truth: the robots'
// true poses and alive flags, the world's contact onsets, and (telemetry only) what the controllers report.
// Events that count into the metrics (deaths, rejoins, leader changes, graph splits) come in through
// count_event, so the events file and the summary can never disagree.
//
// Definitions (docs/recording-format.md; world_server/run/README.md has the reasons):
// - the assignment: the best assignment of the live robots to the shape's places over a proper rigid fit
//   (assignment.hpp); spares (more robots than places) are left out, and with fewer robots than places every
//   robot gets a place and the empty places are left out. The robots' reported labels are only its starting
//   guess. Its shape error: RMS distance of the assigned robots from their fitted places, in grid units.
// - at rest: a robot has stayed within kRestRadius of one point for the last kRestTicks ticks;
// - formed (at a tick): the assignment's shape error <= kFormationError and every assigned robot at rest;
//   formation_tick: the first such tick;
// - goal_tick: the first tick formed with the assigned robots' centroid within goal.radius of the goal;
// - motion ticks: motion_start_tick (first tick any live robot reports Motion: telemetry) to goal_tick
//   inclusive; motion_ticks_minimum: at motion start, (|assigned centroid - goal| - goal.radius)+ divided by
//   max_speed / tick_rate;
// - distortion: the assignment's shape error every tick from formation_tick on;
// - path_length: the distance travelled by the assigned robots' centroid over the motion ticks; a step in
//   which the assigned set changed (a death) is not counted, so a death is not a jump;
// - outcome: none (behaviour other than paper), arrived (goal_tick set), formed_not_arrived, not_formed;
// - stuck_robots (at the end, unless arrived; only for a behaviour that goes somewhere, needs_goal: a robot
//   that stopped is stuck only if it had somewhere to go): live robots neither at a place (the robot nearest
//   to a place of the final fit, within kAtPlace of it; the fit refitted on the better half of the assigned
//   robots, then on the robots within kInlier of a place, so robots stranded far away do not pull it) nor
//   having left a kStuckRadius disc in the last kStuckTicks ticks.
#pragma once

#include <chrono>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "behaviour/descriptor.hpp"
#include "common/mission.hpp"
#include "world_server/run/assignment.hpp"
#include "world_server/run/metrics.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

inline constexpr double kFormationError = 0.1;  // grid units
inline constexpr double kRestRadius = 0.005;    // m
inline constexpr Tick kRestTicks = 10;          // 1 s at 10 ticks/s
inline constexpr double kStuckRadius = 0.01;    // m
inline constexpr Tick kStuckTicks = 300;
inline constexpr double kAtPlace = 0.1;  // grid units
// A live robot whose commands carried no message for this many ticks (or that never broadcast, from this
// tick on) is silent: nobody hears it, so it is left out of the assignment like a dead robot.
inline constexpr Tick kSilentTicks = 50;
inline constexpr double kInlier = 0.3;  // grid units: robots the final fit is refitted on (conclude)
// Ticks between two Hungarian solves when the O(n) certificate fails (the cost: README): kFullSolveEvery
// while the last solve found the shape near formed (error <= 2 x kFormationError), else kFullSolveEvery x
// max(1, (places / 128)^2): at 1024 places a far-from-formed solve costs ~1 s, so it runs every 640 ticks.
inline constexpr Tick kFullSolveEvery = 10;
Tick full_solve_interval(std::size_t places, bool near_formed);

// What the assignment cost so far (for the README's measurements; not in the summary).
struct AssignmentStats {
  std::uint64_t evaluations = 0;  // ticks the assignment was computed
  std::uint64_t full_solves = 0;  // Hungarian solves among them
  std::uint64_t ruled_out = 0;    // ticks not computed: the robots' radial bound above the formation error
  double seconds = 0.0;           // wall time spent in the assignment
};

class MetricsTracker {
 public:
  // The paper's metrics (formation, motion, outcome) apply to a behaviour that needs both a shape and a goal;
  // for any other the outcome is "none" and only the collisions and distances are measured.
  MetricsTracker(const Mission& mission, const behaviour::Descriptor* behaviour);

  void observe(Tick tick, const std::vector<RobotTruth>& robots, ContactCounts contacts);
  // The goal as it stands this tick, before observe: where a world event moved it (goal_events.hpp), an
  // arrival at the goal where it stood is undone (goal_tick is the first arrival at its last place).
  void goal_stands(const Goal& goal);
  // An event as written to events.jsonl ({"tick","kind","id",...}); deaths, rejoins, leader, fragment and
  // rejoin_graph are counted, anything else is ignored.
  void count_event(const nlohmann::ordered_json& event);
  // Components of the shape robots' communication graph this tick (tracked from formation on).
  void note_components(std::size_t components);
  // At the end of the run: stuck_robots (from the last observed tick).
  void conclude();

  const Metrics& metrics() const { return metrics_; }
  const AssignmentStats& assignment_stats() const { return stats_; }
  // The last assignment: a label per robot id (-1: none, dead, or never assigned).
  const std::vector<int>& assigned_labels() const { return assigned_label_; }

 private:
  bool in_motion_window(Tick tick) const;
  struct Anchor {
    Vec2 at;
    Tick since = 0;
    bool set = false;
  };
  static void move_anchor(Anchor& a, Vec2 p, Tick tick, double radius);
  // The assignment of the live robots this tick (stored in assigned_label_ and fit_).
  ShapeAssignment assign(Tick tick, bool force_full);

  bool has_mission_;
  bool goes_somewhere_;        // the behaviour's needs_goal: only then can a robot be stuck
  std::int32_t motion_state_;  // the behaviour's ShapeRules::motion_state
  ShapeAssigner assigner_;
  double grid_spacing_;
  Vec2 goal_;
  double goal_radius_;
  double tick_distance_;  // m: max_speed / tick_rate

  Metrics metrics_;
  AssignmentStats stats_;
  double distortion_sum_ = 0.0;
  std::size_t distortion_count_ = 0;
  Tick last_tick_ = 0;
  std::optional<Tick> last_full_solve_;
  bool last_full_near_formed_ = true;
  std::vector<RobotId> live_ids_;    // this tick's live robots, id order
  std::vector<RobotId> silent_ids_;  // this tick's live but silent robots (kSilentTicks), id order
  std::vector<Vec2> live_positions_;
  std::vector<int> live_labels_;     // their reported labels (the assignment's first guess only)
  std::vector<Anchor> rest_;         // per id
  std::vector<Anchor> stuck_;        // per id
  std::vector<int> assigned_label_;  // per id
  bool have_assignment_ = false;
  RigidFit fit_;
  std::vector<RobotId> previous_assigned_ids_;  // for path_length
  std::optional<Vec2> previous_centroid_;
  bool leader_seen_ = false;
};

}  // namespace swarmform::world
