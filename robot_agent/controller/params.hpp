// The controller's typed parameters: the mission's values plus every row of
// robot_agent/controller/paper_params.hpp, checked once at init (unknown name or out of bounds -> InputError
// naming the parameter).
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "common/mission.hpp"
#include "common/types.hpp"

namespace swarmform::controller {

struct FormationParams {
  // From the mission.
  double grid_spacing = 1.0;  // m
  double max_speed = 0.1;     // m/s
  double tick_rate = 10.0;    // ticks/s
  double comm_range = 3.0;    // m
  Vec2 goal{10.0, 0.0};       // m (the leader's only)
  double goal_radius = 0.5;   // m
  std::uint32_t max_message_bytes = 1024;
  std::uint64_t seed = 1;

  // From the parameter table (names and units there).
  double k_collision = 0.002;
  double r_o = 0.35;
  double reach_tolerance = 0.03;
  double heading_tolerance = 0.05;
  int neighbour_timeout = 20;  // ticks
  int label_timeout = 40;      // ticks
  double k_move = 1.0;
  int seed_settle = 30;  // ticks
  double shape_heading = 1.5707963267948966;
  int ready_timeout = 40;  // ticks
  double k_o = 1.0;
  double k_goal = 1.0;
  double m_obstacle = 0.05;
  double obstacle_range = 0.6;
  double neighbour_mask_angle = 0.35;
  // Every parameter as the mission set it (name -> value), for phases that read their own rows of
  // robot_agent/controller/paper_params.hpp with param_value() (the motion phases: motion_params.hpp).
  std::map<std::string, double> overrides;

  double dt() const { return 1.0 / tick_rate; }  // s per tick
};

// Throws InputError("<mission>", 0, ...) for an unknown name, a value out of bounds, or a bad mission value.
FormationParams params_from_mission(const Mission& mission);

}  // namespace swarmform::controller
