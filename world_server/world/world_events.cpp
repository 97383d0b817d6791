#include "world_server/world/world_events.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <numbers>
#include <utility>

#include "world_server/world/goal_events.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {
namespace {

using yaml::MapReader;
using yaml::Source;

constexpr double kMaxCoordinate = 1.0e4;  // m: as the scenario's other coordinates (scenario.cpp kMaxLength)

std::string tick_text(Tick t) {
  return "tick " + std::to_string(t);
}

std::size_t obstacle_named(const Source& src, const YAML::Node& at, const std::string& path,
                           const std::string& name, const Scenario& s) {
  std::vector<std::size_t> found;
  for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
    if (s.obstacles[i].name == name) found.push_back(i);
  }
  if (found.empty()) {
    std::string named;
    for (const Obstacle& o : s.obstacles) {
      if (!o.name.empty()) named += (named.empty() ? "" : ", ") + o.name;
    }
    yaml::fail(src, at, path,
               "no obstacle named '" + name + "' (" +
                   (named.empty() ? "no obstacle has a name" : "named: " + named) + ")");
  }
  if (found.size() > 1) {
    yaml::fail(src, at, path,
               "'" + name + "' names " + std::to_string(found.size()) +
                   " obstacles: give the one events move a name of its own");
  }
  return found.front();
}

}  // namespace

std::string_view action_word(WorldEvent::Action action) {
  switch (action) {
    case WorldEvent::Action::Appear:
      return "appear";
    case WorldEvent::Action::Disappear:
      return "disappear";
    case WorldEvent::Action::Move:
      return "move";
  }
  return "move";
}

