#include "world_server/world/field_overrides.hpp"

#include <yaml-cpp/yaml.h>

#include "common/input_error.hpp"

namespace swarmform::world {
namespace {

[[noreturn]] void refuse(const std::string& text, const std::string& why) {
  throw InputError("command line", 0, "--set '" + text + "': " + why);
}

std::string dotted(const std::vector<std::string>& key, std::size_t parts) {
  std::string out;
  for (std::size_t i = 0; i < parts; ++i) out += (i ? "." : "") + key[i];
  return out;
}

}  // namespace

FieldOverride parse_field_override(const std::string& text) {
  const std::string usage =
      "expected KEY=VALUE, KEY a scenario field (a dotted path for a nested one: noise.range) and VALUE "
      "YAML (e.g. packet_loss=0.2, packet_loss={rate: 0.2, mean_burst: 5}, noise.range=0.05)";
  const auto eq = text.find('=');
  if (eq == std::string::npos) refuse(text, usage);
  FieldOverride f;
  f.text = text;
  f.value = text.substr(eq + 1);
  const std::string key = text.substr(0, eq);
  std::size_t from = 0;
  while (true) {
    const auto dot = key.find('.', from);
    const std::string part = key.substr(from, dot == std::string::npos ? std::string::npos : dot - from);
    if (part.empty() || part.find_first_of(" \t{}[],:") != std::string::npos) {
      refuse(text, "'" + key + "' is not a field name (" + usage + ")");
    }
    f.key.push_back(part);
    if (dot == std::string::npos) break;
    from = dot + 1;
  }
  if (f.value.find_first_not_of(" \t") == std::string::npos)
    refuse(text, "the value is empty (" + usage + ")");
  try {
    (void)YAML::Load(f.value);
  } catch (const YAML::Exception& e) {
    refuse(text, "the value is not YAML: " + e.msg);
  }
  return f;
}

void apply_field_overrides(YAML::Node& root, const std::vector<FieldOverride>& overrides) {
  for (const FieldOverride& f : overrides) {
    if (!root.IsMap() && !root.IsNull()) refuse(f.text, "the scenario is not a map of fields");
    // Handles share their node, so writing through `at` writes into the tree; reset() moves a handle
    // (operator= would instead overwrite the node it holds).
    YAML::Node at;
    at.reset(root);
    for (std::size_t i = 0; i + 1 < f.key.size(); ++i) {
      YAML::Node next = at[f.key[i]];
      if (next.IsDefined() && !next.IsNull() && !next.IsMap()) {
        refuse(f.text, "the scenario's " + dotted(f.key, i + 1) + " is not a map, so it has no field " +
                           f.key[i + 1] + " (set " + dotted(f.key, i + 1) + " as a whole)");
      }
      if (!next.IsDefined() || next.IsNull()) {
        at[f.key[i]] = YAML::Node(YAML::NodeType::Map);
        next.reset(at[f.key[i]]);
      }
      at.reset(next);
    }
    at[f.key.back()] = YAML::Load(f.value);
  }
}

const FieldOverride* override_of_error(const std::vector<FieldOverride>& overrides, const std::string& what) {
  for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {
    const std::string key = dotted(it->key, it->key.size());
    if (what.compare(0, key.size(), key) != 0) continue;
    const char next = what.size() > key.size() ? what[key.size()] : ':';
    if (next == ':' || next == '.' || next == '[') return &*it;
  }
  return nullptr;
}

}  // namespace swarmform::world
