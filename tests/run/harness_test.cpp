// RunSession on a real World, driven by the in-process harness with random-walk robots: the run directory
// has every file, a killed robot's death is recorded, the trajectory hash is reproducible, independent of
// recording, re-computable from robots.csv, and sensitive to one pose.
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/recording_reader.hpp"
#include "world_server/run/run_end.hpp"
#include "world_server/run/sha256.hpp"

namespace swarmform::harness {
namespace {

namespace fs = std::filesystem;

constexpr const char* kScenario = R"(
shape: SHAPES/triangle.txt
arena: {centre: [0.0, 0.0], width: 10.0, height: 10.0, walls: true}
robots: {count: 8, region: {centre: [0.0, 0.0], width: 4.0, height: 4.0}}
behaviour: random_walk
goal: {x: 3.0, y: 0.0, radius: 0.5}
seed: 3
max_ticks: 100
kills: [{id: 2, tick: 40}]
)";

// The shape by absolute path, so the test runs from any working directory.
world::Scenario scenario() {
  std::string text = kScenario;
  text.replace(text.find("SHAPES"), 6, std::string(SWARMFORM_REPO_DIR) + "/shapes");
  return world::parse_scenario_text(text, "<harness_test>", {}, swarmform::controller::builtin_registry());
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("swarmform-harness-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

TEST(Harness, RunWritesEveryFileAndTheKilledRobotsDeath) {
  const auto dir = fresh_dir("files");
  std::string sha;
  {
    Harness h(scenario(), {dir.string()});
    h.run();
    EXPECT_EQ(h.world().tick(), 100u);
    EXPECT_FALSE(h.world().alive(2));
    EXPECT_THROW(h.controller(2), std::logic_error);
    h.finish(1.5);
  }
  for (const char* f : {"world.json", "robots.csv", "events.jsonl", "world.log", "summary.json"}) {
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  }
  const auto world_json = world::read_json_file((dir / "world.json").string());
  EXPECT_EQ(world_json["robots"], 8);
  EXPECT_EQ(world_json["mode"], "in-process");
  // The radio as the scenario set it (independent loss: no mean burst).
  EXPECT_EQ(world_json["medium"]["packet_loss"]["rate"], 0.0);
  EXPECT_TRUE(world_json["medium"]["packet_loss"]["mean_burst"].is_null());
  EXPECT_EQ(world_json["medium"]["occlusion"], false);

  const auto rows = world::read_robots_csv((dir / "robots.csv").string());
  ASSERT_EQ(rows.size(), 101u * 8u);  // ticks 0..100
  EXPECT_EQ(rows.front().tick, 0u);
  EXPECT_EQ(rows.back().tick, 100u);
  for (const auto& r : rows) {
    // Robot 2 is killed at the start of tick 40, after tick 40's row was recorded.
    const bool expected_alive = r.id != 2 || r.tick <= 40;
    EXPECT_EQ(r.alive, expected_alive) << "robot " << r.id << " tick " << r.tick;
  }

  const auto events = world::read_events_jsonl((dir / "events.jsonl").string());
  int deaths = 0;
  for (const auto& e : events) {
    if (e["kind"] == "death") {
      ++deaths;
      EXPECT_EQ(e["id"], 2);
      EXPECT_EQ(e["tick"], 40);
    }
  }
  EXPECT_EQ(deaths, 1);  // once, although both the harness and the world's alive flag tell of it

  const auto summary = world::read_json_file((dir / "summary.json").string());
  EXPECT_EQ(summary["ticks"], 100);
  EXPECT_EQ(summary["alive_at_end"], 7);
  ASSERT_EQ(summary["deaths"].size(), 1u);
  EXPECT_EQ(summary["deaths"][0]["id"], 2);
  EXPECT_EQ(summary["deaths"][0]["tick"], 40);
  EXPECT_NEAR(summary["ticks_per_second"].get<double>(), 100 / 1.5, 1e-9);

  // The hash is re-computable from the recording alone (documented definition, exact numbers).
  world::Sha256 rehash;
  for (const auto& r : rows) {
    rehash.update_double(r.pose.x);
    rehash.update_double(r.pose.y);
    rehash.update_double(r.pose.theta);
  }
  EXPECT_EQ(summary["trajectory_sha256"], rehash.hex_digest());
  fs::remove_all(dir);
}

// record_every K thins robots.csv to ticks 0, K, 2K... (the same rows as the full recording's), and
// nothing else: every event, the same trajectory_sha256, world.json says K.
// A battery that runs out is an event at its tick, once per robot, and the robot stays alive (no death).
TEST(Harness, AnEmptyBatteryIsAnEventNotADeath) {
  const auto dir = fresh_dir("battery");
  std::string text = kScenario;
  text.replace(text.find("SHAPES"), 6, std::string(SWARMFORM_REPO_DIR) + "/shapes");
  text.replace(text.find("kills: [{id: 2, tick: 40}]"), 26,
               "battery: {capacity: 1, idle: 0.625}");  // 1/16 J a tick
  const auto s =
      world::parse_scenario_text(text, "<harness_test>", {}, swarmform::controller::builtin_registry());
  {
    Harness h(s, {dir.string()});
    h.run();
    h.finish(1.0);
  }
  int empties = 0;
  for (const auto& e : world::read_events_jsonl((dir / "events.jsonl").string())) {
    EXPECT_NE(e["kind"], "death");
    if (e["kind"] != "battery_empty") continue;
    ++empties;
    EXPECT_EQ(e["tick"], 16) << e.dump();
  }
  EXPECT_EQ(empties, 8);
  EXPECT_EQ(world::read_json_file((dir / "summary.json").string())["alive_at_end"], 8);
}

TEST(Harness, RecordEveryFiveWritesAFifthOfTheRowsAndTheSameHash) {
  const auto full_dir = fresh_dir("every1");
  const auto thin_dir = fresh_dir("every5");
  std::string full_summary, thin_summary;
  {
    Harness h(scenario(), {full_dir.string()});
    h.run();
    full_summary = h.finish(1.0);
  }
  {
    Harness h(scenario(), {thin_dir.string(), 0.0, 5});
    h.run();
    thin_summary = h.finish(1.0);
  }
  const auto full = world::read_robots_csv((full_dir / "robots.csv").string());
  const auto thin = world::read_robots_csv((thin_dir / "robots.csv").string());
  ASSERT_EQ(full.size(), 101u * 8u);
  ASSERT_EQ(thin.size(), 21u * 8u);  // ticks 0, 5, ..., 100
  std::size_t k = 0;
  for (const auto& r : full) {
    if (r.tick % 5 != 0) continue;
    ASSERT_LT(k, thin.size());
    EXPECT_EQ(thin[k].tick, r.tick);
    EXPECT_EQ(thin[k].id, r.id);
    EXPECT_EQ(thin[k].pose.x, r.pose.x);
    EXPECT_EQ(thin[k].alive, r.alive);
    ++k;
  }
  EXPECT_EQ(k, thin.size());
  const auto full_json = nlohmann::json::parse(full_summary);
  const auto thin_json = nlohmann::json::parse(thin_summary);
  EXPECT_EQ(thin_json["trajectory_sha256"], full_json["trajectory_sha256"]);
  EXPECT_EQ(thin_json["ticks"], 100);
  EXPECT_EQ(world::read_events_jsonl((thin_dir / "events.jsonl").string()).size(),
            world::read_events_jsonl((full_dir / "events.jsonl").string()).size());
  EXPECT_EQ(world::read_json_file((thin_dir / "world.json").string())["record_every"], 5);
  EXPECT_EQ(world::read_json_file((full_dir / "world.json").string())["record_every"], 1);
  EXPECT_THROW(Harness(scenario(), {thin_dir.string(), 0.0, 0}), std::invalid_argument);
  fs::remove_all(full_dir);
  fs::remove_all(thin_dir);
}

TEST(Harness, TrajectoryHashIsReproducibleAndSeesOnePose) {
  const auto s = scenario();
  std::string a;
  std::string b;
  {
    Harness h(s, {});
    h.run();
    a = nlohmann::json::parse(h.finish(0.0))["trajectory_sha256"];
  }
  const auto dir = fresh_dir("sha");
  {
    Harness h(s, {dir.string()});  // recording to disk changes nothing in the run
    h.run();
    b = nlohmann::json::parse(h.finish(0.0))["trajectory_sha256"];
  }
  EXPECT_EQ(a.size(), 64u);
  EXPECT_EQ(a, b);
  auto moved = s;
  moved.robots[5].x += 1e-9;  // one robot, one nanometre
  Harness h(moved, {});
  h.run();
  EXPECT_NE(nlohmann::json::parse(h.finish(0.0))["trajectory_sha256"], a);
  fs::remove_all(dir);
}

TEST(Harness, RevivedRobotRejoinsWithAFreshController) {
  auto s = scenario();
  s.kills.clear();
  Harness h(s, {});
  for (int i = 0; i < 10; ++i) h.step();
  h.kill(4);
  for (int i = 0; i < 10; ++i) h.step();
  const auto before = h.world().robots()[4].pose;
  h.revive(4);
  EXPECT_NO_THROW(h.controller(4));
  for (int i = 0; i < 30; ++i) h.step();
  EXPECT_TRUE(h.world().alive(4));
  const auto after = h.world().robots()[4].pose;
  EXPECT_GT(std::hypot(after.x - before.x, after.y - before.y), 0.05);  // it drives again
  ASSERT_EQ(h.metrics().deaths.size(), 1u);
  EXPECT_EQ(h.metrics().deaths[0].tick, 10u);
  ASSERT_EQ(h.metrics().rejoins.size(), 1u);
  EXPECT_EQ(h.metrics().rejoins[0].id, 4u);
  EXPECT_EQ(h.metrics().rejoins[0].tick, 20u);
}

TEST(Harness, StopsOnThePredicate) {
  Harness h(scenario(), {});
  h.run([](const Harness& x) { return x.world().tick() >= 17; });
  EXPECT_EQ(h.world().tick(), 17u);
}

}  // namespace
}  // namespace swarmform::harness
