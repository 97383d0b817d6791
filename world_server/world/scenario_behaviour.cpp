#include "world_server/world/scenario_behaviour.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>

#include "behaviour/params.hpp"
#include "common/input_error.hpp"

namespace swarmform::world::scenario_parts {

namespace fs = std::filesystem;
using yaml::MapReader;
using yaml::Source;

namespace {

// A plug-in's (or descriptor file's) path as the scenario gives it: as is when absolute, else the first of
// the scenario's folder and the registry's folders (--plugin-dir, SWARMFORM_PLUGIN_PATH) that holds it. Not
// found: InputError naming every folder searched and how to add one. The registry then refuses a plug-in
// outside its folders. `key`: "plugin" or "descriptor".
std::string resolve_plugin(const Source& src, const YAML::Node& at, const std::string& given,
                           const fs::path& base, const std::vector<fs::path>& folders,
                           const std::string& key = "plugin", const std::string& prefix = "behaviour") {
  std::error_code ec;
  const fs::path g(given);
  const std::string path = prefix + "." + key;
  const std::string what = key == "plugin" ? "plug-in '" + given + "'" : "descriptor file '" + given + "'";
  if (g.is_absolute()) {
    if (fs::exists(g, ec)) return g.string();
    yaml::fail(src, at, path, what + ": no such file");
  }
  std::vector<fs::path> searched{fs::weakly_canonical(fs::absolute(base), ec)};
  for (const fs::path& f : folders) {
    if (std::find(searched.begin(), searched.end(), f) == searched.end()) searched.push_back(f);
  }
  std::string list;
  for (const fs::path& f : searched) {
    if (fs::exists(f / g, ec)) return (f / g).string();
    list += (list.empty() ? "" : ", ") + f.string();
  }
  yaml::fail(src, at, path,
             what + " not found in the folders searched (" + list +
                 "): the scenario's folder, each --plugin-dir DIR and " + behaviour::kPluginPathVariable +
                 "; give the folder that holds it with --plugin-dir DIR");
}

const behaviour::Descriptor& named_behaviour(const Source& src, const YAML::Node* at, const std::string& name,
                                             behaviour::Registry& registry,
                                             const std::string& prefix = "behaviour") {
  if (const behaviour::Descriptor* d = registry.find(name)) return *d;
  const std::string why = "unknown behaviour '" + name + "' (built in: " + registry.names() +
                          "; a plug-in is named by its library: behaviour: {plugin: path/libx.so})";
  if (at) yaml::fail(src, *at, prefix, why);
  throw InputError(at ? src.file : "command line", 0, (at ? "" : "--behaviour: ") + why);
}

}  // namespace

// behaviour: NAME | {name: NAME, params: {...}} | {plugin: PATH, params: {...}} |
// {descriptor: PATH, params: {...}} (docs/scenario-format.md), at `node` (absent: the default, the paper's);
// its fields named under `prefix` ("behaviour", or a group's "groups[1].behaviour").
BehaviourChoice choose_behaviour(const Source& src, const std::optional<YAML::Node>& node,
                                 const fs::path& base, behaviour::Registry& registry,
                                 const std::string& prefix, Mission& mission) {
  BehaviourChoice c;
  const behaviour::Descriptor*& d = c.descriptor;
  if (node && node->IsMap()) {
    MapReader m(src, *node, prefix);
    auto name = m.get("name");
    auto plugin = m.get("plugin");
    auto described = m.get("descriptor");
    if ((name ? 1 : 0) + (plugin ? 1 : 0) + (described ? 1 : 0) > 1) {
      yaml::fail(src, *node, prefix,
                 "give one of name (a built-in), plugin (a library) or descriptor (a JSON file), not two");
    }
    if (described) {
      const std::string given = yaml::to_string(src, *described, prefix + ".descriptor");
      const std::string path =
          resolve_plugin(src, *described, given, base, registry.folders(), "descriptor", prefix);
      try {
        d = &registry.load_descriptor(path);
      } catch (const InputError& e) {
        yaml::fail(src, *described, prefix + ".descriptor", e.what());
      }
      mission.descriptor = fs::canonical(path).string();
    } else if (plugin) {
      const std::string given = yaml::to_string(src, *plugin, prefix + ".plugin");
      const std::string path =
          resolve_plugin(src, *plugin, given, base, registry.folders(), "plugin", prefix);
      try {
        d = &registry.load_plugin(path);
      } catch (const behaviour::PluginError& e) {
        yaml::fail(src, *plugin, prefix + ".plugin", e.what());
      }
      mission.plugin = fs::canonical(path).string();
    } else if (name) {
      d = &named_behaviour(src, &*name, yaml::to_string(src, *name, prefix + ".name"), registry, prefix);
    } else {
      yaml::fail(src, *node, prefix,
                 "expected name: (a built-in), plugin: (a shared library) or descriptor: (a JSON file)");
    }
    c.params_node = m.get("params");
    c.params_path = prefix + ".params";
    m.finish({"name", "plugin", "descriptor", "params"});
  } else if (node) {
    d = &named_behaviour(src, &*node, yaml::to_string(src, *node, prefix), registry, prefix);
  } else {
    d = &named_behaviour(src, nullptr, mission.behaviour, registry);  // the default: the paper's
  }
  return c;
}

// The file's parameters of the chosen behaviour, each checked against its own table at its line.
void set_params(const Source& src, const BehaviourChoice& c, bool behaviour_overridden, Mission& mission) {
  const behaviour::Descriptor& d = *c.descriptor;
  mission.behaviour = std::string(d.name);
  if (!c.params_node || c.params_node->IsNull()) return;
  const YAML::Node& params_node = *c.params_node;
  if (!params_node.IsMap()) yaml::fail(src, params_node, c.params_path, "expected a map of name: value");
  for (const auto& kv : params_node) {
    const std::string name = kv.first.Scalar();
    const std::string path = c.params_path + "." + name;
    // A --behaviour override runs another behaviour than the file's: the file's parameters that it does not
    // have belong to the file's behaviour and are left out (those it has are checked and kept).
    if (behaviour_overridden && !behaviour::find_param(d, name)) continue;
    if (!behaviour::find_param(d, name))
      yaml::fail(src, kv.first, path, behaviour::check_param(d, name, 0.0));
    const double value = yaml::to_number(src, kv.second, path);
    const std::string why = behaviour::check_param(d, name, value);
    if (!why.empty()) yaml::fail(src, kv.second, path, why);
    mission.params[name] = value;
  }
}

// One --param over the file's value, checked against the behaviour's table.
void apply_param(const ParamOverride& p, const std::string& name, const behaviour::Descriptor& d,
                 Mission& mission) {
  try {
    behaviour::check_params(d, {{name, p.value}});
  } catch (const InputError& e) {
    std::string why = e.what();
    if (const std::string prefix = e.file() + ": "; why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
    throw InputError("command line", 0, "--param " + p.text + ": " + why);
  }
  mission.params[name] = p.value;
}

// The top level's behaviour (and the older `controller:` section for the parameters). Every parameter is
// checked against the behaviour's own table, with the line it is on.
void parse_behaviour(const Source& src, MapReader& top, const ScenarioOverrides& ov, const fs::path& base,
                     behaviour::Registry& registry, Scenario& s) {
  BehaviourChoice c = choose_behaviour(src, top.get("behaviour"), base, registry, "behaviour", s.mission);
  if (auto ctl = top.get("controller")) {
    if (c.params_node)
      yaml::fail(src, *ctl, "controller", "the parameters are already given in behaviour.params");
    c.params_node = ctl;
    c.params_path = "controller";
  }
  if (ov.behaviour) {
    c.descriptor = &named_behaviour(src, nullptr, *ov.behaviour, registry);
    s.mission.plugin.clear();
    s.mission.descriptor.clear();
  }
  s.behaviour = c.descriptor;
  set_params(src, c, ov.behaviour.has_value(), s.mission);
  // --param: over the file's values, here, so that every check after this one (the shape's fit reads
  // shape_heading) sees the values the run will have.
  for (const ParamOverride& p : ov.params) {
    if (p.name.find('.') != std::string::npos) {
      throw InputError("command line", 0,
                       "--param " + p.text +
                           ": GROUP.NAME names a robot group, and this scenario has no "
                           "groups: (give NAME=VALUE)");
    }
    apply_param(p, p.name, *s.behaviour, s.mission);
  }
}

}  // namespace swarmform::world::scenario_parts
