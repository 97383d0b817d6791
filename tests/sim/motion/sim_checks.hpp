// Checks on the truth of a run shared by the motion simulation tests: the parent tree as the robots report
// it, and the formation's neighbour graph.
#pragma once

#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "common/robot_state.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::sim_motion {

// "" when the live shape robots' reported parent links form one tree rooted at the one robot that reports
// itself leader; otherwise what is wrong.
inline std::string tree_problem(const std::vector<world::RobotTruth>& robots) {
  std::map<RobotId, std::int32_t> parent;
  std::vector<RobotId> leaders;
  for (const auto& r : robots) {
    if (!r.alive || r.telemetry.label < 0) continue;
    parent[r.id] = r.telemetry.parent;
    if (r.telemetry.leader) leaders.push_back(r.id);
  }
  if (leaders.size() != 1) return std::to_string(leaders.size()) + " robots say they lead";
  const RobotId root = leaders[0];
  if (parent[root] != -1) return "the leader " + std::to_string(root) + " has a parent";
  for (const auto& [id, p] : parent) {
    RobotId at = id;
    std::size_t steps = 0;
    while (at != root) {
      const std::int32_t up = parent[at];
      if (up < 0) return "robot " + std::to_string(at) + " has no parent";
      if (!parent.count(static_cast<RobotId>(up))) {
        return "robot " + std::to_string(at) + "'s parent " + std::to_string(up) +
               " is dead or not in the shape";
      }
      at = static_cast<RobotId>(up);
      if (++steps > parent.size()) return "a cycle through robot " + std::to_string(id);
    }
  }
  return "";
}

// Components of the formation's neighbour graph: live shape robots joined when closer than `range` (the
// tests use 1.5 grid spacings, the paper's 3x3 grid neighbourhood).
inline std::size_t neighbour_components(const std::vector<world::RobotTruth>& robots, double range) {
  std::vector<const world::RobotTruth*> live;
  for (const auto& r : robots) {
    if (r.alive && r.telemetry.label >= 0) live.push_back(&r);
  }
  std::vector<std::size_t> comp(live.size());
  for (std::size_t i = 0; i < live.size(); ++i) comp[i] = i;
  auto find = [&](std::size_t i) {
    while (comp[i] != i) i = comp[i] = comp[comp[i]];
    return i;
  };
  for (std::size_t i = 0; i < live.size(); ++i) {
    for (std::size_t j = i + 1; j < live.size(); ++j) {
      if (std::hypot(live[i]->pose.x - live[j]->pose.x, live[i]->pose.y - live[j]->pose.y) < range) {
        comp[find(i)] = find(j);
      }
    }
  }
  std::set<std::size_t> roots;
  for (std::size_t i = 0; i < live.size(); ++i) roots.insert(find(i));
  return roots.size();
}

inline bool all_arrived(const std::vector<world::RobotTruth>& robots) {
  for (const auto& r : robots) {
    if (r.alive && r.telemetry.label >= 0 &&
        r.telemetry.state != static_cast<std::int32_t>(RobotState::Arrived)) {
      return false;
    }
  }
  return true;
}

}  // namespace swarmform::sim_motion
