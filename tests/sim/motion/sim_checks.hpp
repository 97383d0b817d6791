// Checks on the truth of a run shared by the motion simulation tests: the parent tree as the robots report
// it, and the formation's neighbour graph.
#pragma once

#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/mission.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"
#include "robot_agent/controller/robot_state.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::sim_motion {

// "" when the live shape robots' reported parent links form one tree rooted at the one robot that reports
// itself leader; otherwise what is wrong.
inline std::string tree_problem(const std::vector<world::RobotTruth>& robots) {
  std::map<RobotId, std::int32_t> parent;
  std::vector<RobotId> leaders;
  for (const auto& r : robots) {
    if (!r.alive || controller::kPaperColumns.label_of(r.telemetry) < 0) continue;
    parent[r.id] = controller::kPaperColumns.parent_of(r.telemetry);
    if (controller::kPaperColumns.leader_of(r.telemetry)) leaders.push_back(r.id);
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
    if (r.alive && controller::kPaperColumns.label_of(r.telemetry) >= 0) live.push_back(&r);
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
    if (r.alive && controller::kPaperColumns.label_of(r.telemetry) >= 0 &&
        r.telemetry.state != static_cast<std::int32_t>(RobotState::Arrived)) {
      return false;
    }
  }
  return true;
}

// Arrival, judged from the truth (as the world will judge it): the live labelled robots, each at
// its own label's place after the best proper rigid fit, with an RMS error <= 0.1 grid units, every one of
// them at rest (within 5 mm of one point for the last 10 ticks), and their centroid within goal.radius of the
// goal. (The robots' own labels stand in for the world's best assignment: an upper bound of its error.)
class ArrivalJudge {
 public:
  explicit ArrivalJudge(const Mission& mission) : mission_(mission) {
    for (int r = 0; r < mission.shape.rows; ++r) {
      for (int c = 0; c < mission.shape.cols; ++c) {
        const int label = mission.shape.at(r, c);
        if (label < 0) continue;
        if (static_cast<std::size_t>(label) >= places_.size())
          places_.resize(static_cast<std::size_t>(label) + 1);
        places_[static_cast<std::size_t>(label)] = {c * mission.grid_spacing, -r * mission.grid_spacing};
      }
    }
  }
  // Call once per tick; true from the first tick the swarm stands arrived.
  bool observe(Tick tick, const std::vector<world::RobotTruth>& robots) {
    if (anchor_.size() < robots.size()) anchor_.resize(robots.size(), {0.0, 0.0, -1});
    std::vector<std::pair<Vec2, Vec2>> pairs;  // place, position
    bool at_rest = true;
    for (const auto& r : robots) {
      auto& a = anchor_[r.id];
      if (!r.alive) {
        a.since = -1;
        continue;
      }
      if (a.since < 0 || std::hypot(r.pose.x - a.x, r.pose.y - a.y) > 0.005)
        a = {r.pose.x, r.pose.y, static_cast<long>(tick)};
      const int label = controller::kPaperColumns.label_of(r.telemetry);
      if (label < 0 || static_cast<std::size_t>(label) >= places_.size()) continue;
      pairs.push_back({places_[static_cast<std::size_t>(label)], {r.pose.x, r.pose.y}});
      if (static_cast<long>(tick) < a.since + 10) at_rest = false;
    }
    if (pairs.size() < 2) return false;
    error_ = rigid_error(pairs) / mission_.grid_spacing;
    Vec2 c;
    for (const auto& p : pairs) c = {c.x + p.second.x, c.y + p.second.y};
    c = {c.x / static_cast<double>(pairs.size()), c.y / static_cast<double>(pairs.size())};
    to_goal_ = std::hypot(c.x - mission_.goal.x, c.y - mission_.goal.y);
    if (!arrived_ && at_rest && error_ <= 0.1 && to_goal_ <= mission_.goal_radius) arrived_ = tick;
    return arrived_.has_value();
  }
  std::optional<Tick> arrived() const { return arrived_; }
  double error() const { return error_; }      // grid units, this tick
  double to_goal() const { return to_goal_; }  // m, this tick's centroid

 private:
  struct Anchor {
    double x, y;
    long since;
  };
  static double rigid_error(const std::vector<std::pair<Vec2, Vec2>>& pairs) {
    const double n = static_cast<double>(pairs.size());
    Vec2 pc, rc;
    for (const auto& [p, r] : pairs) {
      pc = {pc.x + p.x / n, pc.y + p.y / n};
      rc = {rc.x + r.x / n, rc.y + r.y / n};
    }
    double dot = 0.0, cross = 0.0;
    for (const auto& [p, r] : pairs) {
      const double ax = p.x - pc.x, ay = p.y - pc.y, bx = r.x - rc.x, by = r.y - rc.y;
      dot += ax * bx + ay * by;
      cross += ax * by - ay * bx;
    }
    const double th = std::atan2(cross, dot), cs = std::cos(th), sn = std::sin(th);
    double sum = 0.0;
    for (const auto& [p, r] : pairs) {
      const double ax = p.x - pc.x, ay = p.y - pc.y;
      const double fx = cs * ax - sn * ay + rc.x, fy = sn * ax + cs * ay + rc.y;
      sum += (fx - r.x) * (fx - r.x) + (fy - r.y) * (fy - r.y);
    }
    return std::sqrt(sum / n);
  }
  Mission mission_;
  std::vector<Vec2> places_;
  std::vector<Anchor> anchor_;
  std::optional<Tick> arrived_;
  double error_ = 0.0, to_goal_ = 0.0;
};

}  // namespace swarmform::sim_motion
