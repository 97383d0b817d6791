// Which robot runs what: a scenario's robot groups (docs/scenario-format.md "Groups") seen the same way
// whether the file gives `groups:` or not. Without groups there is one implicit group of every robot, running
// the scenario's behaviour and mission, so a caller needs no second path for the ordinary run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "behaviour/known_columns.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

// One group as a caller uses it: name empty for the implicit group of a scenario without groups.
struct GroupView {
  std::string_view name;
  RobotId first_id = 0;
  std::size_t count = 0;
  const Mission* mission = nullptr;
  const behaviour::Descriptor* behaviour = nullptr;
};

inline std::size_t group_count(const Scenario& s) {
  return s.groups.empty() ? 1 : s.groups.size();
}

inline GroupView group_view(const Scenario& s, std::size_t k) {
  if (s.groups.empty()) return {{}, 0, s.robots.size(), &s.mission, s.behaviour};
  const RobotGroup& g = s.groups[k];
  return {g.name, g.first_id, g.count, &g.mission, g.behaviour};
}

// The index of the group robot `id` belongs to (ids are contiguous in group order).
inline std::size_t group_of(const Scenario& s, RobotId id) {
  for (std::size_t k = 1; k < s.groups.size(); ++k) {
    if (id < s.groups[k].first_id) return k - 1;
  }
  return s.groups.empty() ? 0 : s.groups.size() - 1;
}

inline const Mission& mission_of(const Scenario& s, RobotId id) {
  return s.groups.empty() ? s.mission : s.groups[group_of(s, id)].mission;
}

inline const behaviour::Descriptor* behaviour_of(const Scenario& s, RobotId id) {
  return s.groups.empty() ? s.behaviour : s.groups[group_of(s, id)].behaviour;
}

// Where each robot's known telemetry columns are (behaviour/known_columns.hpp), by id: its own behaviour's.
inline std::vector<behaviour::KnownColumns> known_columns_by_robot(const Scenario& s) {
  std::vector<behaviour::KnownColumns> out;
  out.reserve(s.robots.size());
  for (RobotId id = 0; id < s.robots.size(); ++id)
    out.push_back(behaviour::KnownColumns::of(behaviour_of(s, id)));
  return out;
}

// The optional sensors any robot of the run reads: the world equips every robot alike.
inline std::uint32_t sensors_of_run(const Scenario& s) {
  std::uint32_t bits = 0;
  for (std::size_t k = 0; k < group_count(s); ++k) {
    const behaviour::Descriptor* d = group_view(s, k).behaviour;
    if (d != nullptr) bits |= d->sensors;
  }
  return bits;
}

}  // namespace swarmform::world
