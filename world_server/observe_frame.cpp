#include "world_server/observe_frame.hpp"

#include <algorithm>

#include "common/sensor_readings.hpp"
#include "world_server/world/robot_groups.hpp"

namespace swarmform::server {

dds::BehaviourView describe_run(const world::Scenario& scenario) {
  dds::BehaviourView run = dds::describe_behaviour(scenario.mission.behaviour, scenario.behaviour);
  run.known = world::known_columns_by_robot(scenario);
  for (const world::RobotGroup& g : scenario.groups) {
    dds::BehaviourView own = dds::describe_behaviour(g.mission.behaviour, g.behaviour);
    for (const std::string& c : own.columns) {
      if (std::find(run.telemetry_fields.begin(), run.telemetry_fields.end(), c) ==
          run.telemetry_fields.end())
        run.telemetry_fields.push_back(c);
    }
    run.groups.push_back(dds::ObservedGroupRow{static_cast<std::uint32_t>(g.first_id),
                                               static_cast<std::uint32_t>(g.count), std::move(own.name),
                                               std::move(own.states), std::move(own.columns)});
  }
  return run;
}

void describe_frame(const dds::BehaviourView& behaviour, dds::ObserveFrameData& frame) {
  frame.behaviour = behaviour.name;
  frame.states = behaviour.states;
  frame.telemetry_fields = behaviour.telemetry_fields;
  frame.columns = behaviour.columns;
  frame.groups = behaviour.groups;
}

void build_frame(const world::World& world, const LatestCommand& latest,
                 const experiment::Formation& formation, const dds::BehaviourView& behaviour,
                 dds::ObserveFrameData& frame) {
  const auto& truth = world.robots();
  frame.tick = world.tick();
  frame.finished = false;
  frame.formation_tick = formation.tick ? static_cast<std::int64_t>(*formation.tick) : -1;
  frame.shape_error = formation.error.value_or(-1.0);
  frame.robots.resize(truth.size());
  frame.alive = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const world::RobotTruth& t = truth[i];
    dds::ObservedRobotRow& r = frame.robots[i];
    r.id = t.id;
    r.pose = t.pose;
    r.alive = t.alive;
    r.state = t.telemetry.state;
    const behaviour::KnownColumns known =
        i < behaviour.known.size() ? behaviour.known[i] : behaviour::KnownColumns{};
    r.label = known.label_of(t.telemetry);
    r.parent = known.parent_of(t.telemetry);
    r.leader = known.leader_of(t.telemetry);
    r.net_force = known.net_force_of(t.telemetry);
    r.leds = t.leds;
    r.extra = t.telemetry.extra;
    r.heard.clear();
    r.ultrasonic.fill(0.0);
    r.equipped = 0;
    r.readings.clear();
    if (t.alive) {
      // A live robot's perception of this tick was made when its packet went out: nothing is computed here.
      const Perception& p = world.perception(t.id);
      r.ultrasonic = p.ultrasonic;
      pack_sensor_readings(p, r.equipped, r.readings);
      for (const RabReading& m : p.messages) r.heard.push_back(m.sender);
    }
    frame.alive += t.alive ? 1 : 0;
    const Command& last = latest(static_cast<RobotId>(i));
    r.left_speed = last.left_speed;
    r.right_speed = last.right_speed;
    r.message_bytes = static_cast<std::uint32_t>(last.message.size());
  }
}

}  // namespace swarmform::server
