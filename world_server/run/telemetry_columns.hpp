// robots.csv's behaviour columns for a run (docs/recording-format.md "Robot groups"): the behaviour's
// telemetry columns; with robot groups, the union of the groups' columns in group order (a name two groups
// share is one column), each robot's values under its own behaviour's names and the others left empty. The
// known columns (label, parent, leader, net_force) are robots.csv's own.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "world_server/world/robot_groups.hpp"

namespace swarmform::world {

struct TelemetryColumns {
  // The behaviours' own columns but the known ones (behaviour/known_columns.hpp), which robots.csv records in
  // its own columns of their names.
  std::vector<std::string> names;
  // For robot id, of_robot[id][c] is the index into its telemetry.extra of column c, -1 when its behaviour
  // has no such column.
  std::vector<std::vector<int>> of_robot;
  std::vector<behaviour::KnownColumns> known;  // by robot id
};

inline TelemetryColumns telemetry_columns(const Scenario& s) {
  TelemetryColumns out;
  for (std::size_t k = 0; k < group_count(s); ++k) {
    const behaviour::Descriptor* d = group_view(s, k).behaviour;
    if (d == nullptr) continue;
    for (const auto& c : d->telemetry) {
      if (!behaviour::is_known_column(c.name) &&
          std::find(out.names.begin(), out.names.end(), c.name) == out.names.end())
        out.names.emplace_back(c.name);
    }
  }
  std::vector<std::vector<int>> of_group;
  for (std::size_t g = 0; g < group_count(s); ++g) {
    std::vector<int> map(out.names.size(), -1);
    if (const behaviour::Descriptor* d = group_view(s, g).behaviour) {
      for (std::size_t k = 0; k < d->telemetry.size(); ++k) {
        const auto at = std::find(out.names.begin(), out.names.end(), d->telemetry[k].name);
        if (at != out.names.end())
          map[static_cast<std::size_t>(at - out.names.begin())] = static_cast<int>(k);
      }
    }
    of_group.push_back(std::move(map));
  }
  for (RobotId id = 0; id < s.robots.size(); ++id) out.of_robot.push_back(of_group[group_of(s, id)]);
  out.known = known_columns_by_robot(s);
  return out;
}

}  // namespace swarmform::world
