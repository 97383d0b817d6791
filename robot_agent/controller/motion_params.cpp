#include "robot_agent/controller/motion_params.hpp"

#include <cmath>

#include "robot_agent/controller/paper_params.hpp"

namespace swarmform::controller::motion {

MotionParams motion_params(const FormationParams& p) {
  auto value = [&](const char* name) { return param_value(p.overrides, name); };
  auto ticks = [&](const char* name) { return static_cast<int>(std::lround(value(name))); };
  MotionParams m;
  m.spacing = p.grid_spacing;
  m.max_speed = p.max_speed;
  m.comm_range = p.comm_range;
  m.goal = p.goal;
  m.goal_radius = p.goal_radius;
  m.ready_timeout = p.ready_timeout;
  m.boundary_delay = ticks("boundary_delay");
  m.neighbour_timeout = p.neighbour_timeout;
  m.boundary_cone = value("boundary_cone");
  m.link_range = value("link_range_fraction") * p.comm_range;
  m.k_o = p.k_o;
  m.k_goal = p.k_goal;
  m.cruise_speed = value("cruise_fraction") * p.max_speed;
  m.strain_scale = value("strain_scale");
  m.m_obstacle = p.m_obstacle;
  m.obstacle_range = p.obstacle_range;
  m.mask_angle = p.neighbour_mask_angle;
  m.mask_slack = value("mask_slack");
  m.fusion_range = value("fusion_range");
  m.small_obstacle_width = value("small_obstacle_width");
  m.wall_distance = value("wall_distance");
  m.k_collision = p.k_collision;
  m.r_o = p.r_o;
  m.arrival_tolerance = value("arrival_tolerance");
  m.arrival_net_force = value("arrival_net_force");
  return m;
}

}  // namespace swarmform::controller::motion
