// `--param NAME=VALUE`, one definition for the two programs that run a scenario (world_server and the
// in-process harness; what `swarm run --param` and `swarm sweep --param` pass): a behaviour parameter set on
// the command line over the scenario's `controller:` value. The loader sets them before its own checks (the
// shape's fit reads shape_heading) and checks each against the behaviour's table; the behaviour's make then
// checks them as a whole, so the flag knows no behaviour's names.
#pragma once

#include <string>
#include <vector>

#include "behaviour/registry.hpp"
#include "common/mission.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

// NAME=VALUE texts as the loader's overrides. Throws InputError ("command line: --param ...") for bad syntax.
std::vector<ParamOverride> parse_param_flags(const std::vector<std::string>& texts);

// After loading: the mission's behaviour made once with its parameters (its own check of them together).
// Throws InputError ("command line: --param ...") naming the flags.
void check_param_flags(const std::vector<std::string>& texts, const Mission& mission,
                       behaviour::Registry& behaviours);

}  // namespace swarmform::world
