// A behaviour described by a JSON file rather than built as a plug-in: the data of a Descriptor (name,
// parameters, states, telemetry columns, needs_goal, sensors) for a behaviour whose controller is a program
// run by robot_agent --exec (docs/agent-protocol.md, "The descriptor file"). It has no controller (make is
// nullptr) and no experiment. The world checks a scenario's parameters against it, records its states and
// telemetry and colours pictures by its states, exactly as for a plug-in.
#pragma once

#include <deque>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "behaviour/descriptor.hpp"

namespace swarmform::behaviour {

// The file's contents, owned: descriptor's spans and string_views point into this object, which is never
// moved or copied (the registry keeps it for the life of the process).
class DescribedBehaviour {
 public:
  DescribedBehaviour() = default;
  DescribedBehaviour(const DescribedBehaviour&) = delete;
  DescribedBehaviour& operator=(const DescribedBehaviour&) = delete;

  const Descriptor& descriptor() const { return descriptor_; }
  // The file as it was named (for messages).
  const std::string& file() const { return file_; }

 private:
  friend std::unique_ptr<const DescribedBehaviour> load_descriptor_file(const std::filesystem::path& path);
  std::string file_;
  std::deque<std::string> text_;  // every string the descriptor's views name; a deque never moves them
  std::vector<ParamSpec> params_;
  std::vector<StateSpec> states_;
  std::vector<TelemetryColumn> telemetry_;
  Descriptor descriptor_;
};

// The behaviour the JSON file at `path` describes, checked: every field's type, no unknown key, api_version
// equal to kApiVersion, lower_case unique names, min <= default <= max (finite), unique state values and
// names, colours "#rrggbb", known sensors, and the registry's own checks of a descriptor
// (descriptor_check.hpp). Throws InputError(path, 0, "KEY.PATH: what"), e.g. "agent.json: params[1].max:
// below min".
std::unique_ptr<const DescribedBehaviour> load_descriptor_file(const std::filesystem::path& path);

}  // namespace swarmform::behaviour