void parse_world_events(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("events");
  if (!node || node->IsNull()) return;
  if (!node->IsSequence()) {
    yaml::fail(src, *node, "events",
               "expected a list of world events, e.g. [{tick: 600, obstacle: gate, do: appear}]");
  }
  struct Checked {
    WorldEvent event;
    YAML::Node node;
    std::string path;
  };
  std::vector<Checked> checked;
  for (std::size_t i = 0; i < node->size(); ++i) {
    const YAML::Node item = (*node)[i];
    const std::string path = "events[" + std::to_string(i) + "]";
    if (!item.IsMap()) {
      yaml::fail(src, item, path,
                 "expected a map {tick, obstacle, do[, centre, yaw]} or {tick, goal[, radius]}");
    }
    MapReader m(src, item, path);
    if (m.has("goal")) {  // the goal moves (goal_events.hpp), checked once the goal is known
      s.goal_events.push_back(parse_goal_event(src, m, s.max_ticks));
      continue;
    }
    WorldEvent e;
    if (!m.has("tick")) yaml::fail(src, item, path, "missing 'tick'");
    e.tick = static_cast<Tick>(m.integer("tick", 1, 1, static_cast<std::int64_t>(s.max_ticks)));
    auto name = m.get("obstacle");
    if (!name)
      yaml::fail(src, item, path,
                 "missing 'obstacle' (the name of one of `obstacles`) or 'goal' ([x, y]: the goal moves)");
    e.obstacle =
        obstacle_named(src, *name, m.field("obstacle"), yaml::to_string(src, *name, m.field("obstacle")), s);
    auto action = m.get("do");
    if (!action) yaml::fail(src, item, path, "missing 'do' (appear, disappear or move)");
    const std::string word = yaml::to_string(src, *action, m.field("do"));
    if (word == "appear") {
      e.action = WorldEvent::Action::Appear;
    } else if (word == "disappear") {
      e.action = WorldEvent::Action::Disappear;
    } else if (word == "move") {
      e.action = WorldEvent::Action::Move;
      auto centre = m.get("centre");
      if (!centre) yaml::fail(src, item, path, "missing 'centre' ([x, y], m): where the obstacle moves to");
      e.centre = yaml::to_vec2(src, *centre, m.field("centre"));
      yaml::check_range(src, *centre, m.field("centre") + "[0]", e.centre.x, -kMaxCoordinate, kMaxCoordinate);
      yaml::check_range(src, *centre, m.field("centre") + "[1]", e.centre.y, -kMaxCoordinate, kMaxCoordinate);
      if (m.has("yaw")) {
        if (s.obstacles[e.obstacle].kind != Obstacle::Kind::Box) {
          yaml::fail(src, item, m.field("yaw"), "a cylinder has no yaw");
        }
        e.yaw = m.number("yaw", 0.0, -2.0 * std::numbers::pi, 2.0 * std::numbers::pi);
      }
    } else {
      yaml::fail(src, *action, m.field("do"), "expected appear, disappear or move, got '" + word + "'");
    }
    if (e.action == WorldEvent::Action::Move) {
      m.finish({"tick", "obstacle", "do", "centre", "yaw"});
    } else {
      m.finish({"tick", "obstacle", "do"});
    }
    checked.push_back({e, item, path});
  }
  std::stable_sort(checked.begin(), checked.end(),
                   [](const Checked& a, const Checked& b) { return a.event.tick < b.event.tick; });
  // Each obstacle's story in tick order: one event a tick, appear only when absent, disappear only when
  // there.
  std::vector<char> present;
  for (const Obstacle& o : s.obstacles) present.push_back(o.present ? 1 : 0);
  std::map<std::size_t, Tick> last;
  for (const Checked& c : checked) {
    const WorldEvent& e = c.event;
    const std::string& name = s.obstacles[e.obstacle].name;
    if (auto it = last.find(e.obstacle); it != last.end() && it->second == e.tick) {
      yaml::fail(
          src, c.node, c.path,
          "a second event for '" + name + "' at " + tick_text(e.tick) + ": one event an obstacle a tick");
    }
    last[e.obstacle] = e.tick;
    if (e.action == WorldEvent::Action::Appear && present[e.obstacle]) {
      yaml::fail(src, c.node, c.path,
                 "'" + name + "' is already there at " + tick_text(e.tick) +
                     " (give it `present: false` to start absent)");
    }
    if (e.action == WorldEvent::Action::Disappear && !present[e.obstacle]) {
      yaml::fail(src, c.node, c.path,
                 "'" + name + "' is not there at " + tick_text(e.tick) + " to disappear");
    }
    if (e.action == WorldEvent::Action::Appear) present[e.obstacle] = 1;
    if (e.action == WorldEvent::Action::Disappear) present[e.obstacle] = 0;
    s.world_events.push_back(e);
  }
}

std::size_t apply_world_events(std::vector<Obstacle>& obstacles, const std::vector<WorldEvent>& events,
                               Tick t) {
  const auto first = std::lower_bound(events.begin(), events.end(), t,
                                      [](const WorldEvent& e, Tick tick) { return e.tick < tick; });
  std::size_t applied = 0;
  for (auto it = first; it != events.end() && it->tick == t; ++it, ++applied) {
    Obstacle& o = obstacles[it->obstacle];
    switch (it->action) {
      case WorldEvent::Action::Appear:
        o.present = true;
        break;
      case WorldEvent::Action::Disappear:
        o.present = false;
        break;
      case WorldEvent::Action::Move:
        o.centre = it->centre;
        if (it->yaw) o.yaw = *it->yaw;
        break;
    }
  }
  return applied;
}

std::string describe_world_event(const WorldEvent& e, const std::vector<Obstacle>& obstacles) {
  std::string text = obstacles[e.obstacle].name;
  if (e.action != WorldEvent::Action::Move) return text;
  char buf[96];
  std::snprintf(buf, sizeof buf, " to (%g, %g)", e.centre.x, e.centre.y);
  text += buf;
  if (e.yaw) {
    std::snprintf(buf, sizeof buf, " yaw %g", *e.yaw);
    text += buf;
  }
  return text;
}

}  // namespace swarmform::world
