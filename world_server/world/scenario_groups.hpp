// `groups:`, a mixed swarm's robot groups (docs/scenario-format.md "Groups"): a part of the loader
// (scenario.cpp puts the parts together), not an API of its own.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "world_server/world/placement.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/scenario_sections.hpp"
#include "world_server/world/yaml_fields.hpp"

namespace swarmform::world::scenario_parts {

// One item of `groups:` as read: its name, behaviour and robots (placed once the shape and goal are known).
struct GroupSection {
  RobotsSection robots;
  YAML::Node node;
};

// `groups:` instead of the top level's robots: and behaviour:. Fills s.groups (names, behaviours, parameters)
// and makes the first group's behaviour and parameters the scenario's own; the robots are placed later
// (resolve_groups).
std::vector<GroupSection> parse_groups(const yaml::Source& src, const YAML::Node& node, yaml::MapReader& top,
                                       const RobotsSection& top_robots, const ScenarioOverrides& ov,
                                       const std::filesystem::path& base, behaviour::Registry& registry,
                                       Scenario& s);
// Whether any of the run's behaviours forms a shape / goes somewhere (every group's, or the one).
bool any_needs_shape(const Scenario& s);
bool any_needs_goal(const Scenario& s);
// Places every group's robots in group order (ids contiguous), each group's mission the scenario's run-wide
// fields with its own behaviour and parameters.
void resolve_groups(const yaml::Source& src, const std::vector<GroupSection>& sections,
                    const ScenarioOverrides& ov, Scenario& s);

}  // namespace swarmform::world::scenario_parts
