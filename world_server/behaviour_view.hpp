// What a viewer needs to know about the behaviour the robots run: the names and colours of its states and the
// telemetry a robot's panel lists. The ONE place the world describes a behaviour to observers: the viewer
// page never hard-codes the paper's states. (The behaviour plug-in API, issue 20, will give each behaviour
// its own descriptor; this function is then the one thing to wire to it.)
#pragma once

#include <string>
#include <vector>

#include "common/dds/observe_wire.hpp"

namespace swarmform::server {

struct BehaviourView {
  std::string name;
  std::vector<dds::StateStyleRow> states;
  std::vector<std::string> telemetry_fields;  // of "state", "label", "parent", "leader", "net_force"
};

// The description of `behaviour` (mission.behaviour). An unknown name gets its state numbers drawn grey.
BehaviourView describe_behaviour(const std::string& behaviour);

}  // namespace swarmform::server
