// robots.csv's behaviour columns for a run (docs/recording-format.md "Robot groups"): the behaviour's
// telemetry columns; with robot groups, the union of the groups' columns in group order (a name two groups
// share is one column), each robot's values under its own behaviour's names and the others left empty.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "world_server/world/robot_groups.hpp"

namespace swarmform::world {

struct TelemetryColumns {
  std::vector<std::string> names;
  // With groups: for robot id, of_robot[id][c] is the index into its telemetry.extra of column c, -1 when its
  // behaviour has no such column. Empty without groups: column c is extra[c] for every robot.
  std::vector<std::vector<int>> of_robot;
};

inline TelemetryColumns telemetry_columns(const Scenario& s) {
  TelemetryColumns out;
  for (std::size_t k = 0; k < group_count(s); ++k) {
    const behaviour::Descriptor* d = group_view(s, k).behaviour;
    if (d == nullptr) continue;
    for (const auto& c : d->telemetry) {
      if (std::find(out.names.begin(), out.names.end(), c.name) == out.names.end())
        out.names.emplace_back(c.name);
    }
  }
  if (s.groups.empty()) return out;
  std::vector<std::vector<int>> of_group;
  for (const RobotGroup& g : s.groups) {
    std::vector<int> map(out.names.size(), -1);
    for (std::size_t k = 0; k < g.behaviour->telemetry.size(); ++k) {
      const auto at = std::find(out.names.begin(), out.names.end(), g.behaviour->telemetry[k].name);
      map[static_cast<std::size_t>(at - out.names.begin())] = static_cast<int>(k);
    }
    of_group.push_back(std::move(map));
  }
  for (RobotId id = 0; id < s.robots.size(); ++id) out.of_robot.push_back(of_group[group_of(s, id)]);
  return out;
}

}  // namespace swarmform::world
