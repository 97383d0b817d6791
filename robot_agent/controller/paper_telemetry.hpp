// The paper behaviour's telemetry columns: the four quantities whose meaning the world knows
// (behaviour/known_columns.hpp), so robots.csv records them in its own columns, the world derives the label
// and leader events from them and the viewers draw the formation tree and the leader.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "behaviour/known_columns.hpp"

namespace swarmform::controller {

inline constexpr std::array kPaperTelemetry = {
    behaviour::TelemetryColumn{behaviour::kLabelColumn, "its label in the shape matrix, -1 none"},
    behaviour::TelemetryColumn{behaviour::kParentColumn,
                               "the id of its parent in the formation tree, -1 none"},
    behaviour::TelemetryColumn{behaviour::kLeaderColumn, "1 while it believes it is the leader, else 0"},
    behaviour::TelemetryColumn{behaviour::kNetForceColumn, "|F_net| (eq. 5), 0 when not in formation motion"},
};

// Where kPaperTelemetry puts the known columns (tests/controller/paper_telemetry_test.cpp checks it).
inline constexpr behaviour::KnownColumns kPaperColumns{0, 1, 2, 3};

// Telemetry::extra in kPaperTelemetry's order.
inline std::vector<double> paper_telemetry(std::int32_t label, std::int32_t parent, bool leader,
                                           double net_force) {
  return {static_cast<double>(label), static_cast<double>(parent), leader ? 1.0 : 0.0, net_force};
}

}  // namespace swarmform::controller
