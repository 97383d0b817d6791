// The example behaviours in whole runs: swarm_inprocess, and world_server with robot_agent processes over DDS
// (inside the caller's network namespace: tests/README.md). Each example's multi-process run has the
// in-process run's trajectory_sha256 (both modes load the same plug-in through the registry; the aggregation
// and foraging draw from their per-robot generators) and the same outcome and behaviour metrics (its
// experiment); the seek_light and avoidance examples run in-process only, judged by their experiments. A
// parameter out of the plug-in's bounds is file:line; a plug-in outside the allowed folders is refused by the
// world, the harness and the agent; a plug-in that fails is a dead robot multi-process and a clear end
// in-process. DDS domain offsets 29 (foraging) and 48..51 (tests/support/test_domain.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/process_fixture.hpp"
#include "tests/support/test_domain.hpp"

namespace {

using swarmform::testing::Process;
using swarmform::testing::read_file;
using swarmform::testing::test_domain;
using Json = nlohmann::json;
namespace fs = std::filesystem;

constexpr double kRunDeadline = 150.0;  // s, for one whole run (each takes a few seconds)
const std::string kExamples = EXAMPLES_DIR;

struct Example {
  std::string name;
  std::string plugin_dir;
  int domain_offset;
};

class ExampleRuns : public swarmform::testing::ProcessFixture {
 protected:
  ExampleRuns() : ProcessFixture("swarmform-examples") {}

  std::string scenario(const std::string& name) const {
    return kExamples + "/" + name + "/" + name + ".yaml";
  }

  // swarm_inprocess to completion; returns its exit code.
  int inprocess(const std::vector<std::string>& args, const std::string& tag) {
    std::vector<std::string> argv = {SWARM_INPROCESS_EXE, "--quiet"};
    argv.insert(argv.end(), args.begin(), args.end());
    Process& p = start(argv, tag);
    const auto code = p.wait_for(kRunDeadline);
    EXPECT_TRUE(code.has_value()) << tag << " did not end within " << kRunDeadline << " s";
    return code.value_or(-1);
  }

  Json summary(const std::string& run) const { return Json::parse(read_file(path(run) + "/summary.json")); }

  // world_server and one robot_agent block of `robots` over DDS domain `domain`, both given `plugin_dir`.
  void multiprocess(const std::string& scenario_path, const std::string& plugin_dir, int robots, int domain,
                    const std::string& run) {
    Process& world = start({WORLD_SERVER_EXE, "--scenario", scenario_path, "--out", path(run), "--domain",
                            std::to_string(domain), "--plugin-dir", plugin_dir, "--connect-timeout", "60"},
                           run + "-world");
    Process& agents = start({ROBOT_AGENT_EXE, "--id", "0", "--count", std::to_string(robots), "--domain",
                             std::to_string(domain), "--plugin-dir", plugin_dir, "--timeout", "60"},
                            run + "-agents");
    const auto code = world.wait_for(kRunDeadline);
    ASSERT_TRUE(code.has_value()) << "world_server did not end within " << kRunDeadline << " s";
    EXPECT_EQ(*code, 0) << world.err();
    EXPECT_TRUE(agents.wait_for(30.0).has_value());
  }

  // robots.csv's (state, leds) of every row, in file order.
  static std::vector<std::pair<std::string, std::string>> state_and_leds(const std::string& csv_path) {
    std::ifstream csv(csv_path);
    std::string line;
    std::getline(csv, line);
    const auto columns = split(line);
    const auto at = [&](const std::string& name) {
      return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
    };
    const std::size_t state = at("state"), leds = at("leds");
    EXPECT_LT(leds, columns.size()) << csv_path << ": no leds column in '" << line << "'";
    std::vector<std::pair<std::string, std::string>> rows;
    while (std::getline(csv, line)) {
      const auto f = split(line);
      if (f.size() != columns.size()) ADD_FAILURE() << csv_path << ": '" << line << "'";
      if (f.size() == columns.size()) rows.emplace_back(f[state], f[leds]);
    }
    return rows;
  }
  static std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out(1);
    for (char c : line) {
      if (c == ',')
        out.emplace_back();
      else
        out.back().push_back(c);
    }
    return out;
  }

