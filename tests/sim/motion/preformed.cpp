#include "tests/sim/motion/preformed.hpp"

#include "robot_agent/controller/drive.hpp"
#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"
#include "robot_agent/controller/params.hpp"

namespace swarmform::sim_motion {

world::Scenario preformed_scenario(world::Scenario scenario, Vec2 origin) {
  const auto params = controller::params_from_mission(scenario.mission);
  const controller::ShapeTable table(scenario.mission.shape, scenario.mission.grid_spacing);
  scenario.robots.clear();
  for (const Vec2& place : table.places(origin, params.shape_heading)) {
    scenario.robots.push_back({place.x, place.y, params.shape_heading});
  }
  return scenario;
}

void PreformedController::init(const Mission& mission, RobotId self) {
  mission_ = mission;
  self_ = self;
  params_ = controller::params_from_mission(mission);
  table_ = controller::ShapeTable(mission.shape, mission.grid_spacing);
  motion_ = std::make_unique<controller::motion::PaperMotion>(params_);
  neighbours_ = controller::NeighbourTable::learning_losses(params_.neighbour_timeout, params_.comm_range,
                                                            params_.max_speed, params_.tick_rate);
  stigmergy_ = controller::Stigmergy(self);
  members_.clear();
  for (int label = 0; label < table_.size(); ++label) members_[static_cast<RobotId>(label)] = label;
  ready_ = false;
  state_ = RobotState::Ready;
}

Command PreformedController::step(const Perception& p) {
  neighbours_.update(p, self_);
  for (const auto& [id, n] : neighbours_.all()) {
    if (n.last_heard == p.tick) stigmergy_.merge_all(neighbours_.entries_heard(n));
  }
  controller::FormationContext ctx;
  ctx.self = self_;
  ctx.tick = p.tick;
  ctx.perception = &p;
  ctx.pose = p.pose;
  ctx.params = &params_;
  ctx.table = &table_;
  ctx.label = static_cast<int>(self_);
  ctx.origin = origin_;
  ctx.places = table_.places(origin_, params_.shape_heading);
  ctx.common_heading = params_.shape_heading;
  ctx.neighbours = &neighbours_;
  ctx.stigmergy = &stigmergy_;
  ctx.members = members_;
  ctx.ready_tick = 0;
  if (!ready_) {
    motion_->on_ready(ctx);
    ready_ = true;
  }
  const auto out = motion_->step(ctx);
  state_ = out.state;

  Command cmd;
  const auto w = controller::clamp_wheels(
      out.wheels ? *out.wheels : controller::drive_velocity(out.velocity, p.pose.theta, params_.max_speed),
      params_.max_speed);
  cmd.left_speed = w.left;
  cmd.right_speed = w.right;
  controller::RobotMessage m;
  m.sender = self_;
  m.state = state_;
  m.label = static_cast<int>(self_);
  m.pose = p.pose;
  m.has_origin = true;
  m.origin = origin_;
  m.motion = out.message;
  m.entries = stigmergy_.outgoing(controller::kMaxEntriesPerMessage);
  cmd.message = controller::encode_message(m);
  cmd.telemetry.state = static_cast<std::int32_t>(state_);
  cmd.telemetry.extra =
      controller::paper_telemetry(static_cast<std::int32_t>(self_), out.parent, out.leader, out.net_force);
  cmd.telemetry.events = out.events;
  return cmd;
}

PreformedRun::PreformedRun(const world::Scenario& scenario, Vec2 origin, const std::string& run_dir)
    : world(scenario), session(world, {run_dir, "in-process"}) {
  for (RobotId id = 0; id < scenario.robots.size(); ++id) {
    controllers.push_back(std::make_unique<PreformedController>(origin));
    controllers.back()->init(scenario.mission, id);
  }
}

void PreformedRun::step() {
  for (RobotId id = 0; id < controllers.size(); ++id) {
    if (!controllers[id]) continue;
    world.apply_command(id, controllers[id]->step(world.perception(id)));
  }
  world.step();
  session.record_tick();
}

void PreformedRun::run(Tick max_ticks, const std::function<bool(const PreformedRun&)>& stop) {
  while (world.tick() < max_ticks) {
    step();
    if (stop && stop(*this)) break;
  }
}

void PreformedRun::kill(RobotId id) {
  world.kill(id);
  controllers[id].reset();
  session.record_death(id);
}

}  // namespace swarmform::sim_motion
