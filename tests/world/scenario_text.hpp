// Scenarios written inline in a test, parsed as if they lived in scenarios/ (so `shape: triangle.txt`
// resolves as in a real file), and the check that one is refused at its line.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world::scenario_text {

inline const std::string kRepo = SWARMFORM_REPO_DIR;
inline const std::string kOrigin = kRepo + "/scenarios/inline-test.yaml";

inline Scenario parse(const std::string& text, const ScenarioOverrides& ov = {}) {
  return parse_scenario_text(text, kOrigin, ov, swarmform::controller::builtin_registry());
}

// Parsing must fail in `file` at `line` (0: no line) with a message containing `what`; a line of the inline
// file is also named in the message as `inline-test.yaml:LINE: `.
inline void expect_rejected(const std::string& text, int line, const std::string& what,
                            const ScenarioOverrides& ov = {}, const std::string& file = kOrigin) {
  try {
    parse(text, ov);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    if (line > 0 && file == kOrigin) {
      EXPECT_NE(std::string(e.what()).find("inline-test.yaml:" + std::to_string(line) + ": "),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace swarmform::world::scenario_text