  // The example in-process, then over DDS: the same trajectory and the same judgement. Returns the in-process
  // summary; the runs are in path("in") and path("multi").
  Json same_trajectory(const Example& e) {
    const std::string dir = e.plugin_dir;
    EXPECT_EQ(inprocess({"--scenario", scenario(e.name), "--plugin-dir", dir, "--out", path("in")}, "in"), 0);
    const Json in = summary("in");
    multiprocess(scenario(e.name), dir, in["robots"].get<int>(), test_domain(e.domain_offset), "multi");
    const Json multi = summary("multi");
    EXPECT_EQ(in["behaviour"], e.name);
    EXPECT_EQ(in["ticks"], multi["ticks"]);
    EXPECT_EQ(in["trajectory_sha256"], multi["trajectory_sha256"]);
    // The behaviour's own judgement is the world's, on the same truth: the same in both modes.
    EXPECT_EQ(in["outcome"], multi["outcome"]);
    EXPECT_EQ(in["success"], multi["success"]);
    EXPECT_EQ(in["behaviour_metrics"], multi["behaviour_metrics"]);
    EXPECT_FALSE(in["trajectory_sha256"].get<std::string>().empty());
    // The behaviour's telemetry columns are recorded after the fixed ones.
    std::ifstream csv(path("multi") + "/robots.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_NE(header.find("net_force,"), std::string::npos) << header;
    return in;
  }

  // A behaviour without an experiment: nothing to judge.
  static void not_judged(const Json& in) {
    EXPECT_EQ(in["outcome"], "none");
    EXPECT_TRUE(in["success"].is_null());
    EXPECT_TRUE(in["behaviour_metrics"].empty());
  }

  // The example in-process alone (the cheap way: no DDS); returns its summary.
  Json inprocess_run(const std::string& name, const std::string& dir) {
    EXPECT_EQ(inprocess({"--scenario", scenario(name), "--plugin-dir", dir, "--out", path(name)}, name), 0);
    return summary(name);
  }
};

TEST_F(ExampleRuns, AggregationInProcessAndMultiProcessHaveTheSameTrajectory) {
  const Json in = same_trajectory({"aggregation", AGGREGATION_DIR, 48});
  // Its own experiment: the metrics its descriptor declares, an outcome.
  EXPECT_TRUE(in["outcome"] == "gathered" || in["outcome"] == "scattered") << in["outcome"];
  EXPECT_EQ(in["success"], in["outcome"] == "gathered");
  const Json& m = in["behaviour_metrics"];
  EXPECT_GE(m["clusters"].get<double>(), 1.0);
  EXPECT_LE(m["largest_cluster"].get<double>(), in["alive_at_end"].get<double>());
  EXPECT_TRUE(m.contains("gathered_tick"));
  EXPECT_TRUE(m["mean_distance_to_centroid"].is_number());
  // The gathered robots' green LEDs reached the world's truth (multi-process: over the wire).
  EXPECT_EQ(m["green_at_end"], in["states_at_end"]["gathered"]);
  EXPECT_GT(m["green_at_end"].get<double>(), 0.0);
  // ... and the recording: every row's LEDs are all green exactly when its state is gathered (both come
  // from the same command), the same rows in both modes.
  const auto in_leds = state_and_leds(path("in") + "/robots.csv");
  EXPECT_EQ(in_leds, state_and_leds(path("multi") + "/robots.csv"));
  std::size_t green = 0;
  for (const auto& [state, leds] : in_leds) {
    EXPECT_EQ(leds, state == "2" ? "#00ff00 #00ff00 #00ff00" : "") << "state " << state;
    green += leds.empty() ? 0 : 1;
  }
  EXPECT_GT(green, 0u);
}
TEST_F(ExampleRuns, DispersionInProcessAndMultiProcessHaveTheSameTrajectory) {
  not_judged(same_trajectory({"dispersion", DISPERSION_DIR, 49}));
}
TEST_F(ExampleRuns, FlockingInProcessAndMultiProcessHaveTheSameTrajectory) {
  not_judged(same_trajectory({"flocking", FLOCKING_DIR, 50}));
}

// Foraging reads the ground, light and proximity sensors and sets its LEDs: over DDS as in-process, bit for
// bit. Its experiment counts deliveries from the robots' states; the LEDs say carrying (yellow) or not
// (blue).
TEST_F(ExampleRuns, ForagingDeliversItemsInProcessAndMultiProcessAlike) {
  const Json in = same_trajectory({"foraging", FORAGING_DIR, 29});
  EXPECT_EQ(in["outcome"], "foraged");
  EXPECT_EQ(in["success"], true);
  const Json& m = in["behaviour_metrics"];
  EXPECT_GE(m["items_delivered"].get<double>(), 4.0);  // the scenario's target_items
  EXPECT_TRUE(m["first_delivery_tick"].is_number());
  EXPECT_LE(m["carrying_at_end"].get<double>(), in["alive_at_end"].get<double>());
  const auto in_leds = state_and_leds(path("in") + "/robots.csv");
  EXPECT_EQ(in_leds, state_and_leds(path("multi") + "/robots.csv"));
  std::size_t carrying = 0, unlit = 0;
  for (const auto& [state, leds] : in_leds) {
    if (leds.empty()) {  // tick 0's rows: no command yet
      ++unlit;
      continue;
    }
    EXPECT_EQ(leds, state == "1" ? "#ffc800 #ffc800 #ffc800" : "#0000ff #0000ff #0000ff")
        << "state " << state;
    carrying += state == "1" ? 1 : 0;
  }
  EXPECT_EQ(unlit, in["robots"].get<std::size_t>());
  EXPECT_GT(carrying, 0u);
}

// SeekLight in-process: every robot gets within the goal's radius (under the light), and the experiment ends
// the run there (done()), before max_ticks.
TEST_F(ExampleRuns, SeekLightReachesTheLightAndEndsTheRun) {
  const Json in = inprocess_run("seek_light", SEEK_LIGHT_DIR);
  EXPECT_EQ(in["outcome"], "reached");
  EXPECT_EQ(in["success"], true);
  EXPECT_EQ(in["end_reason"], "completed");
  const Json& m = in["behaviour_metrics"];
  EXPECT_EQ(m["reached_at_end"], in["alive_at_end"]);
  EXPECT_LT(m["all_reached_tick"].get<double>(), 1500.0);  // the scenario's max_ticks
  EXPECT_LE(m["mean_distance_to_light"].get<double>(), 0.5);
}

// Avoidance in-process: the robots travel among the clutter without touching anything (the experiment's
// contacts on the true geometry, and the world's own contact counts).
TEST_F(ExampleRuns, AvoidanceKeepsClearOfTheClutter) {
  const Json in = inprocess_run("avoidance", AVOIDANCE_DIR);
  EXPECT_EQ(in["outcome"], "avoided");
  EXPECT_EQ(in["success"], true);
  const Json& m = in["behaviour_metrics"];
  EXPECT_EQ(m["contacts"], 0.0);
  EXPECT_GT(m["min_clearance"].get<double>(), 0.0);
  EXPECT_GE(m["mean_distance_travelled"].get<double>(), 3.0);  // min_travel 0.5 of 0.1 m/s x 60 s
  EXPECT_EQ(in["collisions_robot_obstacle"], 0);
  EXPECT_EQ(in["collisions_robot_robot"], 0);
}

// A copy of an example's scenario with `replace` swapped for `with`, in the test's folder.
std::string edited(const std::string& from, const std::string& to, const std::string& replace,
                   const std::string& with) {
  std::string text = read_file(from);
  const auto at = text.find(replace);
  if (at == std::string::npos) throw std::runtime_error("no '" + replace + "' in " + from);
  text.replace(at, replace.size(), with);
  std::ofstream(to) << text;
  return to;
}

TEST_F(ExampleRuns, ABadParameterIsNamedWithFileAndLine) {
  const std::string s =
      edited(scenario("aggregation"), path("bad.yaml"), "stop_distance: 0.4", "stop_distance: 40");
  EXPECT_EQ(inprocess({"--scenario", s, "--plugin-dir", AGGREGATION_DIR, "--no-record"}, "bad"), 2);
  const std::string err = read_file(path("bad.err"));
  EXPECT_NE(err.find(s + ":7: behaviour.params.stop_distance: must be in [0.15, 5]"), std::string::npos)
      << err;

  const std::string u =
      edited(scenario("aggregation"), path("unknown.yaml"), "stop_distance: 0.4", "stop_distanse: 0.4");
  EXPECT_EQ(inprocess({"--scenario", u, "--plugin-dir", AGGREGATION_DIR, "--no-record"}, "unknown"), 2);
  const std::string uerr = read_file(path("unknown.err"));
  EXPECT_NE(uerr.find(u + ":7: behaviour.params.stop_distanse: unknown parameter of behaviour 'aggregation'"),
            std::string::npos)
      << uerr;
}

TEST_F(ExampleRuns, APluginOutsideTheAllowedFoldersIsRefused) {
  // The plug-in copied to a folder of its own, named by its absolute path from a scenario in another folder.
  fs::create_directories(path("elsewhere"));
  fs::create_directories(path("scenario"));
  fs::copy_file(std::string(AGGREGATION_DIR) + "/libaggregation.so", path("elsewhere/libaggregation.so"));
  const std::string s = edited(scenario("aggregation"), path("scenario/outside.yaml"),
                               "plugin: libaggregation.so", "plugin: " + path("elsewhere/libaggregation.so"));
  EXPECT_EQ(inprocess({"--scenario", s, "--no-record"}, "refused"), 2);
  const std::string err = read_file(path("refused.err"));
  EXPECT_NE(err.find(s + ":6: behaviour.plugin: plug-in"), std::string::npos) << err;
  EXPECT_NE(err.find("lies outside the allowed plug-in folders"), std::string::npos) << err;
  // Given the folder, the same scenario runs.
  EXPECT_EQ(inprocess({"--scenario", s, "--plugin-dir", path("elsewhere"), "--no-record", "--max-ticks", "5"},
                      "allowed"),
            0);
}

TEST_F(ExampleRuns, AnAgentRefusesAPluginOutsideItsOwnFolders) {
  const int domain = test_domain(51);
  Process& world =
      start({WORLD_SERVER_EXE, "--scenario", scenario("aggregation"), "--out", path("run"), "--domain",
             std::to_string(domain), "--plugin-dir", AGGREGATION_DIR, "--connect-timeout", "20"},
            "world");
  // The world's mission names the plug-in's path; this agent was given no plug-in folder.
  Process& agent =
      start({ROBOT_AGENT_EXE, "--id", "0", "--domain", std::to_string(domain), "--timeout", "30"}, "agent");
  const auto code = agent.wait_for(60.0);
  ASSERT_TRUE(code.has_value()) << "the agent did not end";
  EXPECT_EQ(*code, 2);
  EXPECT_NE(agent.err().find("lies outside the allowed plug-in folders"), std::string::npos) << agent.err();
  world.kill();
}

TEST_F(ExampleRuns, AFailingPluginEndsAnInProcessRunNamingTheRobotAndTheBehaviour) {
  const std::string s = kExamples + "/tests/faulty/faulty.yaml";
  EXPECT_EQ(inprocess({"--scenario", s, "--plugin-dir", FAULTY_DIR, "--out", path("nan")}, "nan"), 6);
  const std::string err = read_file(path("nan.err"));
  EXPECT_NE(err.find("robot 1's behaviour 'faulty'"), std::string::npos) << err;
  EXPECT_NE(err.find("at tick 20: returned a non-finite wheel speed"), std::string::npos) << err;
  EXPECT_EQ(summary("nan")["end_reason"], "behaviour_failed");

  const std::string t = edited(s, path("throw.yaml"), "how: 0", "how: 1");
  EXPECT_EQ(inprocess({"--scenario", t, "--plugin-dir", FAULTY_DIR, "--no-record"}, "throw"), 6);
  const std::string terr = read_file(path("throw.err"));
  EXPECT_NE(terr.find("robot 1's behaviour 'faulty'"), std::string::npos) << terr;
  EXPECT_NE(terr.find("threw: faulty: thrown on purpose"), std::string::npos) << terr;

  const std::string c = edited(s, path("crash.yaml"), "how: 0", "how: 2");
  EXPECT_EQ(inprocess({"--scenario", c, "--plugin-dir", FAULTY_DIR, "--no-record"}, "crash"), 128 + SIGSEGV);
  const std::string cerr = read_file(path("crash.err"));
  EXPECT_NE(cerr.find("swarm_inprocess: robot 1's behaviour 'faulty'"), std::string::npos) << cerr;
  EXPECT_NE(cerr.find("crashed (SIGSEGV)"), std::string::npos) << cerr;
}

TEST_F(ExampleRuns, AFailingPluginIsADeadRobotNotADeadWorld) {
  const std::string s = kExamples + "/tests/faulty/faulty.yaml";
  for (const std::string how : {"0", "1", "2"}) {  // NaN, an exception, a crash
    SCOPED_TRACE("how " + how);
    const std::string run = "run" + how;
    const std::string scen = edited(s, path(run + ".yaml"), "how: 0", "how: " + how);
    multiprocess(scen, FAULTY_DIR, 4, test_domain(51), run);
    const Json j = summary(run);
    EXPECT_EQ(j["end_reason"], "max_ticks");
    EXPECT_EQ(j["ticks"], 60);
    EXPECT_EQ(j["alive_at_end"], 3);  // robot 1 died, the world and the others went on
  }
}

}  // namespace
