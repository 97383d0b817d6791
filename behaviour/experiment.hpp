// The experiment: a behaviour's own judge, after ARGoS's loop functions (docs/behaviour-api.md, "The
// experiment"). The world makes one per run (never the agents), shows it the truth after every tick, and asks
// it at the end for the behaviour's own metrics and outcome, which summary.json carries. It only watches:
// what it returns never feeds back into the run, so a run's trajectory is the same with or without it. Part
// of the installed behaviour API.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "common/mission.hpp"
#include "common/types.hpp"

namespace swarmform::experiment {

// One robot as it truly is this tick.
struct RobotTruth {
  RobotId id = 0;
  Pose2D pose;                        // arena frame, true (no sensor noise)
  bool alive = true;                  // false: dead (a body in the arena)
  const Telemetry* telemetry{};       // what its controller last reported; never null
  std::array<Rgb, kLedCount> leds{};  // its LEDs as last commanded
  bool silent = false;  // alive but unheard: no message in its commands for 50 ticks (silent_robots)
};

struct ObstacleTruth {
  enum class Kind { Box, Cylinder };
  Kind kind = Kind::Box;
  Vec2 centre;          // m
  double yaw = 0.0;     // rad (boxes)
  Vec2 half_extents;    // m (boxes): half width along the box's x, half depth along its y
  double radius = 0.0;  // m (cylinders)
};

struct ArenaTruth {
  Vec2 centre;
  double width = 0.0;   // m
  double height = 0.0;  // m
  bool walls = false;
};

using Goal = swarmform::Goal;

// One tick of the world. Spans and pointers refer to the world's data and are valid during observe() only.
struct Truth {
  Tick tick = 0;                             // the tick just stepped (0: the start)
  std::span<const RobotTruth> robots;        // every robot, id order
  std::span<const RobotId> died;             // detected dead since the last observe
  std::span<const RobotId> rejoined;         // back since the last observe
  std::span<const ObstacleTruth> obstacles;  // those present this tick (world events), walls excluded
  ArenaTruth arena;
  std::optional<Goal> goal;  // as it stands this tick (world events move it); nullopt: the run has no goal
};

// A value of one of the experiment's own summary fields: null, an integer (a tick, a count), a number, a list
// of integers (robot ids) or a series of (tick, number) pairs (written on one line at the end of
// summary.json).
using SeriesPoint = std::pair<Tick, double>;
using FieldValue =
    std::variant<std::monostate, std::int64_t, double, std::vector<std::int64_t>, std::vector<SeriesPoint>>;

// A field the experiment adds to summary.json's top level, beside the world's generic ones (the paper's
// formation_tick, shape_error_at_goal, stuck_robots...). Its key must be new: not one the world writes, not
// given twice.
struct SummaryField {
  std::string key;
  FieldValue value;
};

// What the experiment concludes.
struct Result {
  std::vector<double> metrics;  // one per declared metric, in the declared order; NaN: not reached (null)
  std::string outcome;          // one of the declared outcomes
  std::vector<SummaryField> summary;  // the experiment's own summary.json keys, in this order (may be empty)
};

// What the world shows live of a behaviour that forms something: the view's formation line, and the tick the
// world starts watching the robots' communication graph (fragmentations, graph_rejoins, max_components).
struct Formation {
  std::optional<Tick> tick;     // the first tick it stood formed; nullopt: not (yet)
  std::optional<double> error;  // its error then (the paper: shape error, grid units)
};

class Experiment {
 public:
  virtual ~Experiment() = default;
  // Once, before tick 0 is observed: the mission (parameters, seed, goal...) and the number of robots.
  virtual void init(const Mission& mission, std::size_t robots) = 0;
  // Tick 0 (the starting poses), then after every step, every tick.
  virtual void observe(const Truth& truth) = 0;
  // Once, when the run ends (whatever the reason).
  virtual Result conclude() = 0;
  // Asked after every observe (ARGoS's IsExperimentFinished): true ends the run at the next tick, with
  // end_reason completed (one tick later because world_server decides before it records the tick it steps).
  virtual bool done() const { return false; }
  // Asked after every observe: the formation so far (the default: none, ever).
  virtual Formation formation() const { return {}; }
};

}  // namespace swarmform::experiment
