// The Khepera IV's world in the recording, through the in-process harness (the same RunSession and recorder
// as the DDS world): the LEDs a controller sets reach robots.csv at the tick they were lit and the reader
// gives them back; readings.csv holds the optional sensors' readings each robot was given; world.json
// carries the sensor scenarios' floor, lights and battery as their files say.
#include <unistd.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <sstream>

#include <gtest/gtest.h>
#include <png.h>

#include "behaviour/registry.hpp"
#include "common/sensor_readings.hpp"
#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/recording_reader.hpp"

namespace swarmform::harness {
namespace {

namespace fs = std::filesystem;

// A fresh run directory under the temporary folder, named for `name` and this process.
fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("swarmform-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

// Runs `s` to its end in-process into `dir` (every `record_every`-th tick recorded).
void run_into(const world::Scenario& s, const fs::path& dir, Tick record_every = 1) {
  Harness h(s, {dir.string(), 0.0, record_every});
  h.run();
  h.finish(1.0);
}

// What a blinker robot lights when it sees tick `tick`: every fourth tick nothing, else LED 0 by its id and
// the tick, LED 1 off, LED 2 blue.
std::array<Rgb, kLedCount> blink(RobotId self, Tick tick) {
  if (tick % 4 == 3) return {};
  return {Rgb{static_cast<std::uint8_t>(20 * self), static_cast<std::uint8_t>(tick % 256), 0}, Rgb{},
          Rgb{0, 0, 255}};
}

class Blinker final : public controller::Controller {
 public:
  void init(const Mission&, RobotId self) override { self_ = self; }
  Command step(const Perception& p) override {
    Command c;
    c.left_speed = c.right_speed = 0.02;
    c.leds = blink(self_, p.tick);
    return c;
  }
  void reset() override {}

 private:
  RobotId self_ = 0;
};

std::unique_ptr<controller::Controller> make_blinker() {
  return std::make_unique<Blinker>();
}

const behaviour::Descriptor kBlinker{
    .name = "blinker",
    .summary = "lights its LEDs by tick",
    .params = {},
    .states = {},
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make_blinker,
    .sensors = 0,
    .experiment = {},
};

TEST(KheperaRecording, EveryRobotsLedsAreRecordedAtTheTickTheyWereLitAndReadBack) {
  behaviour::Registry registry;
  registry.add(kBlinker);
  const world::Scenario s = world::parse_scenario_text(R"(
behaviour: blinker
arena: {centre: [0.0, 0.0], width: 10.0, height: 10.0, walls: true}
robots: {count: 5, region: {centre: [0.0, 0.0], width: 4.0, height: 4.0}}
seed: 4
max_ticks: 30
)",
                                                       "<leds_recording_test>", {}, registry);
  const fs::path dir = fresh_dir("leds-test");
  run_into(s, dir);
  const auto rows = world::read_robots_csv((dir / "robots.csv").string());
  ASSERT_EQ(rows.size(), 31u * 5u);
  std::size_t lit = 0;
  for (const auto& r : rows) {
    // Row t is the state after the world's t-th step, which applied the commands of the robots' tick t-1.
    const std::array<Rgb, kLedCount> expected =
        r.tick == 0 ? std::array<Rgb, kLedCount>{} : blink(r.id, r.tick - 1);
    EXPECT_EQ(r.leds, expected) << "robot " << r.id << " tick " << r.tick;
    lit += r.leds[2] == Rgb{0, 0, 255} ? 1 : 0;
  }
  EXPECT_EQ(lit, 23u * 5u);  // ticks 1..30 but those after a dark tick 3, 7, ..., 27
  // On disk: an unlit robot's field is empty.
  std::ifstream csv(dir / "robots.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "tick,id,x,y,theta,alive,state,label,parent,leader,net_force,leds");
  std::getline(csv, line);
  EXPECT_EQ(line.back(), ',') << line;
  fs::remove_all(dir);
}

// What each Sensing robot was given, by (id, tick): its optional sensors' readings in the layout of
// common/sensor_readings.hpp. Controllers run on the harness's pool: hence the lock.
std::mutex g_sensed_mutex;
std::map<std::pair<RobotId, Tick>, std::vector<double>> g_sensed;

class Sensing final : public controller::Controller {
 public:
  void init(const Mission&, RobotId self) override { self_ = self; }
  Command step(const Perception& p) override {
    std::uint32_t equipped = 0;
    std::vector<double> values;
    pack_sensor_readings(p, equipped, values);
    {
      std::lock_guard<std::mutex> lock(g_sensed_mutex);
      g_sensed[{self_, p.tick}] = values;
    }
    Command c;
    c.left_speed = 0.05;
    c.right_speed = 0.02 + 0.01 * self_;  // turning circles of different radii: the readings change
    return c;
  }
  void reset() override {}

 private:
  RobotId self_ = 0;
};

std::unique_ptr<controller::Controller> make_sensing() {
  return std::make_unique<Sensing>();
}

constexpr std::uint32_t kEverySensor =
    behaviour::kProximity | behaviour::kLight | behaviour::kGround | behaviour::kLidar | behaviour::kBattery;

const behaviour::Descriptor kSensing{
    .name = "sensing",
    .summary = "drives in circles reading every optional sensor",
    .params = {},
    .states = {},
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make_sensing,
    .sensors = kEverySensor,
    .experiment = {},
};

std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string f; std::getline(in, f, ',');) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

TEST(KheperaRecording, ReadingsCsvHoldsTheReadingsEachRobotWasGivenAtEveryRecordedTick) {
  behaviour::Registry registry;
  registry.add(kSensing);
  const world::Scenario s = world::parse_scenario_text(R"(
behaviour: sensing
arena: {centre: [0.0, 0.0], width: 4.0, height: 4.0, walls: true}
obstacles:
  - {type: cylinder, name: post, centre: [0.8, 0.0], radius: 0.2}
robots: {count: 4, region: {centre: [-0.5, 0.0], width: 1.5, height: 1.5}}
lights:
  - {position: [1.5, 1.0], height: 0.3, intensity: 2.0}
battery: {capacity: 100.0, idle: 0.1, moving: 20.0}
lidar: {rays: 16, fov: 3.6651914291880923, max_range: 2.0}
noise: {proximity: 0.02, light: 0.01, ground: 0.02, lidar: 0.01}
kills:
  - {id: 2, tick: 7}
seed: 3
max_ticks: 20
)",
                                                       "<readings_recording_test>", {}, registry);
  {
    std::lock_guard<std::mutex> lock(g_sensed_mutex);
    g_sensed.clear();
  }
  const fs::path dir = fresh_dir("readings-test");
  run_into(s, dir, /*record_every=*/2);
  std::ifstream csv(dir / "readings.csv");
  ASSERT_TRUE(csv) << "no readings.csv";
  std::string line;
  std::getline(csv, line);
  std::string header = "tick,id";
  for (const std::string& c : sensor_reading_columns(kEverySensor)) header += "," + c;
  EXPECT_EQ(line, header);
  const std::size_t values = sensor_readings_count(kEverySensor);
  ASSERT_EQ(values, 8u + 8u + 4u + 3u + 1u);
  std::size_t rows = 0, compared = 0, dead = 0;
  Tick previous_tick = 0;
  while (std::getline(csv, line)) {
    const std::vector<std::string> f = fields_of(line);
    ASSERT_EQ(f.size(), 2 + values) << line;
    const Tick tick = std::stoull(f[0]);
    const auto id = static_cast<RobotId>(std::stoul(f[1]));
    EXPECT_EQ(tick % 2, 0u) << line;  // --record-every 2, as robots.csv
    EXPECT_EQ(id, rows % 4) << line;  // every robot, in id order
    EXPECT_GE(tick, previous_tick);
    previous_tick = tick;
    ++rows;
    if (id == 2 && tick > 7) {  // killed at the start of tick 7: its rows from tick 8 on are empty
      for (std::size_t k = 2; k < f.size(); ++k) EXPECT_EQ(f[k], "") << line;
      ++dead;
      continue;
    }
    std::vector<double> recorded(values);
    for (std::size_t k = 0; k < values; ++k) {
      const std::string& v = f[2 + k];
      const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), recorded[k]);
      ASSERT_TRUE(ec == std::errc() && end == v.data() + v.size()) << "'" << v << "' in " << line;
    }
    EXPECT_EQ(recorded[20], 16.0) << line;  // the lidar's ray count
    std::lock_guard<std::mutex> lock(g_sensed_mutex);
    const auto given = g_sensed.find({id, tick});
    if (given == g_sensed.end()) {
      EXPECT_EQ(tick, 20u) << line;  // the last row: no controller stepped on it
      continue;
    }
    // Bit for bit what the controller was given at that tick (shortest round-trip text).
    EXPECT_EQ(recorded, given->second) << line;
    ++compared;
  }
  EXPECT_EQ(rows, 11u * 4u);                      // ticks 0, 2, ..., 20
  EXPECT_EQ(dead, 7u);                            // robot 2 at ticks 8..20
  EXPECT_EQ(compared, 10u * 4u - 6u);             // ticks 0..18, robot 2's from tick 8 on left out
  EXPECT_LT(g_sensed.rbegin()->second[23], 1.0);  // a battery that drains (robot 3, tick 19)
  fs::remove_all(dir);
}

