// The measurement of a behaviour that forms a shape and takes it to a goal, from the truth an experiment sees
// (behaviour/experiment.hpp): the assignment of the live robots to the shape's places, when the shape stands
// formed and when at the goal, its error then, the distortion in motion, the path of its centre, the robots
// stuck short of their places. The paper's experiment (robot_agent/controller/paper_experiment.cpp) is built
// on it and any shape-forming plug-in's experiment may be: it is part of the installed behaviour API. It only
// watches: nothing it computes feeds back into the run.
//
// Definitions (docs/recording-format.md; behaviour/README.md has the reasons and the cost):
// - the assignment: the best assignment of the live, heard robots (RobotTruth::alive and not silent) to the
//   shape's places over a proper rigid fit (shape_assignment.hpp); spares (more robots than places) are left
//   out, and with fewer robots than places every robot gets a place and the empty places are left out. The
//   robots' reported labels are only its starting guess. Its shape error: RMS distance of the assigned
//   robots from their fitted places, in grid units.
// - at rest: a robot has stayed within kRestRadius of one point for the last kRestTicks ticks;
// - formed (at a tick): the assignment's shape error <= kFormationError and every assigned robot at rest;
//   formation_tick: the first such tick;
// - goal_tick: the first tick formed with the assigned robots' centroid within goal.radius of the goal as it
//   stands (Truth::goal: when a world event moves it, an arrival before is undone);
// - motion ticks: motion_start_tick (first tick any live robot reports the behaviour's
//   ShapeRules::motion_state) to goal_tick inclusive; motion_ticks_minimum: at motion start, (|assigned
//   centroid - goal| - goal.radius)+ divided by max_speed / tick_rate;
// - distortion: the assignment's shape error every tick from formation_tick on;
// - path_length: the distance travelled by the assigned robots' centroid over the motion ticks; a step in
//   which the assigned set changed (a death) is not counted, so a death is not a jump;
// - outcome: arrived (goal_tick set), formed_not_arrived, not_formed; none when the mission has no shape;
// - stuck_robots (at the end, unless arrived): live robots neither at a place (the robot nearest to a place
//   of the final fit, within kAtPlace of it; the fit refitted on the better half of the assigned robots, then
//   on the robots within kInlier of a place, so robots stranded far away do not pull it) nor having left a
//   kStuckRadius disc in the last kStuckTicks ticks.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "behaviour/descriptor.hpp"
#include "behaviour/experiment.hpp"
#include "behaviour/known_columns.hpp"
#include "behaviour/shape_assignment.hpp"
#include "common/mission.hpp"

namespace swarmform::shape_metrics {

inline constexpr double kFormationError = 0.1;  // grid units
inline constexpr double kRestRadius = 0.005;    // m
inline constexpr Tick kRestTicks = 10;          // 1 s at 10 ticks/s
inline constexpr double kStuckRadius = 0.01;    // m
inline constexpr Tick kStuckTicks = 300;
inline constexpr double kAtPlace = 0.1;  // grid units
inline constexpr double kInlier = 0.3;   // grid units: robots the final fit is refitted on (conclude)
// Ticks between two Hungarian solves when the O(n) certificate fails (the cost: behaviour/README.md):
// kFullSolveEvery while the last solve found the shape near formed (error <= 2 x kFormationError), else
// kFullSolveEvery x max(1, (places / 128)^2): at 1024 places a far-from-formed solve costs ~1 s, so it runs
// every 640 ticks.
inline constexpr Tick kFullSolveEvery = 10;
Tick full_solve_interval(std::size_t places, bool near_formed);

// What the measurement found so far (summary.json's keys of the same names).
struct Measures {
  std::optional<Tick> formation_tick;              // first tick the shape stands formed
  std::optional<double> shape_error_at_formation;  // grid units
  std::optional<Tick> motion_start_tick;           // first tick a robot reports the motion state
  std::optional<double> motion_ticks_minimum;  // the assigned centroid's distance to the goal disc at motion
                                               // start, at max_speed: the fewest ticks the motion can take
  std::optional<Tick> goal_tick;  // first tick the shape stands formed with its centroid in the goal
  std::optional<double> shape_error_at_goal;        // grid units
  std::optional<double> peak_distortion;            // max shape error over the motion ticks, grid units
  std::optional<double> mean_distortion;            // mean shape error over the motion ticks, grid units
  std::vector<std::pair<Tick, double>> distortion;  // (tick, shape error) for every tick from formation on
  double path_length = 0.0;   // m, travelled by the centre of the assigned robots in motion
  std::uint32_t arrived = 0;  // live robots assigned a place at the last tick, once goal_tick is set; else 0
  std::string outcome = "not_formed";  // arrived, formed_not_arrived, not_formed; none: no shape
  std::vector<RobotId> stuck_robots;   // filled at the end (ShapeMetrics::conclude)
};

// What the assignment cost so far (for behaviour/README.md's measurements; not in the summary).
struct AssignmentStats {
  std::uint64_t evaluations = 0;  // ticks the assignment was computed
  std::uint64_t full_solves = 0;  // Hungarian solves among them
  std::uint64_t ruled_out = 0;    // ticks not computed: the robots' radial bound above the formation error
  double seconds = 0.0;           // wall time spent in the assignment
};

class ShapeMetrics {
 public:
  // The shape, grid spacing, goal and max speed are the mission's; the shape's heading and the motion state
  // the behaviour's (Descriptor::shape_rules).
  ShapeMetrics(const Mission& mission, const behaviour::Descriptor& behaviour);

