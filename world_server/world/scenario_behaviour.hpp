// The scenario's choice of behaviour and its parameters (docs/scenario-format.md, "Behaviours"): a part of
// the loader (scenario.cpp puts the parts together), not an API of its own.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "world_server/world/placement.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/yaml_fields.hpp"

namespace swarmform::world::scenario_parts {

// A behaviour as chosen in the file: its descriptor and, in `mission`, its name, plug-in or descriptor file
// and parameters.
struct BehaviourChoice {
  const behaviour::Descriptor* descriptor = nullptr;
  std::optional<YAML::Node> params_node;
  std::string params_path;
};

// behaviour: NAME | {name: NAME, params: {...}} | {plugin: PATH, params: {...}} |
// {descriptor: PATH, params: {...}} at `node` (absent: the default, the paper's); its fields named under
// `prefix` ("behaviour", or a group's "groups[1].behaviour").
BehaviourChoice choose_behaviour(const yaml::Source& src, const std::optional<YAML::Node>& node,
                                 const std::filesystem::path& base, behaviour::Registry& registry,
                                 const std::string& prefix, Mission& mission);
// The file's parameters of the chosen behaviour, each checked against its own table at its line.
void set_params(const yaml::Source& src, const BehaviourChoice& c, bool behaviour_overridden,
                Mission& mission);
// One --param over the file's value, checked against the behaviour's table.
void apply_param(const ParamOverride& p, const std::string& name, const behaviour::Descriptor& d,
                 Mission& mission);
// The top level's behaviour (and the older `controller:` section for the parameters).
void parse_behaviour(const yaml::Source& src, yaml::MapReader& top, const ScenarioOverrides& ov,
                     const std::filesystem::path& base, behaviour::Registry& registry, Scenario& s);

}  // namespace swarmform::world::scenario_parts