// A behaviour that declares no optional sensor records no readings.csv.
TEST(KheperaRecording, NoSensorsNoReadingsCsv) {
  behaviour::Registry registry;
  registry.add(kBlinker);
  const world::Scenario s = world::parse_scenario_text(R"(
behaviour: blinker
arena: {centre: [0.0, 0.0], width: 10.0, height: 10.0, walls: true}
robots: {count: 2, region: {centre: [0.0, 0.0], width: 4.0, height: 4.0}}
max_ticks: 3
)",
                                                       "<no_readings_test>", {}, registry);
  const fs::path dir = fresh_dir("no-readings");
  run_into(s, dir);
  EXPECT_TRUE(fs::exists(dir / "robots.csv"));
  EXPECT_FALSE(fs::exists(dir / "readings.csv"));
  fs::remove_all(dir);
}

// world.json of a short run of scenarios/sensors/NAME.yaml.
nlohmann::json world_json_of(const std::string& name) {
  const world::Scenario s =
      world::load_scenario(std::string(SWARMFORM_REPO_DIR) + "/scenarios/sensors/" + name + ".yaml", {},
                           swarmform::controller::builtin_registry());
  const fs::path dir = fresh_dir("khepera-" + name);
  {
    Harness h(s, {dir.string()});
    h.step();
    h.finish(1.0);
  }
  nlohmann::json j = world::read_json_file((dir / "world.json").string());
  fs::remove_all(dir);
  return j;
}

