// make_controller: the behaviour named by the mission. Parameters are checked here, once, so a bad mission
// fails at init with a message instead of misbehaving later.
#include <string>

#include "common/input_error.hpp"
#include "robot_agent/controller/controller.hpp"
#include "robot_agent/controller/paper_controller.hpp"
#include "robot_agent/controller/params.hpp"
#include "robot_agent/controller/random_walk.hpp"

namespace swarmform::controller {

std::unique_ptr<Controller> make_controller(const Mission& mission, RobotId self) {
  (void)params_from_mission(mission);  // throws InputError on an unknown or out-of-bounds parameter
  std::unique_ptr<Controller> c;
  if (mission.behaviour == "paper") {
    if (mission.shape.label_count() == 0) throw InputError("<mission>", 0, "behaviour 'paper' needs a shape");
    c = std::make_unique<PaperController>();
  } else if (mission.behaviour == "random_walk") {
    c = std::make_unique<RandomWalk>();
  } else {
    throw InputError("<mission>", 0,
                     "unknown behaviour '" + mission.behaviour + "' (expected 'paper' or 'random_walk')");
  }
  c->init(mission, self);
  return c;
}

}  // namespace swarmform::controller
