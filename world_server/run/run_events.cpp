#include "world_server/run/run_events.hpp"

#include <array>
#include <string>

#include "world_server/run/comm_graph.hpp"

namespace swarmform::world {

namespace {

// The kinds the recorder derives itself or the front end reports with fixed meanings
// (docs/recording-format.md); a controller's event may not pose as one of them.
constexpr std::array<std::string_view, 9> kReservedKinds = {
    "state", "label", "leader", "leader_lost", "death", "rejoin", "fragment", "rejoin_graph", "command"};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

}  // namespace

std::vector<Event> controller_events(Tick tick, const std::vector<RobotTruth>& robots) {
  std::vector<Event> out;
  for (const auto& r : robots) {
    if (r.telemetry.events.empty() || r.telemetry_tick + 1 != tick) continue;
    for (const std::string& text : r.telemetry.events) {
      std::size_t b = 0;
      while (b < text.size() && is_space(text[b])) ++b;
      std::size_t e = b;
      while (e < text.size() && !is_space(text[e])) ++e;
      std::string kind = text.substr(b, e - b);
      if (kind.empty()) kind = "controller_event";
      for (const auto reserved : kReservedKinds) {
        if (kind == reserved) {
          kind.insert(0, "controller_");
          break;
        }
      }
      while (e < text.size() && is_space(text[e])) ++e;
      std::size_t end = text.size();
      while (end > e && is_space(text[end - 1])) --end;
      Event ev = make_event(tick, kind, r.id);
      ev["detail"] = text.substr(e, end - e);
      ev["source"] = "controller";
      out.push_back(std::move(ev));
    }
  }
  return out;
}

std::string EventDeriver::state_name(std::int32_t s, std::size_t id) const {
  for (const auto& st : id < robot_states_.size() ? robot_states_[id] : states_) {
    if (st.value == s) return std::string(st.name);
  }
  return "unknown";
}

Event make_event(Tick tick, std::string_view kind, std::int64_t id) {
  Event e;
  e["tick"] = tick;
  e["kind"] = kind;
  e["id"] = id;
  return e;
}

std::vector<Event> EventDeriver::observe(Tick tick, const std::vector<RobotTruth>& robots, bool track_graph,
                                         std::size_t& components) {
  std::vector<Event> out;
  if (seen_.size() < robots.size()) seen_.resize(robots.size());
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotTruth& r = robots[i];
    Seen& s = seen_[i];
    if (!baseline_) {
      s.alive = r.alive;
      s.telemetry = r.telemetry;
      continue;
    }
    if (s.alive != r.alive) {
      out.push_back(make_event(tick, r.alive ? "rejoin" : "death", r.id));
      s.alive = r.alive;
    }
    if (!r.alive) continue;  // a dead robot's last report is not news
    const Telemetry& before = s.telemetry;
    const Telemetry& now = r.telemetry;
    if (before.state != now.state) {
      Event e = make_event(tick, "state", r.id);
      e["from"] = before.state;
      e["to"] = now.state;
      e["from_name"] = state_name(before.state, i);
      e["to_name"] = state_name(now.state, i);
      out.push_back(std::move(e));
    }
    const behaviour::KnownColumns known = known_of(i);
    if (known.label_of(before) != known.label_of(now)) {
      Event e = make_event(tick, "label", r.id);
      e["from"] = known.label_of(before);
      e["to"] = known.label_of(now);
      out.push_back(std::move(e));
    }
    s.telemetry = now;
  }
  baseline_ = true;
  observe_leader(tick, robots, out);
  components = 0;
  if (track_graph) observe_graph(tick, robots, out, components);
  return out;
}

// The leader is the robot that says so. The incumbent keeps the title while it is alive and claims it. When
// it dies or stops claiming, `leader_lost` is recorded at once; a robot becomes the new leader after claiming
// it alone for kLeaderSettleTicks ticks (the event is written then, with `since` = the first of those ticks).
void EventDeriver::observe_leader(Tick tick, const std::vector<RobotTruth>& robots, std::vector<Event>& out) {
  const auto claims = [&](RobotId id) {
    return id < robots.size() && robots[id].alive && known_of(id).leader_of(robots[id].telemetry);
  };
  if (leader_ && claims(*leader_)) {
    candidate_.reset();
    return;
  }
  if (leader_) {
    out.push_back(make_event(tick, "leader_lost", *leader_));
    leader_.reset();
  }
  std::optional<RobotId> only;
  for (const auto& r : robots) {
    if (!r.alive || !known_of(r.id).leader_of(r.telemetry)) continue;
    if (only) {  // contested: nobody yet
      candidate_.reset();
      return;
    }
    only = r.id;
  }
  if (!only) {
    candidate_.reset();
    return;
  }
  if (!candidate_ || candidate_->id != *only) candidate_ = Candidate{*only, tick};
  if (tick + 1 - candidate_->since < kLeaderSettleTicks) return;
  Event e = make_event(tick, "leader", *only);
  e["previous"] = last_leader_ ? static_cast<std::int64_t>(*last_leader_) : std::int64_t{-1};
  e["since"] = candidate_->since;
  out.push_back(std::move(e));
  leader_ = only;
  last_leader_ = only;
  candidate_.reset();
}

void EventDeriver::observe_graph(Tick tick, const std::vector<RobotTruth>& robots, std::vector<Event>& out,
                                 std::size_t& components) {
  std::vector<Vec2> points;
  std::vector<RobotId> ids;
  for (const auto& r : robots) {
    // The formation's robots: those holding a label, in a run whose behaviours report labels; every live one
    // in a run where none does.
    if (!r.alive || (labelled_run_ && known_of(r.id).label_of(r.telemetry) < 0)) continue;
    points.push_back({r.pose.x, r.pose.y});
    ids.push_back(r.id);
  }
  if (points.empty()) return;
  const auto component = range_components(points, comm_range_);
  components = component_count(component);
  if (components > 1 && components_ <= 1) {
    Event e = make_event(tick, "fragment", -1);
    auto groups = nlohmann::ordered_json::array();
    for (std::size_t c = 0; c < components; ++c) groups.push_back(nlohmann::ordered_json::array());
    for (std::size_t i = 0; i < ids.size(); ++i) groups[component[i]].push_back(ids[i]);
    e["components"] = std::move(groups);
    out.push_back(std::move(e));
  } else if (components == 1 && components_ > 1) {
    Event e = make_event(tick, "rejoin_graph", -1);
    e["robots"] = ids;
    out.push_back(std::move(e));
  }
  components_ = components;
}

std::optional<Event> EventDeriver::death(Tick tick, RobotId id) {
  if (id < seen_.size()) {
    if (!seen_[id].alive) return std::nullopt;
    seen_[id].alive = false;
  }
  return make_event(tick, "death", id);
}

std::optional<Event> EventDeriver::rejoin(Tick tick, RobotId id) {
  if (id < seen_.size()) {
    if (seen_[id].alive) return std::nullopt;
    seen_[id].alive = true;
  }
  return make_event(tick, "rejoin", id);
}

}  // namespace swarmform::world
