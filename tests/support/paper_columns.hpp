// Hand-made telemetry of a paper robot: its known columns (label, parent, leader, net force) set one at a
// time in Telemetry::extra, where the paper behaviour reports them
// (robot_agent/controller/paper_telemetry.hpp).
#pragma once

#include <cstdint>

#include "common/types.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"

namespace swarmform::testing {

inline double& paper_column(Telemetry& t, int at) {
  if (t.extra.size() != controller::kPaperTelemetry.size())
    t.extra = controller::paper_telemetry(-1, -1, false, 0.0);
  return t.extra[static_cast<std::size_t>(at)];
}
inline void set_label(Telemetry& t, std::int32_t label) {
  paper_column(t, controller::kPaperColumns.label) = label;
}
inline void set_parent(Telemetry& t, std::int32_t parent) {
  paper_column(t, controller::kPaperColumns.parent) = parent;
}
inline void set_leader(Telemetry& t, bool leader) {
  paper_column(t, controller::kPaperColumns.leader) = leader ? 1.0 : 0.0;
}
inline void set_net_force(Telemetry& t, double force) {
  paper_column(t, controller::kPaperColumns.net_force) = force;
}

}  // namespace swarmform::testing
