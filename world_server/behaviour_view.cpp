#include "world_server/behaviour_view.hpp"

#include "common/robot_state.hpp"

namespace swarmform::server {

BehaviourView describe_behaviour(const std::string& behaviour) {
  BehaviourView v;
  v.name = behaviour;
  if (behaviour == "paper") {
    // The colours of the post-run pictures (scripts/swarmform/scene.py): grey before a label, warm while
    // forming, green when ready, blue in motion, purple at the goal.
    const char* colours[] = {"#9e9e9e", "#ff9800", "#fdd835", "#8bc34a", "#2e7d32", "#1e88e5", "#8e24aa"};
    for (std::int32_t s = 0; s <= static_cast<std::int32_t>(RobotState::Arrived); ++s) {
      v.states.push_back(
          dds::StateStyleRow{s, std::string(to_string(static_cast<RobotState>(s))), colours[s]});
    }
    v.telemetry_fields = {"state", "label", "parent", "leader", "net_force"};
  } else if (behaviour == "random_walk") {
    v.states.push_back(dds::StateStyleRow{0, "walking", "#1e88e5"});
    v.telemetry_fields = {"state"};
  } else {
    v.telemetry_fields = {"state", "label", "parent", "leader", "net_force"};
  }
  return v;
}

}  // namespace swarmform::server
