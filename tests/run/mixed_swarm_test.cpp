// A mixed swarm in process (docs/scenario-format.md "Groups", scenarios/mixed_swarm.yaml): each robot runs
// its own group's behaviour; the paper's experiment judges the shapers alone; summary.json's `groups` and
// world.json's `groups` say so; state events are named by each robot's own behaviour.
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/paper_controller.hpp"
#include "robot_agent/controller/random_walk.hpp"
#include "world_server/run/recording_reader.hpp"
#include "world_server/world/robot_groups.hpp"

namespace swarmform::harness {
namespace {

namespace fs = std::filesystem;

world::Scenario mixed(const world::ScenarioOverrides& ov = {}) {
  return world::load_scenario(std::string(SWARMFORM_REPO_DIR) + "/scenarios/mixed_swarm.yaml", ov,
                              swarmform::controller::builtin_registry());
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("swarmform-mixed-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

int sum_of(const nlohmann::json& counts) {
  int n = 0;
  for (const auto& [name, count] : counts.items()) n += count.get<int>();
  return n;
}

TEST(MixedSwarm, EachRobotRunsItsGroupsBehaviourAndEachGroupIsJudgedAndRecordedOnItsOwn) {
  const auto dir = fresh_dir("run");
  const world::Scenario scenario = mixed();
  Harness h(scenario, {dir.string()});
  for (RobotId id = 0; id < 8; ++id) {
    EXPECT_NE(dynamic_cast<const controller::PaperController*>(&h.controller(id)), nullptr) << id;
  }
  for (RobotId id = 8; id < 12; ++id) {
    EXPECT_NE(dynamic_cast<const controller::RandomWalk*>(&h.controller(id)), nullptr) << id;
  }
  // The walkers stay in their one state; the shapers leave theirs (they take labels), over the run.
  std::set<std::int32_t> shaper_states, mover_states;
  h.run([&](const Harness& run) {
    for (const auto& r : run.world().robots())
      (r.id < 8 ? shaper_states : mover_states).insert(r.telemetry.state);
    return false;
  });
  EXPECT_EQ(mover_states, std::set<std::int32_t>{0});
  EXPECT_GE(shaper_states.size(), 3u);
  const nlohmann::json summary = nlohmann::json::parse(h.finish(1.0));

  // The top level is the first group's (the shapers').
  EXPECT_EQ(summary["behaviour"], "paper");
  EXPECT_EQ(summary["robots"], 12);
  EXPECT_EQ(sum_of(summary["states_at_end"]), 8);
  ASSERT_TRUE(summary.contains("groups")) << summary.dump(2);
  const auto& groups = summary["groups"];
  ASSERT_EQ(groups.size(), 2u);
  const auto& shapers = groups["shapers"];
  EXPECT_EQ(shapers["behaviour"], "paper");
  EXPECT_EQ(shapers["first_id"], 0);
  EXPECT_EQ(shapers["count"], 8);
  EXPECT_EQ(shapers["outcome"], summary["outcome"]);
  EXPECT_EQ(shapers["success"], summary["success"]);
  EXPECT_TRUE(shapers.contains("formation_tick"));  // the paper's experiment's own keys, per group
  EXPECT_EQ(shapers["formation_tick"], summary["formation_tick"]);
  EXPECT_EQ(sum_of(shapers["states_at_end"]), 8);  // its own robots by its own state names
  EXPECT_TRUE(shapers["states_at_end"].contains("motion"));
  EXPECT_FALSE(shapers["states_at_end"].contains("walking"));
  // The paper's experiment was shown the 8 shapers only: with the 4 walkers it would never see all its
  // robots in the shape, and nobody but a shaper is ever stuck short of a place.
  EXPECT_NE(shapers["formation_tick"], nullptr) << shapers.dump(2);
  for (const auto& id : shapers["stuck_robots"]) EXPECT_LT(id.get<int>(), 8);
  const auto& movers = groups["movers"];
  EXPECT_EQ(movers["behaviour"], "random_walk");
  EXPECT_EQ(movers["first_id"], 8);
  EXPECT_EQ(movers["count"], 4);
  EXPECT_EQ(movers["outcome"], "none");
  EXPECT_EQ(movers["success"], nullptr);
  EXPECT_EQ(movers["states_at_end"], (nlohmann::json{{"walking", 4}}));
  EXPECT_FALSE(movers.contains("formation_tick"));

  // world.json: every group, with its own descriptor; the top-level descriptor the first group's.
  const nlohmann::json world_json = world::read_json_file((dir / "world.json").string());
  ASSERT_EQ(world_json["groups"].size(), 2u);
  EXPECT_EQ(world_json["groups"][0]["name"], "shapers");
  EXPECT_EQ(world_json["groups"][0]["first_id"], 0);
  EXPECT_EQ(world_json["groups"][0]["count"], 8);
  EXPECT_EQ(world_json["groups"][0]["behaviour_descriptor"]["name"], "paper");
  EXPECT_EQ(world_json["groups"][1]["name"], "movers");
  EXPECT_EQ(world_json["groups"][1]["first_id"], 8);
  EXPECT_EQ(world_json["groups"][1]["behaviour_descriptor"]["name"], "random_walk");
  EXPECT_EQ(world_json["groups"][1]["behaviour_descriptor"]["states"][0]["name"], "walking");
  EXPECT_EQ(world_json["behaviour_descriptor"]["name"], "paper");

  // State events carry the robot's own behaviour's names: only shapers change state, by the paper's names.
  int state_events = 0;
  for (const auto& e : world::read_events_jsonl((dir / "events.jsonl").string())) {
    if (e["kind"] != "state") continue;
    ++state_events;
    EXPECT_LT(e["id"].get<int>(), 8);
    EXPECT_NE(e["to_name"], "unknown");
  }
  EXPECT_GT(state_events, 8);
  fs::remove_all(dir);
}

// A robot of another behaviour whose messages are in no format the paper knows: it stands still and
// broadcasts bytes of every length and value (a plug-in's own encoding, as the paper's robots hear it).
class ForeignTalker final : public controller::Controller {
 public:
  void init(const Mission&, RobotId self) override { self_ = self; }
  Command step(const Perception& p) override {
    Command c;
    const std::size_t n = (p.tick * 7 + self_) % 64;
    for (std::size_t k = 0; k < n; ++k)
      c.message.push_back(static_cast<std::uint8_t>((p.tick * 31 + k * 17 + self_) & 0xff));
    return c;
  }
  void reset() override {}

 private:
  RobotId self_ = 0;
};

TEST(MixedSwarm, ThePaperGroupFormsAndArrivesAmongRobotsSpeakingAnotherFormat) {
  const world::Scenario scenario = mixed();
  Harness h(scenario);
  for (RobotId id = 8; id < 12; ++id) {
    auto c = std::make_unique<ForeignTalker>();
    c->init(world::mission_of(scenario, id), id);
    h.set_controller(id, std::move(c));
  }
  h.run();
  const nlohmann::json summary = nlohmann::json::parse(h.finish(1.0));
  EXPECT_EQ(summary["groups"]["shapers"]["outcome"], "arrived") << summary["groups"]["shapers"].dump(2);
  EXPECT_EQ(summary["groups"]["shapers"]["arrived"], 8);
}

TEST(MixedSwarm, AScenarioWithoutGroupsWritesNoGroupsKey) {
  world::ScenarioOverrides ov;
  ov.max_ticks = 5;
  Harness h(world::load_scenario(std::string(SWARMFORM_REPO_DIR) + "/scenarios/paper.yaml", ov,
                                 swarmform::controller::builtin_registry()));
  h.run();
  const nlohmann::json summary = nlohmann::json::parse(h.finish(1.0));
  EXPECT_FALSE(summary.contains("groups"));
}

}  // namespace
}  // namespace swarmform::harness