TEST(KheperaRecording, WorldJsonCarriesTheFloorOfIrClutter) {
  const nlohmann::json j = world_json_of("ir_clutter");
  const auto& f = j["floor"];
  EXPECT_EQ(f["grey"], 0.9);
  EXPECT_TRUE(f["colour"].is_null());
  EXPECT_TRUE(f["image"].is_null());
  ASSERT_EQ(f["regions"].size(), 3u);
  EXPECT_EQ(f["regions"][0]["kind"], "circle");
  EXPECT_EQ(f["regions"][0]["radius"], 0.5);
  EXPECT_EQ(f["regions"][0]["grey"], 0.0);
  EXPECT_EQ(f["regions"][1]["kind"], "rectangle");
  EXPECT_EQ(f["regions"][1]["centre"][1], 1.4);
  EXPECT_EQ(f["regions"][1]["half_extents"][0], 2.0);
  EXPECT_EQ(f["regions"][1]["half_extents"][1], 0.2);
  EXPECT_EQ(f["regions"][2]["yaw"], 0.3);
  EXPECT_EQ(f["regions"][2]["colour"], "#ff0000");
  EXPECT_NEAR(f["regions"][2]["grey"].get<double>(), 0.299, 1e-12);
  EXPECT_TRUE(j["lights"].empty());
  EXPECT_TRUE(j["battery"].is_null());
}

TEST(KheperaRecording, WorldJsonCarriesTheLightAndTheBatteryOfPhototaxis) {
  const nlohmann::json j = world_json_of("phototaxis");
  ASSERT_EQ(j["lights"].size(), 1u);
  EXPECT_EQ(j["lights"][0]["position"], nlohmann::json::array({2.6, 0.3}));
  EXPECT_EQ(j["lights"][0]["height"], 0.3);
  EXPECT_EQ(j["lights"][0]["intensity"], 2.5);
  EXPECT_EQ(j["battery"],
            nlohmann::json({{"capacity", 100.0}, {"idle", 0.1}, {"moving", 20.0}, {"start", 1.0}}));
  EXPECT_TRUE(j["floor"]["regions"].empty());
  EXPECT_EQ(j["floor"]["grey"], 1.0);
}

TEST(KheperaRecording, TheFloorImageIsCopiedIntoTheRunFolderAndWorldJsonNamesTheCopy) {
  const fs::path dir = fresh_dir("floor-copy");
  fs::create_directories(dir / "scenario");
  std::vector<std::uint8_t> rgb(3u * 4u * 2u, 255);
  rgb[0] = 0;  // one red-less pixel: not a plain white file
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 4;
  image.height = 2;
  image.format = PNG_FORMAT_RGB;
  const fs::path source = dir / "scenario" / "my_floor.png";
  ASSERT_NE(png_image_write_to_file(&image, source.c_str(), 0, rgb.data(), 0, nullptr), 0);
  const world::Scenario s = world::parse_scenario_text(R"(
behaviour: random_walk
arena: {centre: [0.0, 0.0], width: 4.0, height: 2.0, walls: true}
robots: {count: 2, region: {centre: [0.0, 0.0], width: 1.0, height: 1.0}}
floor: {image: my_floor.png}
max_ticks: 5
)",
                                                       (dir / "scenario" / "s.yaml").string(), {},
                                                       swarmform::controller::builtin_registry());
  const fs::path run = dir / "run";
  {
    Harness h(s, {run.string()});
    h.step();
    h.finish(1.0);
  }
  const nlohmann::json j = world::read_json_file((run / "world.json").string());
  EXPECT_EQ(j["floor"]["image"]["file"], "floor.png");
  EXPECT_EQ(j["floor"]["image"]["source"], fs::absolute(source).lexically_normal().string());
  EXPECT_EQ(j["floor"]["image"]["width"], 4);
  auto bytes = [](const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  EXPECT_EQ(bytes(run / "floor.png"), bytes(source));
  EXPECT_FALSE(fs::exists(run / "floor.png.tmp"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace swarmform::harness
