// `--set KEY=VALUE` (swarm_inprocess, what `swarm sweep --loss/--burst/--noise/--set` vary): any scenario
// field set on the command line over the file's. KEY is a dotted path of map keys (packet_loss, noise.range,
// arena.width), VALUE YAML (0.2, {rate: 0.2, mean_burst: 5}, [3, 4]). The value replaces the file's node
// before the loader reads the file, so it is checked exactly like a field written in the file; an error in
// it is reported as the flag's ("command line: --set 'TEXT': KEY: why"), not at a line of the file.
#pragma once

#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace swarmform::world {

struct FieldOverride {
  std::string text;              // as given, for messages
  std::vector<std::string> key;  // the dotted path, split
  std::string value;             // YAML text
};

// Throws InputError ("command line: --set 'TEXT': why") for bad syntax (no '=', an empty key part, a value
// that is not YAML).
FieldOverride parse_field_override(const std::string& text);

// Sets each override into `root` (a scenario's top-level map), creating the maps on its path that the file
// does not have. Throws InputError naming the flag when the path runs through something that is not a map.
void apply_field_overrides(YAML::Node& root, const std::vector<FieldOverride>& overrides);

// The override an error of the loader is about: the last whose KEY the message's field path starts with
// (`what` is the message after "file:line: "), or null.
const FieldOverride* override_of_error(const std::vector<FieldOverride>& overrides, const std::string& what);

}  // namespace swarmform::world
