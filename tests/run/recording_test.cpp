// The recording format: what RecordingWriter writes, the reader gets back exactly; world.json and
// summary.json carry every documented key; the SHA-256 helper is the standard one.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "common/input_error.hpp"
#include "tests/support/paper_columns.hpp"
#include "world_server/run/recorder.hpp"
#include "world_server/run/recording_format.hpp"
#include "world_server/run/recording_reader.hpp"
#include "world_server/run/run_events.hpp"
#include "world_server/run/sha256.hpp"

namespace swarmform::world {
namespace {

namespace fs = std::filesystem;

// Per process: other build folders may run the same tests at the same time.
fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("swarmform-run-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

std::vector<RobotTruth> robots_at(Tick tick) {
  std::vector<RobotTruth> robots(4);
  for (RobotId i = 0; i < 4; ++i) {
    RobotTruth& r = robots[i];
    r.id = i;
    // Values whose shortest decimal form is long or unusual: the round trip must still be exact.
    r.pose = {0.1 * i + 1.0 / 3.0 * static_cast<double>(tick), -1e-300 * i, std::numbers::pi - i};
    r.alive = i != 2;
    r.telemetry.state = static_cast<std::int32_t>(tick % 7);
    testing::set_label(r.telemetry, static_cast<std::int32_t>(i) - 1);
    testing::set_parent(r.telemetry, i == 0 ? -1 : 0);
    testing::set_leader(r.telemetry, i == 0);
    testing::set_net_force(r.telemetry, std::sqrt(2.0) * static_cast<double>(tick));
    // Robot 1's LEDs change every tick (every byte value passes through one of them); the others' stay off.
    if (i == 1) {
      const auto v = static_cast<std::uint8_t>(tick * 37 % 256);
      r.leds = {Rgb{v, 0, 255}, Rgb{}, Rgb{255, static_cast<std::uint8_t>(255 - v), 16}};
    }
  }
  return robots;
}

TEST(Recording, RobotsCsvAndEventsRoundTrip) {
  const auto dir = fresh_dir("roundtrip");
  {
    // The paper's known columns: robots.csv's label, parent, leader and net_force are read from them.
    RecordingWriter writer(dir.string(), {}, 0, {},
                           std::vector<behaviour::KnownColumns>(4, controller::kPaperColumns));
    for (Tick t = 0; t < 25; ++t) writer.write_rows(t, robots_at(t));
    Event e = make_event(12, "state", 3);
    e["from"] = 1;
    e["to"] = 2;
    writer.write_event(e);
    Event f = make_event(20, "fragment", -1);
    f["components"] = {{0, 1}, {3}};
    writer.write_event(f);
  }  // closed without a summary, as a crashed run would be (after its last flush)

  const auto rows = read_robots_csv((dir / "robots.csv").string());
  ASSERT_EQ(rows.size(), 25u * 4u);
  for (Tick t = 0; t < 25; ++t) {
    const auto expected = robots_at(t);
    for (RobotId i = 0; i < 4; ++i) {
      const RecordedRow& r = rows[t * 4 + i];
      EXPECT_EQ(r.tick, t);
      EXPECT_EQ(r.id, i);
      // Bit-exact: the recording can be replayed and re-hashed.
      EXPECT_EQ(r.pose.x, expected[i].pose.x);
      EXPECT_EQ(r.pose.y, expected[i].pose.y);
      EXPECT_EQ(r.pose.theta, expected[i].pose.theta);
      EXPECT_EQ(r.alive, expected[i].alive);
      EXPECT_EQ(r.state, expected[i].telemetry.state);
      const Telemetry& said = expected[i].telemetry;
      EXPECT_EQ(r.label, static_cast<std::int32_t>(i) - 1);
      EXPECT_EQ(r.label, controller::kPaperColumns.label_of(said));
      EXPECT_EQ(r.parent, controller::kPaperColumns.parent_of(said));
      EXPECT_EQ(r.leader, controller::kPaperColumns.leader_of(said));
      EXPECT_EQ(r.net_force, controller::kPaperColumns.net_force_of(said));
      EXPECT_EQ(r.leds, expected[i].leds) << "robot " << i << " tick " << t;
    }
  }
  // The LEDs' column: empty for robots whose LEDs are all off, one #rrggbb a LED otherwise.
  std::ifstream csv(dir / "robots.csv");
  std::string header, row0, row1;
  std::getline(csv, header);
  std::getline(csv, row0);
  std::getline(csv, row1);
  EXPECT_EQ(header, std::string(kRobotsCsvHeader) + ",leds");
  EXPECT_EQ(row0.back(), ',') << row0;
  EXPECT_TRUE(row1.ends_with(",#0000ff #000000 #ffff10")) << row1;
  const auto events = read_events_jsonl((dir / "events.jsonl").string());
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0]["tick"], 12);
  EXPECT_EQ(events[0]["kind"], "state");
  EXPECT_EQ(events[0]["id"], 3);
  EXPECT_EQ(events[0]["to"], 2);
  EXPECT_EQ(events[1]["components"][1][0], 3);
  fs::remove_all(dir);
}

TEST(Recording, FlushedAsItGoesSoACrashedRunKeepsItsTicks) {
  const auto dir = fresh_dir("flush");
  RecordingWriter writer(dir.string());
  for (Tick t = 0; t < kFlushEveryTicks; ++t) writer.write_rows(t, robots_at(t));
  // Still open: a reader sees every tick written up to the last flush.
  const auto rows = read_robots_csv((dir / "robots.csv").string());
  EXPECT_EQ(rows.size(), kFlushEveryTicks * 4);
  fs::remove_all(dir);
}

TEST(Recording, TruncatedFilesAreReportedWithFileAndLine) {
  const auto dir = fresh_dir("truncated");
  fs::create_directories(dir);
  const auto csv = (dir / "robots.csv").string();
  {
    std::ofstream out(csv);
    out << kRobotsCsvHeader << "\n0,0,1,2,3,1,0,-1,-1,0,0\n1,0,1.5,2";
  }
  try {
    read_robots_csv(csv);
    FAIL() << "a cut-off line must be reported";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("robots.csv:3"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_robots_csv(csv, /*allow_truncated_tail=*/true).size(), 1u);
  {
    std::ofstream out(csv);
    out << kRobotsCsvHeader << "\n0,0,1,2,3,1,0,-1,-1,0,0\n1,0,1.5,2,x,1,0,-1,-1,0,0\n";
  }
  EXPECT_THROW(read_robots_csv(csv), InputError);
  const auto jsonl = (dir / "events.jsonl").string();
  {
    std::ofstream out(jsonl);
    out << R"({"tick":1,"kind":"death","id":2})"
        << "\n"
        << R"({"tick":2,"kind":)"
        << "\n";
  }
  try {
    read_events_jsonl(jsonl);
    FAIL() << "a broken event must be reported";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
  }
  fs::remove_all(dir);
}

// A recording older than the `leds` column (with a behaviour's telemetry column after the fixed ones) reads
// with every LED off; a bad `leds` field is named with its line.
TEST(Recording, RobotsCsvWithoutTheLedsColumnStillReads) {
  const auto dir = fresh_dir("no-leds");
  fs::create_directories(dir);
  const auto csv = (dir / "robots.csv").string();
  {
    std::ofstream out(csv);
    out << kRobotsCsvHeader << ",neighbours\n0,0,1,2,3,1,0,-1,-1,0,0,\n1,0,1.5,2,3,1,4,2,-1,1,0.5,3\n";
  }
  const auto rows = read_robots_csv(csv);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].pose.x, 1.5);
  EXPECT_EQ(rows[1].state, 4);
  EXPECT_EQ(rows[1].net_force, 0.5);
  for (const auto& r : rows) EXPECT_EQ(r.leds, (std::array<Rgb, kLedCount>{}));
  {
    std::ofstream out(csv);
    out << kRobotsCsvHeader << ",leds,neighbours\n0,0,1,2,3,1,0,-1,-1,0,0,#FF8000 #000000 #000001,2\n"
        << "1,0,1,2,3,1,0,-1,-1,0,0,#ff8000,2\n";
  }
  try {
    read_robots_csv(csv);
    FAIL() << "a bad leds field must be reported";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("bad leds '#ff8000'"), std::string::npos) << e.what();
  }
  {
    std::ofstream out(csv);
    out << kRobotsCsvHeader << ",leds,neighbours\n0,0,1,2,3,1,0,-1,-1,0,0,#FF8000 #000000 #000001,2\n";
  }
  const auto upper = read_robots_csv(csv);
  ASSERT_EQ(upper.size(), 1u);
  EXPECT_EQ(upper[0].leds, (std::array<Rgb, kLedCount>{Rgb{255, 128, 0}, Rgb{}, Rgb{0, 0, 1}}));
  fs::remove_all(dir);
}

