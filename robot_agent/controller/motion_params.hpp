// The motion phases' parameters, typed: the mission's values and the rows of
// robot_agent/controller/paper_params.hpp that the Ready and motion phases read (robot_agent/README.md,
// "Ready and motion", says what each does).
#pragma once

#include "common/types.hpp"
#include "robot_agent/controller/params.hpp"

namespace swarmform::controller::motion {

struct MotionParams {
  // From the mission.
  double spacing = 1.0;      // m, grid spacing
  double max_speed = 0.1;    // m/s
  double comm_range = 3.0;   // m
  Vec2 goal{10.0, 0.0};      // m: every robot holds it, only the leader uses it
  double goal_radius = 0.5;  // m: the world judges arrival by the shape's centroid within it
  // Ready.
  int ready_timeout = 40;                     // ticks in Ready before Motion
  int boundary_delay = 10;                    // ticks in Ready before judging the boundary role
  int neighbour_timeout = 20;                 // ticks of silence before a neighbour is marked dead
  double boundary_cone = 0.5235987755982988;  // rad
  double link_range = 2.7;                    // m, longest parent link
  // Formation and goal forces, eq. (2)-(5).
  double k_o = 1.0;
  double k_goal = 1.0;
  double cruise_speed = 0.1;  // m/s, eq. (3) saturation
  double strain_scale = 0.2;  // m/s, the leader's wait for a strained shape (0: never waits)
  // Obstacles, eq. (6)-(7), Algorithm 2, wall-following.
  double m_obstacle = 1.0;
  double obstacle_range = 0.6;        // m
  double mask_angle = 0.35;           // rad
  double mask_slack = 0.1;            // m
  double fusion_range = 1.0;          // m
  double small_obstacle_width = 0.5;  // m
  double wall_distance = 0.4;         // m
  // Collision avoidance, eq. (1) (the formation engineer's collision_avoidance.hpp).
  double k_collision = 0.002;
  double r_o = 0.35;  // m
  // Arrival.
  double arrival_tolerance = 0.1;   // m
  double arrival_net_force = 0.01;  // m/s
};

MotionParams motion_params(const FormationParams& p);

}  // namespace swarmform::controller::motion