  // Every tick, from tick 0 (Experiment::observe).
  void observe(const experiment::Truth& truth);
  // At the end of the run: stuck_robots (from the last observed tick).
  void conclude();

  const Measures& measures() const { return measures_; }
  const AssignmentStats& assignment_stats() const { return stats_; }
  // The last assignment: a label per robot id (-1: none, dead, silent, or never assigned).
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

  bool has_shape_;
  std::int32_t motion_state_;      // the behaviour's ShapeRules::motion_state
  behaviour::KnownColumns known_;  // where its robots report their labels
  ShapeAssigner assigner_;
  double grid_spacing_;
  Vec2 goal_;
  double goal_radius_;
  double tick_distance_;  // m: max_speed / tick_rate

  Measures measures_;
  AssignmentStats stats_;
  double distortion_sum_ = 0.0;
  std::size_t distortion_count_ = 0;
  Tick last_tick_ = 0;
  std::optional<Tick> last_full_solve_;
  bool last_full_near_formed_ = true;
  std::vector<RobotId> live_ids_;  // this tick's live, heard robots, id order
  std::vector<Vec2> live_positions_;
  std::vector<int> live_labels_;     // their reported labels (the assignment's first guess only)
  std::vector<Anchor> rest_;         // per id
  std::vector<Anchor> stuck_;        // per id
  std::vector<int> assigned_label_;  // per id
  bool have_assignment_ = false;
  RigidFit fit_;
  std::vector<RobotId> previous_assigned_ids_;  // for path_length
  std::optional<Vec2> previous_centroid_;
};

// The keys summary_fields returns, in its order, with their kinds: an experiment that returns them declares
// them in one line, `.summary = shape_metrics::kSummaryFields` (docs/recording-format.md has each meaning).
inline constexpr std::array<behaviour::SummarySpec, 13> kSummaryFields = {{
    {"formation_tick", behaviour::SummaryKind::Tick, "first tick the shape stands formed"},
    {"shape_error_at_formation", behaviour::SummaryKind::Number, "shape error at formation_tick, grid units"},
    {"motion_start_tick", behaviour::SummaryKind::Tick, "first tick a robot reports the motion state"},
    {"motion_ticks_minimum", behaviour::SummaryKind::Number, "the fewest ticks the motion can take"},
    {"goal_tick", behaviour::SummaryKind::Tick, "first tick formed with its centroid in the goal"},
    {"shape_error_at_goal", behaviour::SummaryKind::Number, "shape error at goal_tick, grid units"},
    {"peak_distortion", behaviour::SummaryKind::Number, "max shape error over the motion ticks, grid units"},
    {"mean_distortion", behaviour::SummaryKind::Number, "mean shape error over the motion ticks, grid units"},
    {"path_length", behaviour::SummaryKind::Number, "m travelled by the shape's centre in motion"},
    {"arrived", behaviour::SummaryKind::Count, "live robots with a place at the end, once goal_tick is set"},
    {"stuck_robots", behaviour::SummaryKind::Ids, "live robots neither at a place nor moving, at the end"},
    {"stuck_robot_count", behaviour::SummaryKind::Count, "the length of stuck_robots"},
    {"distortion", behaviour::SummaryKind::Series, "(tick, shape error) from formation_tick on"},
}};

// The measures as summary.json's keys, in its order (Result::summary): kSummaryFields' keys.
std::vector<experiment::SummaryField> summary_fields(const Measures& measures);

}  // namespace swarmform::shape_metrics
