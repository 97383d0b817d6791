// Perception::goal (common/types.hpp) to and from a SensorPacket: has_goal and three doubles, copied bit for
// bit, so an agent's controller sees the goal the in-process one does.
#pragma once

#include <cmath>
#include <string>

#include "common/dds/internal/idl.hpp"
#include "common/types.hpp"

namespace swarmform::dds::internal {

inline void put_goal(const Perception& p, sfdds_SensorPacket& s) {
  s.has_goal = p.goal.has_value();
  s.goal_x = p.goal ? p.goal->at.x : 0.0;
  s.goal_y = p.goal ? p.goal->at.y : 0.0;
  s.goal_radius = p.goal ? p.goal->radius : 0.0;
}

inline void take_goal(const sfdds_SensorPacket& s, Perception& p) {
  p.goal = s.has_goal ? std::optional<Goal>(Goal{{s.goal_x, s.goal_y}, s.goal_radius}) : std::nullopt;
}

// Why the packet's goal cannot be used (empty: it can): a goal somewhere, with a radius.
inline std::string goal_problem(const sfdds_SensorPacket& s) {
  if (!s.has_goal) return {};
  if (!std::isfinite(s.goal_x) || !std::isfinite(s.goal_y) || !std::isfinite(s.goal_radius) ||
      s.goal_radius <= 0.0) {
    return "goal: not a finite point with a radius > 0";
  }
  return {};
}

}  // namespace swarmform::dds::internal
