// Reads a run directory back (docs/recording-format.md): for tests, and for C++ tools that replay a run.
// A truncated or corrupt file throws InputError naming file:line and what is wrong. A last line cut off in
// the middle (a run killed while writing) is an error here too: the caller decides whether to keep what came
// before (read_robots_csv's `allow_truncated_tail`).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/types.hpp"

namespace swarmform::world {

struct RecordedRow {
  Tick tick = 0;
  RobotId id = 0;
  Pose2D pose;
  bool alive = true;
  std::int32_t state = 0;
  std::int32_t label = -1;
  std::int32_t parent = -1;
  bool leader = false;
  double net_force = 0.0;
  std::array<Rgb, kLedCount> leds{};  // all off in a recording older than its `leds` column
};

// robots.csv, with or without the `leds` column (a recording older than it: every LED off). With
// `allow_truncated_tail`, a last line without its newline is dropped instead of reported.
std::vector<RecordedRow> read_robots_csv(const std::string& path, bool allow_truncated_tail = false);
// events.jsonl, one object per line (each with at least tick, kind and id).
std::vector<nlohmann::json> read_events_jsonl(const std::string& path);
// world.json or summary.json.
nlohmann::json read_json_file(const std::string& path);

}  // namespace swarmform::world
