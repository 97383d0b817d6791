// The behaviour API in one include, for plug-ins (docs/behaviour-api.md):
//   #include <swarmform/behaviour.hpp>
// the controller interface, the descriptor, the experiment, the per-robot random generator, differential
// drive, the parameter helpers, the plug-in macro and the plain types a controller sees (Perception, Command,
// Mission).
#pragma once

#include "behaviour/controller.hpp"
#include "behaviour/descriptor.hpp"
#include "behaviour/drive.hpp"
#include "behaviour/experiment.hpp"
#include "behaviour/params.hpp"
#include "behaviour/plugin.hpp"
#include "behaviour/random.hpp"
#include "common/input_error.hpp"
#include "common/mission.hpp"
#include "common/types.hpp"
