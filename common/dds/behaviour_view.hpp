// What a viewer needs to know about the behaviour the robots run: the names and colours of its states and the
// telemetry a robot's panel lists. The ONE place the world describes a behaviour to observers: the viewer
// page never hard-codes the paper's states: they come from the behaviour's own descriptor (behaviour/
// descriptor.hpp: a built-in's or a plug-in's), as the post-run pictures' do.
#pragma once

#include <string>
#include <vector>

#include "behaviour/descriptor.hpp"
#include "behaviour/known_columns.hpp"
#include "common/dds/observe_wire.hpp"

namespace swarmform::dds {

struct BehaviourView {
  std::string name;
  std::vector<StateStyleRow> states;
  std::vector<std::string> telemetry_fields;  // "state", then `columns`
  std::vector<std::string> columns;  // its telemetry columns (the descriptor's), Telemetry::extra's names
  // A mixed swarm's groups, in id order, each with its own behaviour's states and columns; the fields above
  // are then the first group's, except `telemetry_fields`: every group's, for a panel that lists what each
  // robot has.
  std::vector<ObservedGroupRow> groups;
  // Where each robot's known columns are (behaviour/known_columns.hpp), by id: the frames' label, parent,
  // leader and net force come from them. Empty: none for any robot.
  std::vector<behaviour::KnownColumns> known;
};

// The description of behaviour `name` from its descriptor `d`: its states' names and colours, the state
// field, then its columns. Without a descriptor (a recording made before descriptors), the
// state numbers are drawn grey.
BehaviourView describe_behaviour(const std::string& name, const behaviour::Descriptor* d);

}  // namespace swarmform::dds
