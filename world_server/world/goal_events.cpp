#include "world_server/world/goal_events.hpp"

#include <algorithm>
#include <cstdio>

#include "common/input_error.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {
namespace {

constexpr double kMaxCoordinate = 1.0e4;  // m: as the scenario's other coordinates (scenario.cpp kMaxLength)

bool inside_walls(const Scenario& s, Vec2 p) {
  return std::abs(p.x - s.arena_centre.x) <= s.arena_width / 2.0 &&
         std::abs(p.y - s.arena_centre.y) <= s.arena_height / 2.0;
}

}  // namespace

GoalEvent parse_goal_event(const yaml::Source& src, yaml::MapReader& m, Tick max_ticks) {
  GoalEvent e;
  e.line = yaml::line_of(m.node());
  if (!m.has("tick")) yaml::fail(src, m.node(), m.path(), "missing 'tick'");
  e.tick = static_cast<Tick>(m.integer("tick", 1, 1, static_cast<std::int64_t>(max_ticks)));
  const auto at = m.get("goal");
  e.goal.at = yaml::to_vec2(src, *at, m.field("goal"));
  yaml::check_range(src, *at, m.field("goal") + "[0]", e.goal.at.x, -kMaxCoordinate, kMaxCoordinate);
  yaml::check_range(src, *at, m.field("goal") + "[1]", e.goal.at.y, -kMaxCoordinate, kMaxCoordinate);
  e.radius_given = m.has("radius");
  if (e.radius_given) e.goal.radius = m.positive("radius", 0.0, kMaxCoordinate);
  m.finish({"tick", "goal", "radius"});
  return e;
}

void check_goal_events(const std::string& origin, Scenario& s) {
  auto& events = s.goal_events;
  if (events.empty()) return;
  std::stable_sort(events.begin(), events.end(),
                   [](const GoalEvent& a, const GoalEvent& b) { return a.tick < b.tick; });
  if (!s.mission.has_goal) {
    throw InputError(origin, events.front().line,
                     "events: a goal move, but the run has no goal (give the scenario a `goal:`)");
  }
  double radius = s.mission.goal_radius;
  for (std::size_t i = 0; i < events.size(); ++i) {
    GoalEvent& e = events[i];
    if (i > 0 && events[i - 1].tick == e.tick) {
      throw InputError(origin, e.line,
                       "events: a second goal move at tick " + std::to_string(e.tick) + ": one a tick");
    }
    if (!e.radius_given) e.goal.radius = radius;
    radius = e.goal.radius;
    if (s.walls && !inside_walls(s, e.goal.at)) {
      char at[96];
      std::snprintf(at, sizeof at, "(%g, %g)", e.goal.at.x, e.goal.at.y);
      throw InputError(origin, e.line,
                       std::string("events: the goal moves to ") + at + ", outside the arena's walls");
    }
  }
}

std::optional<Goal> goal_at(const Scenario& s, Tick t) {
  if (!s.mission.has_goal) return std::nullopt;
  Goal g{s.mission.goal, s.mission.goal_radius};
  for (const GoalEvent& e : s.goal_events) {
    if (e.tick > t) break;
    g = e.goal;
  }
  return g;
}

std::string describe_goal_event(const GoalEvent& e) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "to (%g, %g) radius %g", e.goal.at.x, e.goal.at.y, e.goal.radius);
  return buf;
}

}  // namespace swarmform::world
