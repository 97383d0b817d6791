// Scheduled faults in the in-process harness (world/faults.hpp, harness.hpp): a stalled robot's controller is
// not stepped for the stall's ticks, a restart gives a killed robot a fresh controller and brings it back,
// each fault's start and end is an event in events.jsonl, and the world faults change the trajectory.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::harness {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

const std::string kScenario = std::string(SWARMFORM_REPO_DIR) + "/tests/integration/random_walk_8.yaml";

world::Scenario scenario_with(std::vector<std::string> faults, Tick max_ticks = 60) {
  world::ScenarioOverrides ov;
  ov.faults = std::move(faults);
  ov.max_ticks = max_ticks;
  return world::load_scenario(kScenario, ov, swarmform::controller::builtin_registry());
}

// Counts its steps and stands still.
class Counting : public controller::Controller {
 public:
  explicit Counting(int* steps) : steps_(steps) {}
  void init(const Mission&, RobotId) override {}
  Command step(const Perception&) override {
    ++*steps_;
    return Command{};
  }
  void reset() override {}

 private:
  int* steps_;
};

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("swarmform-faults-sim-" + std::to_string(getpid()))) {
    fs::remove_all(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string str() const { return path_.string(); }

 private:
  fs::path path_;
};

std::vector<Json> events(const std::string& run_dir) {
  std::ifstream in(run_dir + "/events.jsonl");
  std::vector<Json> out;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(Json::parse(line));
  }
  return out;
}

// The (tick, id) of every event of `kind` whose detail starts with `text`.
std::vector<std::pair<int, int>> fault_events(const std::vector<Json>& all, const std::string& kind,
                                              const std::string& text) {
  std::vector<std::pair<int, int>> out;
  for (const Json& e : all) {
    if (e.value("kind", "") == kind && e.value("detail", "").rfind(text + ":", 0) == 0)
      out.emplace_back(e["tick"].get<int>(), e["id"].get<int>());
  }
  return out;
}

TEST(FaultsInProcess, AStalledRobotsControllerIsNotSteppedForTheStallAndEventsSaySo) {
  TempDir dir;
  {
    Harness h(scenario_with({"stall:3@5+10"}), {dir.str()});
    int steps = 0;
    h.set_controller(3, std::make_unique<Counting>(&steps));
    int steps_at_5 = -1;
    int steps_at_15 = -1;
    for (int t = 0; t < 20; ++t) {
      if (h.world().tick() == 5) steps_at_5 = steps;
      if (h.world().tick() == 15) steps_at_15 = steps;
      h.step();
    }
    EXPECT_EQ(steps_at_5, 5);
    EXPECT_EQ(steps_at_15, 5);  // ticks 5..14: not stepped
    EXPECT_EQ(steps, 10);
    EXPECT_TRUE(h.world().alive(3));  // a stall is not a death
    h.finish(0.0);
  }
  const auto all = events(dir.str());
  EXPECT_EQ(fault_events(all, "fault", "stall:3@5+10"), (std::vector<std::pair<int, int>>{{5, 3}}));
  EXPECT_EQ(fault_events(all, "fault_end", "stall:3@5+10"), (std::vector<std::pair<int, int>>{{15, 3}}));
}

TEST(FaultsInProcess, ARestartGivesTheKilledRobotAFreshControllerAndARejoin) {
  TempDir dir;
  {
    Harness h(scenario_with({"kill:2@4", "restart:2@9"}), {dir.str()});
    int steps = 0;
    h.set_controller(2, std::make_unique<Counting>(&steps));
    for (int t = 0; t < 9; ++t) h.step();
    EXPECT_FALSE(h.world().alive(2));
    EXPECT_EQ(steps, 4);
    h.step();  // tick 9: the restart
    EXPECT_TRUE(h.world().alive(2));
    EXPECT_EQ(steps, 4);  // the counting controller is gone: a fresh one of the mission's behaviour runs
    EXPECT_EQ(dynamic_cast<const Counting*>(&h.controller(2)), nullptr);
    h.finish(0.0);
  }
  const auto all = events(dir.str());
  EXPECT_EQ(fault_events(all, "fault", "restart:2@9"), (std::vector<std::pair<int, int>>{{9, 2}}));
  bool death = false;
  bool rejoin = false;
  for (const Json& e : all) {
    death = death || (e["kind"] == "death" && e["id"] == 2 && e["tick"] == 4);
    rejoin = rejoin || (e["kind"] == "rejoin" && e["id"] == 2 && e["tick"] == 9);
  }
  EXPECT_TRUE(death);
  EXPECT_TRUE(rejoin);
}

TEST(FaultsInProcess, WorldFaultsAreEventsWithTheRobotOrMinusOneAndChangeTheRun) {
  TempDir dir;
  std::string with_faults;
  {
    Harness h(scenario_with({"wheel:1/left@10+30", "loss:all@20+5", "range:4@30=1", "ultrasonic:5/2@3"}),
              {dir.str()});
    h.run();
    with_faults = Json::parse(h.finish(0.0))["trajectory_sha256"];
  }
  std::ifstream world_json(dir.str() + "/world.json");
  EXPECT_EQ(Json::parse(world_json)["faults"],
            Json({"wheel:1/left@10+30", "loss:all@20+5", "range:4@30=1", "ultrasonic:5/2@3"}));
  const auto all = events(dir.str());
  EXPECT_EQ(fault_events(all, "fault", "wheel:1/left@10+30"), (std::vector<std::pair<int, int>>{{10, 1}}));
  EXPECT_EQ(fault_events(all, "fault_end", "wheel:1/left@10+30"),
            (std::vector<std::pair<int, int>>{{40, 1}}));
  EXPECT_EQ(fault_events(all, "fault", "loss:all@20+5"), (std::vector<std::pair<int, int>>{{20, -1}}));
  EXPECT_EQ(fault_events(all, "fault_end", "loss:all@20+5"), (std::vector<std::pair<int, int>>{{25, -1}}));
  EXPECT_EQ(fault_events(all, "fault", "range:4@30=1"), (std::vector<std::pair<int, int>>{{30, 4}}));
  EXPECT_EQ(fault_events(all, "fault", "ultrasonic:5/2@3"), (std::vector<std::pair<int, int>>{{3, 5}}));
  Harness clean(scenario_with({}));
  clean.run();
  EXPECT_NE(Json::parse(clean.finish(0.0))["trajectory_sha256"], with_faults);
  // The same faults give the same run again.
  Harness again(scenario_with({"wheel:1/left@10+30", "loss:all@20+5", "range:4@30=1", "ultrasonic:5/2@3"}));
  again.run();
  EXPECT_EQ(Json::parse(again.finish(0.0))["trajectory_sha256"], with_faults);
}

}  // namespace
}  // namespace swarmform::harness
