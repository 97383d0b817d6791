// The built-in behaviours, registered through the same descriptor API as a plug-in
// (behaviour/descriptor.hpp): "paper" (the paper's controller) and "random_walk" (a simple wandering
// behaviour, random_walk.hpp).
#pragma once

#include <memory>

#include "behaviour/controller.hpp"
#include "behaviour/descriptor.hpp"
#include "behaviour/registry.hpp"

namespace swarmform::controller {

const behaviour::Descriptor& paper_descriptor();
const behaviour::Descriptor& random_walk_descriptor();

// Adds both to `registry`.
void add_builtins(behaviour::Registry& registry);

// A registry holding the built-ins and no plug-in folder, one per process (tests and benchmarks, which run
// only the built-ins; the programs make their own, with their plug-in folders).
behaviour::Registry& builtin_registry();

// The built-in behaviour named by mission.behaviour, initialised (builtin_registry().make): for tests and
// tools that run only the built-ins. Throws InputError for an unknown name or an invalid parameter.
std::unique_ptr<Controller> make_controller(const Mission& mission, RobotId self);

}  // namespace swarmform::controller
