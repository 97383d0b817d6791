// `swarm_inprocess --param NAME=VALUE`: a behaviour parameter set on the command line over the scenario's
// `controller:` value (what `swarm sweep --param` varies). Checked by the behaviour itself (the registry's
// make: its parameter table's names and bounds), so the flag knows no behaviour's names.
#pragma once

#include <string>
#include <vector>

#include "behaviour/registry.hpp"
#include "common/mission.hpp"

namespace swarmform::harness {

// Sets each NAME=VALUE in mission.params, then has the mission's behaviour check them. Throws InputError
// ("command line: --param ...") naming the flag for bad syntax, and the parameter for an unknown name or a
// value out of its bounds.
void apply_param_flags(const std::vector<std::string>& texts, Mission& mission,
                       behaviour::Registry& behaviours);

}  // namespace swarmform::harness
