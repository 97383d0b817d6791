// `--record-every K`, one definition for the two programs that record a run (world_server and the in-process
// harness), so both take and refuse the same values with the same words.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "common/types.hpp"

namespace swarmform::world {

inline CLI::Option* add_record_every_flag(CLI::App& app, Tick& record_every) {
  return app
      .add_option("--record-every", record_every,
                  "K: robots.csv gets the rows of every K-th tick only (ticks 0, K, 2K...; an integer >= 1, "
                  "default 1); events, metrics and trajectory_sha256 still cover every tick")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            const bool digits = !text.empty() && text.size() <= 9 &&
                                text.find_first_not_of("0123456789") == std::string::npos;
            if (!digits || std::stoul(text) < 1)
              return "must be an integer from 1 to 999999999, got '" + text + "'";
            return {};
          },
          "K>=1"));
}

}  // namespace swarmform::world
