// The run's metrics, computed from the truth (docs/recording-format.md). Updated once per tick by RunSession.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/shape.hpp"
#include "common/types.hpp"

namespace swarmform::world {

struct DeathRecord {
  RobotId id = 0;
  Tick tick = 0;
};

struct Metrics {
  // Formation and arrival are judged on the true poses (metrics_tracker.hpp has the definitions): the best
  // assignment of the live robots to the shape's places over a rigid fit, at rest, within kFormationError.
  std::optional<Tick> formation_tick;              // first tick the shape stands formed
  std::optional<double> shape_error_at_formation;  // grid units
  std::optional<Tick> motion_start_tick;           // first tick a robot reports Motion (telemetry)
  std::optional<double> motion_ticks_minimum;  // the assigned centroid's distance to the goal disc at motion
                                               // start, at max_speed: the fewest ticks the motion can take
  std::optional<Tick> goal_tick;  // first tick the shape stands formed with its centroid in the goal
  std::optional<double> shape_error_at_goal;        // grid units
  std::optional<double> peak_distortion;            // max shape error over the motion ticks, grid units
  std::optional<double> mean_distortion;            // mean shape error over the motion ticks, grid units
  std::vector<std::pair<Tick, double>> distortion;  // (tick, shape error) for every tick from formation on
  std::uint32_t collisions_robot_robot = 0;         // contact onsets
  std::uint32_t collisions_robot_obstacle = 0;      // contact onsets (walls, obstacles, dead bodies)
  double path_length = 0.0;   // m, travelled by the centre of the assigned robots in motion
  std::uint32_t arrived = 0;  // live robots assigned a place at the last tick, once goal_tick is set; else 0
  // How the mission ended: "arrived", "formed_not_arrived", "not_formed", or "none" (no shape or goal to
  // reach: behaviour random_walk).
  std::string outcome = "not_formed";
  std::vector<RobotId> stuck_robots;   // filled at the end (MetricsTracker::conclude)
  std::vector<RobotId> silent_robots;  // live at the end but silent (kSilentTicks): left out of the shape
  std::vector<DeathRecord> deaths;
  std::vector<DeathRecord> rejoins;
  std::uint32_t leader_changes = 0;  // times the robot reporting leader=true changed (first one not counted)
  // The communication graph of the live shape robots (edges: true distance <= comm_range), from formation on.
  std::uint32_t fragmentations = 0;  // times it went from one component to several
  std::uint32_t graph_rejoins = 0;   // times it went from several components back to one
  std::uint32_t max_components = 0;  // the most components seen at once (1 = never split)
};

// A robot's position with the label it holds.
struct LabelledPosition {
  int label = -1;
  Vec2 position;  // m, arena frame
};

// The shape error (docs/recording-format.md): RMS distance of each robot from its label's place after the
// best rigid fit (rotation and translation, no scaling) of the label grid onto the robots, in grid units
// (divided by the grid spacing). Labels held by no live robot are left out; returns nullopt for fewer than 2
// robots.
std::optional<double> shape_error(const ShapeMatrix& shape, double grid_spacing,
                                  const std::vector<LabelledPosition>& robots);

}  // namespace swarmform::world
