// A viewer's frame (sf_observe) from what the world already holds: the truth, the controllers' last
// telemetry, this tick's perceptions and the last commands. Called between publishing a round's packets and
// collecting its commands, while the agents compute: it adds nothing to the round's critical path in
// lockstep.
#pragma once

#include <functional>

#include "behaviour/experiment.hpp"
#include "common/dds/behaviour_view.hpp"
#include "common/dds/observe_wire.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

// Each robot's last command taken, by id.
using LatestCommand = std::function<const Command&(RobotId)>;

// How the run's robots are described to a viewer: the scenario's behaviour, and with robot groups each
// group's own (its states and telemetry columns), so that a robot is drawn and listed as its own behaviour
// says.
dds::BehaviourView describe_run(const world::Scenario& scenario);

// The run's description in `frame` (behaviour, states, telemetry fields, columns, groups): set once, as it
// never changes during a run; build_frame leaves it as it is.
void describe_frame(const dds::BehaviourView& behaviour, dds::ObserveFrameData& frame);

// `frame`'s rows are reused. `formation`: the behaviour's experiment's (the frame's formation_tick and
// shape_error; none without an experiment).
void build_frame(const world::World& world, const LatestCommand& latest,
                 const experiment::Formation& formation, const dds::BehaviourView& behaviour,
                 dds::ObserveFrameData& frame);

}  // namespace swarmform::server