Scenario small_scenario() {
  Scenario s;
  s.source = "scenarios/test.yaml";
  s.robots = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.obstacles.push_back({Obstacle::Kind::Box, "wall", {3, 1}, 0.5, {1.0, 0.2}, 0.0});
  s.obstacles.push_back({Obstacle::Kind::Cylinder, "post", {6, -1}, 0.0, {}, 0.3});
  s.mission.shape = ShapeMatrix{2, 2, {0, 1, -1, 2}};
  s.mission.goal = {10, 0.5};
  s.kills.push_back({1, 50});
  return s;
}

TEST(Recording, WorldJsonHasTheDocumentedFields) {
  const auto j = describe_world(small_scenario(), "in-process");
  for (const char* key : {"format", "version", "scenario", "seed", "mode", "tick_rate", "robots", "arena",
                          "obstacles", "goal", "grid_spacing", "comm_range", "shape", "robot_radius"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["format"], "swarmform-recording");
  EXPECT_EQ(j["robots"], 3);
  EXPECT_EQ(j["arena"]["centre"][0], 4.0);
  EXPECT_EQ(j["obstacles"][0]["kind"], "box");
  EXPECT_EQ(j["obstacles"][0]["half_extents"][1], 0.2);
  EXPECT_EQ(j["obstacles"][1]["kind"], "cylinder");
  EXPECT_EQ(j["obstacles"][1]["radius"], 0.3);
  EXPECT_EQ(j["goal"]["y"], 0.5);
  EXPECT_EQ(j["shape"]["cells"].size(), 4u);
  // No optional sensors' world: a plain white floor, no lights, no battery.
  EXPECT_EQ(j["floor"]["grey"], 1.0);
  EXPECT_TRUE(j["floor"]["colour"].is_null());
  EXPECT_TRUE(j["floor"]["image"].is_null());
  EXPECT_TRUE(j["floor"]["regions"].empty());
  EXPECT_TRUE(j["lights"].empty());
  EXPECT_TRUE(j["battery"].is_null());
}

// The floor (base, regions in painting order, each with its colour when the scenario gave one), the lights
// and the battery, as the scenario said them, for the pictures.
TEST(Recording, WorldJsonCarriesTheFloorTheLightsAndTheBattery) {
  Scenario s = small_scenario();
  s.floor.grey = 0.5;
  s.floor.regions.push_back({FloorRegion::Kind::Circle, {2.0, -1.0}, 0.5, {}, 0.0, 0.0, std::nullopt});
  s.floor.regions.push_back(
      {FloorRegion::Kind::Rectangle, {-2.0, 1.0}, 0.0, {0.5, 2.0}, 0.25, 0.299, Rgb{255, 0, 10}});
  s.lights.push_back({{2.6, 0.3}, 0.3, 2.5});
  s.battery = BatterySpec{100.0, 0.1, 20.0, 0.75};
  const auto j = describe_world(s, "in-process");
  const auto& f = j["floor"];
  EXPECT_EQ(f["grey"], 0.5);
  EXPECT_TRUE(f["image"].is_null());
  ASSERT_EQ(f["regions"].size(), 2u);
  EXPECT_EQ(f["regions"][0]["kind"], "circle");
  EXPECT_EQ(f["regions"][0]["centre"][0], 2.0);
  EXPECT_EQ(f["regions"][0]["radius"], 0.5);
  EXPECT_EQ(f["regions"][0]["grey"], 0.0);
  EXPECT_TRUE(f["regions"][0]["colour"].is_null());
  EXPECT_EQ(f["regions"][1]["kind"], "rectangle");
  EXPECT_EQ(f["regions"][1]["half_extents"][1], 2.0);
  EXPECT_EQ(f["regions"][1]["yaw"], 0.25);
  EXPECT_EQ(f["regions"][1]["colour"], "#ff000a");
  ASSERT_EQ(j["lights"].size(), 1u);
  EXPECT_EQ(j["lights"][0]["position"][0], 2.6);
  EXPECT_EQ(j["lights"][0]["height"], 0.3);
  EXPECT_EQ(j["lights"][0]["intensity"], 2.5);
  EXPECT_EQ(j["battery"]["capacity"], 100.0);
  EXPECT_EQ(j["battery"]["start"], 0.75);
}

// A lockstep run's summary inputs: `ticks` ticks in `wall_seconds`, the rest pointing at the caller's
// objects.
SummaryInputs lockstep_inputs(const Scenario& s, const std::vector<RobotTruth>& robots, const Metrics& m,
                              Tick ticks, double wall_seconds) {
  SummaryInputs in;
  in.scenario = &s;
  in.mode = "lockstep";
  in.ticks = ticks;
  in.wall_seconds = wall_seconds;
  in.robots = &robots;
  in.metrics = &m;
  return in;
}

TEST(Recording, SummaryHasEveryKeyNullWhereNotReached) {
  const Scenario s = small_scenario();
  const auto robots = robots_at(3);
  Metrics m;
  m.deaths.push_back({2, 7});
  SummaryInputs in = lockstep_inputs(s, robots, m, 100, 2.0);
  in.trajectory_sha256 = std::string(64, 'a');
  EXPECT_EQ(make_summary(in)["outcome"], "none");             // no experiment's verdict: nothing judged
  EXPECT_FALSE(make_summary(in).contains("formation_tick"));  // the world measures no shape of its own
  // The paper's experiment's fields (behaviour/shape_metrics.hpp summary_fields), as ExperimentRunner
  // converts them.
  ExperimentVerdict verdict;
  verdict.outcome = "not_formed";
  verdict.success = false;
  verdict.fields = {{"formation_tick", 40},
                    {"shape_error_at_formation", 0.05},
                    {"motion_start_tick", nullptr},
                    {"motion_ticks_minimum", nullptr},
                    {"goal_tick", nullptr},
                    {"shape_error_at_goal", nullptr},
                    {"peak_distortion", nullptr},
                    {"mean_distortion", nullptr},
                    {"path_length", 0.0},
                    {"arrived", 0},
                    {"stuck_robots", nlohmann::ordered_json::array()},
                    {"stuck_robot_count", 0}};
  verdict.series = {{"distortion", nlohmann::ordered_json::array()}};
  in.verdict = &verdict;
  const auto j = make_summary(in);
  for (const char* key : {"robots",
                          "seed",
                          "mode",
                          "ticks",
                          "wall_seconds",
                          "ticks_per_second",
                          "alive_at_end",
                          "deaths",
                          "rejoins",
                          "collisions_robot_robot",
                          "collisions_robot_obstacle",
                          "formation_tick",
                          "shape_error_at_formation",
                          "motion_start_tick",
                          "goal_tick",
                          "shape_error_at_goal",
                          "peak_distortion",
                          "mean_distortion",
                          "leader_changes",
                          "path_length",
                          "arrived",
                          "outcome",
                          "success",
                          "behaviour_metrics",
                          "stuck_robots",
                          "stuck_robot_count",
                          "motion_ticks_minimum",
                          "trajectory_sha256"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["ticks_per_second"], 50.0);
  EXPECT_EQ(j["steady_from_tick"], 0);
  EXPECT_TRUE(j["steady_ticks_per_second"].is_null());  // no steady window measured
  EXPECT_EQ(j["alive_at_end"], 3);
  EXPECT_EQ(j["formation_tick"], 40);
  EXPECT_TRUE(j["goal_tick"].is_null());
  EXPECT_TRUE(j["peak_distortion"].is_null());
  EXPECT_EQ(j["deaths"][0]["id"], 2);
  EXPECT_EQ(j["deaths"][0]["tick"], 7);
  EXPECT_EQ(j["outcome"], "not_formed");
  EXPECT_TRUE(j["motion_ticks_minimum"].is_null());
  EXPECT_EQ(j["stuck_robot_count"], 0);
  verdict.fields["stuck_robots"] = {1, 4};
  verdict.fields["stuck_robot_count"] = 2;
  verdict.outcome = "formed_not_arrived";
  const auto k = make_summary(in);
  EXPECT_EQ(k["stuck_robots"], nlohmann::ordered_json::parse("[1, 4]"));
  EXPECT_EQ(k["stuck_robot_count"], 2);
  EXPECT_EQ(k["outcome"], "formed_not_arrived");

  // The text form keeps the long distortion series on one line and parses back to the same document.
  verdict.series["distortion"] = nlohmann::ordered_json::parse("[[40, 0.05], [41, 0.0625]]");
  const auto with_series = make_summary(in);
  const std::string text = summary_text(with_series);
  EXPECT_EQ(nlohmann::ordered_json::parse(text), with_series);
  EXPECT_NE(text.find("\"distortion\": [[40,0.05],[41,0.0625]]"), std::string::npos) << text;
}

// A disk that fills during the run still takes its outcome: the writer allocates summary.json's room when it
// makes the run directory and writes the summary into it; on a full disk, when the whole does not fit, the
// summary cut to its outcome does, whatever the run (here far larger than the room: 5,000 deaths, a
// distortion series of 20,000 ticks).
TEST(Recording, SummaryRoomIsReservedAtTheStartAndTheOutcomeAloneAlwaysFitsIt) {
  const auto dir = fresh_dir("room");
  {
    RecordingWriter writer(dir.string());
    struct stat st {};
    ASSERT_EQ(::stat((dir / "summary.json.tmp").c_str(), &st), 0);
    EXPECT_GE(static_cast<std::size_t>(st.st_blocks) * 512, kSummaryRoomBytes);  // allocated, not sparse
    EXPECT_FALSE(writer.write_summary(nlohmann::ordered_json{{"end_reason", "max_ticks"}}));  // not cut
  }
  EXPECT_FALSE(fs::exists(dir / "summary.json.tmp"));
  EXPECT_EQ(nlohmann::ordered_json::parse(std::ifstream(dir / "summary.json"))["end_reason"], "max_ticks");
  fs::remove_all(dir);

  const Scenario s = small_scenario();
  const auto robots = robots_at(3);
  Metrics m;
  for (RobotId i = 0; i < 5000; ++i) m.deaths.push_back({i, 7});
  ExperimentVerdict verdict;
  verdict.outcome = "formed_not_arrived";
  verdict.fields["stuck_robots"] = std::vector<RobotId>(1000, 1);
  auto& series = verdict.series["distortion"] = nlohmann::ordered_json::array();
  for (Tick t = 0; t < 20000; ++t) series.push_back({t, 0.0625});
  SummaryInputs in = lockstep_inputs(s, robots, m, 20000, 2.0);
  in.verdict = &verdict;
  in.trajectory_sha256 = std::string(64, 'a');
  in.end_reason = "disk_full";
  const auto whole = make_summary(in);
  ASSERT_GT(summary_text(whole).size(), kSummaryRoomBytes);
  const auto outcome = summary_outcome(whole);
  EXPECT_LT(summary_text(outcome).size(), kSummaryRoomBytes / 4);
  EXPECT_FALSE(outcome.contains("distortion"));
  for (const char* key :
       {"end_reason", "ticks", "outcome", "alive_at_end", "trajectory_sha256", "provenance"}) {
    EXPECT_EQ(outcome[key], whole[key]) << key;
  }
  EXPECT_EQ(outcome["deaths"].size(), kOutcomeListEntries);
  EXPECT_EQ(outcome["deaths"][3], whole["deaths"][3]);
  EXPECT_EQ(outcome["summary_cut"]["lists_cut_to_16_entries"]["deaths"], 5000);
  EXPECT_EQ(outcome["summary_cut"]["lists_cut_to_16_entries"]["stuck_robots"], 1000);
  EXPECT_EQ(outcome["summary_cut"]["left_out"][0], "distortion");
}

TEST(Recording, SummarySteadyRateLeavesTheWarmupTicksOut) {
  const Scenario s = small_scenario();
  const auto robots = robots_at(3);
  const Metrics m;
  SummaryInputs in = lockstep_inputs(s, robots, m, 700, 3.0);
  in.steady = SteadyWindow{100, 2.4};  // 600 ticks in the last 2.4 s
  auto j = make_summary(in);
  EXPECT_EQ(j["steady_from_tick"], 100);
  EXPECT_DOUBLE_EQ(j["steady_ticks_per_second"].get<double>(), 250.0);
  EXPECT_DOUBLE_EQ(j["ticks_per_second"].get<double>(), 700 / 3.0);  // the whole run's, unchanged

  in.ticks = 100;  // the run ended at the warm-up's last tick: nothing to measure
  EXPECT_TRUE(make_summary(in)["steady_ticks_per_second"].is_null());
  in.ticks = 700;
  in.steady.seconds = 0.0;  // never reached
  EXPECT_TRUE(make_summary(in)["steady_ticks_per_second"].is_null());
}

TEST(Sha256, StandardVectorsAndIncrementalUse) {
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  Sha256 sha;
  sha.update("a", 1);
  const auto partial = sha.hex_digest();  // reading does not end the stream
  sha.update("bc", 2);
  EXPECT_EQ(sha.hex_digest(), sha256_hex("abc"));
  EXPECT_NE(partial, sha.hex_digest());
}

TEST(Sha256, DoublesAreHashedByTheirBitPattern) {
  Sha256 a;
  Sha256 b;
  Sha256 c;
  a.update_double(0.0);
  b.update_double(0.0);
  c.update_double(-0.0);  // equal as numbers, not as bits
  EXPECT_EQ(a.hex_digest(), b.hex_digest());
  EXPECT_NE(a.hex_digest(), c.hex_digest());
  Sha256 d;
  d.update_double(std::nextafter(0.0, 1.0));
  EXPECT_NE(a.hex_digest(), d.hex_digest());
}

}  // namespace
}  // namespace swarmform::world
