// Where a run came from, for summary.json's `provenance`: the product's version, its git commit ("+dirty"
// when built from a changed work tree), the build type, and a SHA-256 of the scenario as loaded (every
// resolved field: overrides, placement and shape included; not the file's path), so two runs can be told
// comparable or not without trusting file names.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "world_server/world/scenario.hpp"

namespace swarmform::world {

// {"product", "version", "git_commit", "build_type", "scenario_sha256"}
nlohmann::ordered_json provenance(const Scenario& scenario);

// Lower-case hex SHA-256 of the loaded scenario's canonical JSON text (doubles written so that they read back
// exactly).
std::string scenario_sha256(const Scenario& scenario);

}  // namespace swarmform::world
