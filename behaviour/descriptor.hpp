// What a behaviour says about itself (docs/behaviour-api.md): its name, its parameter table, its states and
// their colours, the telemetry columns it records, whether it needs a shape or a goal, how it forms a shape
// (what the world checks and measures of it), how to make one controller, the optional sensors it reads and
// its experiment (its own metrics and outcome, experiment.hpp). The built-in behaviours and the
// shared-library plug-ins describe themselves with this one struct; the world validates a scenario's
// parameters through `params`, the pictures colour robots by `states`, the recorder names `telemetry`'s
// columns. A descriptor is static data: it lives as long as the program (a plug-in is never unloaded).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "behaviour/controller.hpp"
#include "behaviour/experiment.hpp"

namespace swarmform::behaviour {

// Raised with any change to Descriptor, Controller, Experiment, Mission, Perception or Command: a plug-in
// built against another version is refused with both numbers named, never run (docs/behaviour-api.md has the
// list).
inline constexpr std::uint32_t kApiVersion = 6;

struct ParamSpec {
  std::string_view name;  // as written in the scenario: `behaviour: {params: {name: value}}`
  double default_value;
  double min_value;  // inclusive bounds, checked by the world with the scenario's file:line
  double max_value;
  std::string_view doc;  // meaning and unit
};

struct StateSpec {
  std::int32_t value;       // Telemetry::state as the controller reports it
  std::string_view name;    // for legends, the report and events
  std::string_view colour;  // for pictures: "#rrggbb"
};

struct TelemetryColumn {
  std::string_view name;  // robots.csv column (after its own); lower_case, unique, none of its own names
  std::string_view doc;   // meaning and unit
};

// Where a shape-forming behaviour puts its shape's label 0, as far as the world can tell before the run: the
// world checks that the shape fits inside the walls from there (docs/scenario-format.md, "The shape must
// fit").
enum class ShapeAnchor : std::int32_t {
  Unknown = 0,        // the world cannot tell: no fit check
  NearestOrigin = 1,  // at the start position of the robot nearest the arena's origin (0, 0)
};

// What the world needs to know of how a behaviour forms its shape (with `needs_shape`) to check a scenario
// and measure a run. The world knows nothing else of shapes, labels or leaders.
struct ShapeRules {
  static constexpr std::int32_t kNoState = -1;
  ShapeAnchor anchor = ShapeAnchor::Unknown;
  // The parameter (radians) that turns the shape: label L stands at anchor + R(heading - pi/2) * offset(L),
  // offset in the matrix's own axes (columns along +x, rows down along -y). Empty: the shape stands as
  // written (heading pi/2).
  std::string_view heading_param;
  // The state a robot reports while its formation travels to the goal: the first tick a robot reports it
  // starts the motion's metrics (summary.json motion_start_tick). kNoState: the metrics start from the
  // formation alone.
  std::int32_t motion_state = kNoState;
};

// The Khepera IV's optional sensors (common/types.hpp Perception), as bits of Descriptor::sensors: the world
// computes only the ones a behaviour declares; the others are not equipped (empty).
enum Sensor : std::uint32_t {
  kProximity = 1U << 0,
  kLight = 1U << 1,
  kGround = 1U << 2,
  kLidar = 1U << 3,
  kBattery = 1U << 4,
};

// A metric the behaviour's experiment returns (summary.json behaviour_metrics.NAME).
struct MetricSpec {
  std::string_view name;  // lower_case, unique
  std::string_view doc;   // meaning and unit
};

// The kind of value a summary field holds (experiment.hpp FieldValue; null is always allowed: not reached).
enum class SummaryKind : std::int32_t {
  Tick = 0,    // std::int64_t: a tick
  Count = 1,   // std::int64_t: a count
  Number = 2,  // double
  Ids = 3,     // std::vector<std::int64_t>: robot ids
  Series = 4,  // std::vector<SeriesPoint>: (tick, number) pairs, written last
};

// A top-level summary.json key the behaviour's experiment returns (Result::summary): summary.json has every
// declared key, in this order (null when conclude did not give it), whatever the run.
struct SummarySpec {
  std::string_view key;  // lower_case, unique, none of the keys the world writes itself (ticks, outcome...)
  SummaryKind kind = SummaryKind::Number;
  std::string_view doc;  // meaning and unit
};

// The behaviour's own judge (experiment.hpp): what it returns, declared so a launcher can check a gate's keys
// and a sweep can judge success before the run. All empty (the default): no experiment, outcome "none".
struct ExperimentSpec {
  std::span<const MetricSpec> metrics;         // Result::metrics, in this order
  std::span<const SummarySpec> summary;        // Result::summary's keys, in this order
  std::span<const std::string_view> outcomes;  // every value Result::outcome may take ("none" is reserved)
  std::string_view success;                    // the one outcome that counts as success, among `outcomes`
  std::unique_ptr<experiment::Experiment> (*make)() = nullptr;  // one per run, made by the world
};

struct Descriptor {
  std::uint32_t api_version = kApiVersion;
  std::string_view name;     // the scenario's `behaviour: NAME`; a plug-in's own name (unique in a run)
  std::string_view summary;  // one line for --help and the report
  std::span<const ParamSpec> params;
  std::span<const StateSpec> states;  // empty: every robot is drawn in one colour
  // Telemetry::extra[k] is telemetry[k]; a controller fills exactly telemetry.size() values (or none).
  std::span<const TelemetryColumn> telemetry;
  bool needs_shape = false;  // the scenario must give `shape:`; the shape metrics apply
  bool needs_goal = false;   // the scenario's goal must lie inside the walls; the run has an outcome
  ShapeRules shape_rules;    // with needs_shape: how the shape is placed, turned, and when it moves
  std::unique_ptr<controller::Controller> (*make)() = nullptr;  // a fresh, not yet initialised controller
  std::uint32_t sensors = 0;  // Sensor bits: the optional sensors the controller reads
  ExperimentSpec experiment;  // its own metrics and outcome; {}: none
};

}  // namespace swarmform::behaviour
