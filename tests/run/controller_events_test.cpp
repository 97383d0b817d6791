// The controllers' own events (Telemetry::events, "<kind> <detail>") reach events.jsonl through RunSession on
// a real World: kind from the first word, the rest as `detail`, source "controller", written once at the
// tick after the command that carried them (not again while a robot's command is missing and its old
// telemetry stands), and a first word that names a derived kind cannot pose as it.
#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/recording_reader.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

namespace fs = std::filesystem;

constexpr const char* kScenario = R"(
shape: SHAPES/triangle.txt
arena: {centre: [0.0, 0.0], width: 10.0, height: 10.0, walls: true}
robots: {count: 3, region: {centre: [0.0, 0.0], width: 4.0, height: 4.0}}
behaviour: random_walk
goal: {x: 3.0, y: 0.0, radius: 0.5}
seed: 5
max_ticks: 100
)";

Scenario scenario() {
  std::string text = kScenario;
  text.replace(text.find("SHAPES"), 6, std::string(SWARMFORM_REPO_DIR) + "/shapes");
  return parse_scenario_text(text, "<controller_events_test>", {}, swarmform::controller::builtin_registry());
}

Command saying(std::vector<std::string> events) {
  Command c;
  c.telemetry.state = 1;
  c.telemetry.events = std::move(events);
  return c;
}

TEST(ControllerEvents, AreWrittenOnceWithKindAndDetail) {
  const fs::path dir =
      fs::temp_directory_path() / ("swarmform-controller-events-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  {
    const Scenario s = scenario();
    World world(s);
    RunSession session(world, {dir.string()});
    // Tick 0: robot 1 reports two events, one of them named like a derived kind; robot 2 one without detail.
    world.apply_command(0, saying({}));
    world.apply_command(1, saying({"label_taken 3 parent_label 0", "leader 1"}));
    world.apply_command(2, saying({"  arrived "}));
    world.step();
    session.record_tick();  // tick 1
    // Tick 1: no command from anyone: the old telemetry stands, its events are not news.
    world.step();
    session.record_tick();  // tick 2
    // Tick 2: robot 1 says the same again: a new report, written again.
    world.apply_command(1, saying({"label_taken 3 parent_label 0"}));
    world.step();
    session.record_tick();  // tick 3
    const auto summary = nlohmann::json::parse(session.finish(0.1));
    EXPECT_EQ(summary["leader_changes"], 0);  // "leader 1" from a controller is not an election
  }
  std::vector<nlohmann::json> mine;
  for (auto& e : read_events_jsonl((dir / "events.jsonl").string())) {
    if (e.value("source", "") == "controller") mine.push_back(e);
  }
  ASSERT_EQ(mine.size(), 4u);
  EXPECT_EQ(mine[0]["tick"], 1);
  EXPECT_EQ(mine[0]["id"], 1);
  EXPECT_EQ(mine[0]["kind"], "label_taken");
  EXPECT_EQ(mine[0]["detail"], "3 parent_label 0");
  EXPECT_EQ(mine[1]["tick"], 1);
  EXPECT_EQ(mine[1]["kind"], "controller_leader");
  EXPECT_EQ(mine[1]["detail"], "1");
  EXPECT_EQ(mine[2]["tick"], 1);
  EXPECT_EQ(mine[2]["id"], 2);
  EXPECT_EQ(mine[2]["kind"], "arrived");
  EXPECT_EQ(mine[2]["detail"], "");
  EXPECT_EQ(mine[3]["tick"], 3);
  EXPECT_EQ(mine[3]["id"], 1);
  EXPECT_EQ(mine[3]["kind"], "label_taken");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace swarmform::world
