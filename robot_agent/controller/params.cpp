#include "robot_agent/controller/params.hpp"

#include <cmath>
#include <string>

#include "common/input_error.hpp"
#include "robot_agent/controller/paper_params.hpp"

namespace swarmform::controller {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("<mission>", 0, what);
}

}  // namespace

FormationParams params_from_mission(const Mission& mission) {
  for (const auto& [name, value] : mission.params) {
    const ParamSpec* spec = find_param(name);
    require(spec != nullptr, "unknown controller parameter '" + name + "'");
    require(std::isfinite(value) && value >= spec->min_value && value <= spec->max_value,
            "controller parameter '" + name + "' = " + std::to_string(value) + " is outside [" +
                std::to_string(spec->min_value) + ", " + std::to_string(spec->max_value) + "]");
  }
  require(std::isfinite(mission.max_speed) && mission.max_speed > 0.0, "max_speed must be > 0");
  require(std::isfinite(mission.tick_rate) && mission.tick_rate > 0.0, "tick_rate must be > 0");
  require(std::isfinite(mission.grid_spacing) && mission.grid_spacing > 0.0, "grid_spacing must be > 0");

  FormationParams p;
  p.grid_spacing = mission.grid_spacing;
  p.max_speed = mission.max_speed;
  p.tick_rate = mission.tick_rate;
  p.comm_range = mission.comm_range;
  p.goal = mission.goal;
  p.goal_radius = mission.goal_radius;
  p.max_message_bytes = mission.max_message_bytes;
  p.seed = mission.seed;

  auto value = [&](const char* name) { return param_value(mission.params, name); };
  auto ticks = [&](const char* name) { return static_cast<int>(std::lround(value(name))); };
  p.k_collision = value("k_collision");
  p.r_o = value("r_o");
  p.reach_tolerance = value("reach_tolerance");
  p.heading_tolerance = value("heading_tolerance");
  p.neighbour_timeout = ticks("neighbour_timeout");
  p.label_timeout = ticks("label_timeout");
  p.k_move = value("k_move");
  p.seed_settle = ticks("seed_settle");
  p.shape_heading = value("shape_heading");
  p.ready_timeout = ticks("ready_timeout");
  p.k_o = value("k_o");
  p.k_goal = value("k_goal");
  p.m_obstacle = value("m_obstacle");
  p.obstacle_range = value("obstacle_range");
  p.neighbour_mask_angle = value("neighbour_mask_angle");
  p.overrides = mission.params;
  return p;
}

}  // namespace swarmform::controller
