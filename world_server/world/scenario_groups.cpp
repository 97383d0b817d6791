#include "world_server/world/scenario_groups.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>

#include "common/input_error.hpp"
#include "world_server/world/robot_groups.hpp"
#include "world_server/world/scenario_behaviour.hpp"

namespace swarmform::world::scenario_parts {

namespace fs = std::filesystem;
using yaml::MapReader;
using yaml::Source;

namespace {

bool lower_case_name(const std::string& n) {
  if (n.empty() || !(n[0] >= 'a' && n[0] <= 'z')) return false;
  return std::all_of(n.begin(), n.end(),
                     [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; });
}

}  // namespace

// `groups:` (docs/scenario-format.md "Groups"): instead of the top level's robots: and behaviour:. Fills
// s.groups (names, behaviours, parameters) and makes the first group's behaviour and parameters the
// scenario's own; the robots are placed later (resolve_groups).
std::vector<GroupSection> parse_groups(const Source& src, const YAML::Node& node, MapReader& top,
                                       const RobotsSection& top_robots, const ScenarioOverrides& ov,
                                       const fs::path& base, behaviour::Registry& registry, Scenario& s) {
  if (top.has("robots")) {
    yaml::fail(src, top_robots.node, "robots",
               "give groups: or a top-level robots:, not both (each group has its own robots:)");
  }
  for (const char* key : {"behaviour", "controller"}) {
    if (auto n = top.get(key)) {
      yaml::fail(src, *n, key,
                 std::string("give groups: or a top-level ") + key +
                     ":, not both (each group has its own "
                     "behaviour:, its parameters in behaviour.params)");
    }
  }
  if (ov.behaviour) {
    throw InputError("command line", 0,
                     "--behaviour: the scenario has groups:, each naming its own behaviour; change them in "
                     "the file");
  }
  if (ov.robots) {
    throw InputError("command line", 0,
                     "--robots: the scenario has groups:, each with its own robots.count; change them in the "
                     "file (or --set 'groups=...')");
  }
  if (!node.IsSequence() || node.size() == 0) {
    yaml::fail(src, node, "groups", "expected a non-empty list of {name, behaviour, robots}");
  }
  std::vector<GroupSection> sections;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    const std::string path = "groups[" + std::to_string(i) + "]";
    MapReader m(src, item, path);
    RobotGroup g;
    auto name = m.get("name");
    if (!name) yaml::fail(src, item, path, "missing 'name' (lower_case, unique)");
    g.name = yaml::to_string(src, *name, path + ".name");
    if (!lower_case_name(g.name)) {
      yaml::fail(src, *name, path + ".name",
                 "'" + g.name + "' is not lower_case (a-z first, then a-z, 0-9 or _)");
    }
    for (const RobotGroup& other : s.groups) {
      if (other.name == g.name) yaml::fail(src, *name, path + ".name", "'" + g.name + "' is given twice");
    }
    auto behaviour_node = m.get("behaviour");
    if (!behaviour_node) yaml::fail(src, item, path, "missing 'behaviour' (as the top level's behaviour:)");
    auto robots_node = m.get("robots");
    if (!robots_node) yaml::fail(src, item, path, "missing 'robots' ({count, region} or {poses})");
    m.finish({"name", "behaviour", "robots"});
    const BehaviourChoice c =
        choose_behaviour(src, behaviour_node, base, registry, path + ".behaviour", g.mission);
    g.behaviour = c.descriptor;
    set_params(src, c, false, g.mission);
    s.groups.push_back(std::move(g));
    sections.push_back({parse_robots_node(src, *robots_node, path + ".robots"), item});
  }
  // --param NAME=V is the first group's, --param GROUP.NAME=V that group's.
  for (const ParamOverride& p : ov.params) {
    const auto dot = p.name.find('.');
    RobotGroup* into = &s.groups.front();
    std::string name = p.name;
    if (dot != std::string::npos) {
      const std::string group = p.name.substr(0, dot);
      name = p.name.substr(dot + 1);
      into = nullptr;
      std::string known;
      for (RobotGroup& g : s.groups) {
        if (g.name == group) into = &g;
        known += (known.empty() ? "" : ", ") + g.name;
      }
      if (into == nullptr) {
        throw InputError("command line", 0,
                         "--param " + p.text + ": no robot group '" + group + "' (groups: " + known + ")");
      }
    }
    apply_param(p, name, *into->behaviour, into->mission);
  }
  const RobotGroup& first = s.groups.front();
  s.behaviour = first.behaviour;
  s.mission.behaviour = first.mission.behaviour;
  s.mission.plugin = first.mission.plugin;
  s.mission.descriptor = first.mission.descriptor;
  s.mission.params = first.mission.params;
  return sections;
}

// Whether any of the run's behaviours forms a shape / goes somewhere (every group's, or the one).
bool any_needs_shape(const Scenario& s) {
  for (std::size_t k = 0; k < group_count(s); ++k) {
    if (group_view(s, k).behaviour->needs_shape) return true;
  }
  return false;
}
bool any_needs_goal(const Scenario& s) {
  for (std::size_t k = 0; k < group_count(s); ++k) {
    if (group_view(s, k).behaviour->needs_goal) return true;
  }
  return false;
}

// Places every group's robots in group order (ids contiguous), each group's mission the scenario's run-wide
// fields with its own behaviour and parameters.
void resolve_groups(const Source& src, const std::vector<GroupSection>& sections, const ScenarioOverrides& ov,
                    Scenario& s) {
  for (std::size_t k = 0; k < sections.size(); ++k) {
    RobotGroup& g = s.groups[k];
    Mission own = std::move(g.mission);
    g.mission = s.mission;
    g.mission.behaviour = std::move(own.behaviour);
    g.mission.plugin = std::move(own.plugin);
    g.mission.descriptor = std::move(own.descriptor);
    g.mission.params = std::move(own.params);
    g.first_id = static_cast<RobotId>(s.robots.size());
    const std::optional<std::size_t> count =
        g.behaviour->needs_shape ? static_cast<std::size_t>(s.mission.shape.label_count()) : 0;
    resolve_robots(src, sections[k].robots, ov, s, "groups[" + std::to_string(k) + "].robots", k, count);
    g.count = s.robots.size() - g.first_id;
    if (s.robots.size() > static_cast<std::size_t>(kMaxRobots)) {
      throw InputError(src.file, yaml::line_of(sections[k].node),
                       "groups: " + std::to_string(s.robots.size()) + " robots in all, more than " +
                           std::to_string(kMaxRobots));
    }
  }
}

}  // namespace swarmform::world::scenario_parts
