// The Khepera IV's world in the recording, through the in-process harness (the same RunSession and recorder
// as the DDS world): the LEDs a controller sets reach robots.csv at the tick they were lit and the reader
// gives them back; world.json carries the sensor scenarios' floor, lights and battery as their files say.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <png.h>

#include "behaviour/registry.hpp"
#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/recording_reader.hpp"

namespace swarmform::harness {
namespace {

namespace fs = std::filesystem;

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
  const fs::path dir = fs::temp_directory_path() / ("swarmform-leds-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  {
    Harness h(s, {dir.string()});
    h.run();
    h.finish(1.0);
  }
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

// world.json of a short run of scenarios/sensors/NAME.yaml.
nlohmann::json world_json_of(const std::string& name) {
  const world::Scenario s =
      world::load_scenario(std::string(SWARMFORM_REPO_DIR) + "/scenarios/sensors/" + name + ".yaml", {},
                           swarmform::controller::builtin_registry());
  const fs::path dir =
      fs::temp_directory_path() / ("swarmform-khepera-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
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
  const fs::path dir = fs::temp_directory_path() / ("swarmform-floor-copy-" + std::to_string(::getpid()));
  fs::remove_all(dir);
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
