// The paper behaviour's parameters: every name a scenario may set for it, with its default, bounds and unit.
// The table is the behaviour's descriptor's (builtins.cpp), so the world checks a scenario against it
// (file:line) and the controller fills its typed parameter struct from it. Add a parameter by adding a row
// here; document it in robot_agent/README.md.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "behaviour/descriptor.hpp"

namespace swarmform::controller {

using behaviour::ParamSpec;

inline constexpr std::array kPaperParams = {
    // Label allotment and shape formation (paper III.C).
    ParamSpec{"k_collision", 0.002, 0.0, 10.0, "eq. (1) collision repulsion gain"},
    ParamSpec{"r_o", 0.35, 0.0, 5.0, "eq. (1) threshold distance under which neighbours repel, m"},
    ParamSpec{"reach_tolerance", 0.03, 0.001, 1.0,
              "distance to its place at which a robot has reached it, m"},
    ParamSpec{"heading_tolerance", 0.05, 0.001, 1.0,
              "heading error at which a reached robot stops turning, rad"},
    ParamSpec{"neighbour_timeout", 20, 1, 1e6,
              "ticks without a message before a neighbour is taken for dead"},
    ParamSpec{"label_timeout", 40, 1, 1e6,
              "ticks before a silent robot's label is freed for others; raised for shapes over ~50 labels "
              "(robot_agent/controller/label_timeout.hpp)"},
    ParamSpec{"k_move", 1.0, 0.0, 100.0, "proportional gain towards the target place, 1/s"},
    ParamSpec{
        "seed_settle", 30, 1, 1e6,
        "ticks the flooded closest-to-origin candidate must stay unchanged before it becomes the seed; "
        "also the hop age past which a relayed candidate is dropped (must exceed the swarm's diameter)"},
    ParamSpec{"shape_heading", 1.5707963267948966, -3.1415926535897931, 3.1415926535897931,
              "arena direction of the shape's 'up' (towards row 0) and the common heading, rad"},
    // Ready and formation motion (paper III.C 'Ready', III.D).
    ParamSpec{"ready_timeout", 40, 0, 1e6, "ticks in 'ready' before the leader starts for the goal"},
    ParamSpec{"k_o", 1.0, 0.0, 100.0, "eq. (2), (4) reference/attractive force gain"},
    ParamSpec{"k_goal", 1.0, 0.0, 100.0, "eq. (3) goal attraction gain"},
    // Obstacles (paper III.E).
    ParamSpec{"m_obstacle", 1.0, 0.0, 100.0, "eq. (6)-(7) obstacle repulsion gain, per unit of |F_goal|"},
    ParamSpec{"obstacle_range", 0.6, 0.0, 2.0, "ultrasonic readings beyond this are not repulsive, m"},
    ParamSpec{"neighbour_mask_angle", 0.35, 0.0, 3.2, "Alg. 2 clearance around a neighbour's azimuth, rad"},
    // Ready and motion phases, added by the motion engineer (robot_agent/README.md, "Ready and motion").
    ParamSpec{"boundary_cone", 0.5235987755982988, 0.01, 1.5,
              "half-angle around heading +-pi/2 in which a neighbour hides a robot's left/right side, rad"},
    ParamSpec{"cruise_fraction", 1.0, 0.05, 1.0,
              "eq. (3) saturation: the leader's cruise speed as a fraction of the speed limit"},
    ParamSpec{"link_range_fraction", 0.9, 0.1, 1.0,
              "longest parent link, as a fraction of the communication range"},
    ParamSpec{"fusion_range", 1.0, 0.25, 2.0,
              "ultrasonic echoes nearer than this judge an obstacle's size, m"},
    ParamSpec{"small_obstacle_width", 0.5, 0.0, 5.0,
              "echo span under which an obstacle is small (wall-follow) rather than large (give way), m"},
    ParamSpec{"wall_distance", 0.4, 0.1, 2.0, "distance kept from a small obstacle while wall-following, m"},
    ParamSpec{"mask_slack", 0.1, 0.0, 1.0,
              "Alg. 2 range tolerance: an echo this much nearer than a neighbour is still it, m"},
    ParamSpec{"arrival_tolerance", 0.1, 0.01, 5.0,
              "the leader has arrived when its place is this close to where the goal puts it, m"},
    ParamSpec{"arrival_net_force", 0.01, 0.0, 1.0,
              "a follower whose parent has arrived stops once |F_net| is below this, m/s"},
    ParamSpec{"boundary_delay", 10, 1, 1e6, "ticks in 'ready' before a robot judges its boundary role"},
    ParamSpec{"strain_scale", 0.2, 0.0, 10.0,
              "leader cruise x (1 - (largest lag in the tree - 1.5 speed limit) / this), at least 0.3; "
              "0: never slows, m/s"},
};

inline const ParamSpec* find_param(std::string_view name) {
  for (const auto& p : kPaperParams) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

// The value of `name` from a mission's overrides, or its default. `name` must be in the table.
inline double param_value(const std::map<std::string, double>& overrides, std::string_view name) {
  auto it = overrides.find(std::string(name));
  if (it != overrides.end()) return it->second;
  const ParamSpec* spec = find_param(name);
  return spec ? spec->default_value : 0.0;
}

}  // namespace swarmform::controller
