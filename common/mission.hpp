// The mission every robot agent receives from the world's durable Mission topic: the shape to form, where to
// take it, and the controller's parameters. An agent needs no file of its own; this is all it is told.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "common/shape.hpp"
#include "common/types.hpp"

namespace swarmform {

struct Mission {
  // The behaviour's name (a built-in: "paper", "random_walk"; or a plug-in's own name) and, for a plug-in,
  // the canonical path of its shared library. An agent loads it only from its own plug-in folders
  // (behaviour/registry.hpp), never because the mission names it.
  std::string behaviour = "paper";
  std::string plugin;  // empty: a built-in
  // For a behaviour described by a JSON file (behaviour/descriptor_file.hpp): its canonical path. Such a
  // behaviour has no controller; an agent runs it only with --exec, and never reads the file.
  std::string descriptor;
  ShapeMatrix shape;          // the label matrix (common/shape.hpp)
  double grid_spacing = 1.0;  // m between horizontally/vertically adjacent labels (paper Table II)
  // The goal, when the run has one: the scenario's `goal:`, or for a behaviour that goes somewhere
  // (needs_goal) without one, the default (10, 0) r 0.5. A behaviour that does not go somewhere and whose
  // scenario gives no goal is told there is none: has_goal false, goal (0, 0), goal_radius 0. Every robot is
  // told the same; which robot acts on it is the behaviour's business (the paper's: only its elected leader).
  bool has_goal = true;
  Vec2 goal{10.0, 0.0};      // m, arena frame
  double goal_radius = 0.5;  // m
  double max_speed = 0.1;    // m/s, wheel speed limit (the world clamps anything above)
  double tick_rate = 10.0;   // ticks per second of simulated time
  double comm_range = 3.0;   // m, range-and-bearing range (for the controller's own reasoning only)
  std::uint32_t max_message_bytes = 1024;  // the world drops larger outgoing messages
  std::uint64_t seed = 1;  // per-run seed; a controller mixes in its id for its own randomness
  // The behaviour's parameters by name, as the scenario sets them (`behaviour: {params: ...}` or
  // `controller:`); the behaviour's own table (behaviour/descriptor.hpp) holds the names, bounds and
  // defaults.
  std::map<std::string, double> params;
};

}  // namespace swarmform
