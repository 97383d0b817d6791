#include "world_server/run/telemetry_check.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "world_server/world/robot_groups.hpp"

namespace swarmform::world {

namespace {

// Printable ASCII only: an event string is written into JSON and a log line; control bytes and invalid
// UTF-8 have no business there.
bool printable(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return c >= 0x20 && c < 0x7f; });
}

// The shortest text that reads back as `v` (2000000000, -1, 0.5).
std::string number_text(double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, res.ptr);
}

void note(TelemetryDrops& d, const std::string& what) {
  if (d.first.empty()) d.first = what;
}

}  // namespace

TelemetryLimits telemetry_limits(const Scenario& scenario, std::size_t group) {
  TelemetryLimits l;
  l.labels = scenario.mission.shape.label_count();
  l.robots = static_cast<std::uint32_t>(scenario.robots.size());
  if (const behaviour::Descriptor* d = group_view(scenario, group).behaviour) {
    const auto& states = d->states;
    l.min_state = 0;
    l.max_state = 0;
    for (const auto& st : states) {
      l.min_state = std::min(l.min_state, st.value);
      l.max_state = std::max(l.max_state, st.value);
    }
    l.extra = d->telemetry.size();
    l.known = behaviour::KnownColumns::of(d);
  }
  return l;
}

TelemetryDrops check_telemetry(Telemetry& t, const Telemetry& accepted, const TelemetryLimits& limits) {
  TelemetryDrops d;
  if (t.state < limits.min_state || t.state > limits.max_state) {
    note(d, "state " + std::to_string(t.state) + " outside " + std::to_string(limits.min_state) + ".." +
                std::to_string(limits.max_state));
    t.state = accepted.state;
    ++d.fields;
  }
  bool extra_ok = t.extra.empty() || t.extra.size() == limits.extra;
  for (const double v : t.extra) extra_ok = extra_ok && std::isfinite(v);
  if (!extra_ok) {
    note(d, std::to_string(t.extra.size()) + " telemetry columns, expected " + std::to_string(limits.extra) +
                " finite values");
    t.extra = accepted.extra;
    ++d.fields;
  }
  // A known column's value out of its range takes the value accepted before (none when there is none).
  const auto check_known = [&](int at, double low, double high, bool whole, const char* name, double none) {
    if (at < 0 || static_cast<std::size_t>(at) >= t.extra.size()) return;
    double& v = t.extra[static_cast<std::size_t>(at)];
    if (v >= low && v <= high && (!whole || v == std::floor(v))) return;
    note(d, std::string(name) + " " + number_text(v) + " outside " + number_text(low) + ".." +
                number_text(high));
    v = t.extra.size() == accepted.extra.size() ? accepted.extra[static_cast<std::size_t>(at)] : none;
    ++d.fields;
  };
  const behaviour::KnownColumns& k = limits.known;
  check_known(k.label, -1.0, static_cast<double>(limits.labels) - 1.0, true, "label", -1.0);
  check_known(k.parent, -1.0, static_cast<double>(limits.robots) - 1.0, true, "parent", -1.0);
  check_known(k.leader, 0.0, 1.0, true, "leader", 0.0);
  check_known(k.net_force, 0.0, limits.max_net_force, false, "net_force", 0.0);
  if (!t.events.empty()) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < t.events.size(); ++i) {
      std::string& e = t.events[i];
      if (kept >= limits.max_events) {
        note(d, "more than " + std::to_string(limits.max_events) + " event strings");
      } else if (e.size() > limits.max_event_bytes) {
        note(d, "an event string of " + std::to_string(e.size()) + " bytes (at most " +
                    std::to_string(limits.max_event_bytes) + ")");
      } else if (!printable(e)) {
        note(d, "an event string with bytes other than printable ASCII");
      } else {
        if (kept != i) t.events[kept] = std::move(e);
        ++kept;
        continue;
      }
      ++d.events;
    }
    t.events.resize(kept);
  }
  return d;
}

}  // namespace swarmform::world
