// The telemetry columns whose meaning the world knows (docs/behaviour-api.md, "Telemetry columns"). A
// behaviour that declares a column of one of these names reports that quantity in it; the world then checks
// it, records it in robots.csv's own column of that name, derives events from it and the viewers draw it. A
// behaviour that declares none has none: the world never makes up a label, a parent, a leader or a force.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>

#include "behaviour/descriptor.hpp"

namespace swarmform::behaviour {

// Its place in the shape (needs_shape): -1 none, else 0..labels-1. The world logs its changes (`label`
// events) and watches the communication graph among the robots holding one; the shape measurement pairs
// robots and places by it.
inline constexpr std::string_view kLabelColumn = "label";
// The robot it follows: -1 none, else a robot id. Drawn as a link from it to its parent.
inline constexpr std::string_view kParentColumn = "parent";
// 1 while it believes it leads, else 0. Drawn as a ring; the world's `leader` / `leader_lost` events and
// `leader_changes` come from it.
inline constexpr std::string_view kLeaderColumn = "leader";
// The magnitude of the force it steers by (>= 0, finite). Plotted against the distance travelled.
inline constexpr std::string_view kNetForceColumn = "net_force";

inline constexpr std::array<std::string_view, 4> kKnownColumns = {kLabelColumn, kParentColumn, kLeaderColumn,
                                                                  kNetForceColumn};
inline constexpr bool is_known_column(std::string_view name) {
  return std::find(kKnownColumns.begin(), kKnownColumns.end(), name) != kKnownColumns.end();
}

// Where a behaviour's known columns are in Telemetry::extra (-1: not declared), and their values in one
// telemetry. A value not reported yet (extra empty) reads as "none": -1, not a leader, 0.
struct KnownColumns {
  int label = -1;
  int parent = -1;
  int leader = -1;
  int net_force = -1;

  static KnownColumns of(const Descriptor* d) {
    KnownColumns k;
    if (d == nullptr) return k;
    for (std::size_t i = 0; i < d->telemetry.size(); ++i) {
      const std::string_view name = d->telemetry[i].name;
      const int at = static_cast<int>(i);
      if (name == kLabelColumn) k.label = at;
      if (name == kParentColumn) k.parent = at;
      if (name == kLeaderColumn) k.leader = at;
      if (name == kNetForceColumn) k.net_force = at;
    }
    return k;
  }

  bool known(std::size_t column) const {
    const int c = static_cast<int>(column);
    return c == label || c == parent || c == leader || c == net_force;
  }
  std::int32_t label_of(const Telemetry& t) const { return id_at(t, label); }
  std::int32_t parent_of(const Telemetry& t) const { return id_at(t, parent); }
  bool leader_of(const Telemetry& t) const { return value_at(t, leader) != 0.0; }
  double net_force_of(const Telemetry& t) const { return value_at(t, net_force); }

 private:
  static double value_at(const Telemetry& t, int at) {
    if (at < 0 || static_cast<std::size_t>(at) >= t.extra.size()) return 0.0;
    const double v = t.extra[static_cast<std::size_t>(at)];
    return std::isfinite(v) ? v : 0.0;
  }
  // An id or a label: a whole number in int32's range, else -1 (none).
  static std::int32_t id_at(const Telemetry& t, int at) {
    if (at < 0 || static_cast<std::size_t>(at) >= t.extra.size()) return -1;
    const double v = t.extra[static_cast<std::size_t>(at)];
    if (!std::isfinite(v) || v < -1.0 || v > 2147483647.0 || v != std::floor(v)) return -1;
    return static_cast<std::int32_t>(v);
  }
};

}  // namespace swarmform::behaviour
