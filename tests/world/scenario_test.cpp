// The scenario loader: every file in scenarios/ loads; bad files are refused with file:line and what.
#include "world_server/world/scenario.hpp"
#include "robot_agent/controller/builtins.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

#include "common/input_error.hpp"
#include "tests/world/scenario_text.hpp"
#include "world_server/world/placement.hpp"

namespace swarmform::world {
namespace {

using scenario_text::expect_rejected;
using scenario_text::kOrigin;
using scenario_text::kRepo;
using scenario_text::parse;

bool connected(const std::vector<Pose2D>& poses, double range) {
  std::vector<char> seen(poses.size(), 0);
  std::vector<std::size_t> stack{0};
  seen[0] = 1;
  std::size_t count = 1;
  while (!stack.empty()) {
    const std::size_t i = stack.back();
    stack.pop_back();
    for (std::size_t j = 0; j < poses.size(); ++j) {
      if (!seen[j] && std::hypot(poses[i].x - poses[j].x, poses[i].y - poses[j].y) <= range) {
        seen[j] = 1;
        ++count;
        stack.push_back(j);
      }
    }
  }
  return count == poses.size();
}

TEST(Scenario, EveryFileInScenariosLoads) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kRepo + "/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    EXPECT_NO_THROW({
      const Scenario s = load_scenario(entry.path().string(), {}, swarmform::controller::builtin_registry());
      EXPECT_GT(s.robots.size(), 0u);
      EXPECT_GT(s.mission.shape.label_count(), 0);
    }) << entry.path();
  }
  EXPECT_GE(files, 3);
}

// A square block shape of side x side labels, written to a temporary file; returns its path.
std::string block_shape_file(int side) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("swarmform-block-" + std::to_string(side) + "-" + std::to_string(::getpid()) + ".txt");
  std::ofstream out(path);
  for (int r = 0; r < side; ++r) {
    for (int c = 0; c < side; ++c) out << (c > 0 ? " " : "") << r * side + c;
    out << "\n";
  }
  return path.string();
}

// A 10 x 10 block with the paper's scenario was accepted, and 62 robots pushed against the walls.
TEST(Scenario, RefusesAShapeThatCannotFitInsideTheWalls) {
  const std::string block = block_shape_file(10);
  ScenarioOverrides ov;
  ov.shape_file = block;
  try {
    load_scenario(kRepo + "/scenarios/paper.yaml", ov, swarmform::controller::builtin_registry());
    ADD_FAILURE() << "a 10 x 10 block was accepted in the paper's 20 x 12 m arena";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kRepo + "/scenarios/paper.yaml");
    EXPECT_NE(std::string(e.what()).find("shape: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot fit inside the walls"), std::string::npos) << e.what();
  }
  // The shape named in the file: the error points at its line.
  expect_rejected("arena: {centre: [4, 0], width: 20, height: 12, walls: true}\nshape: " + block + "\n", 2,
                  "shape: swarmform-block-10-");
  // In a 60 m arena it fits; without walls nothing is checked; a random walk forms no shape.
  EXPECT_NO_THROW(
      parse("arena: {centre: [0, 0], width: 60, height: 60, walls: true}\nshape: " + block + "\n"));
  EXPECT_NO_THROW(
      parse("arena: {centre: [4, 0], width: 20, height: 12, walls: false}\nshape: " + block + "\n"));
  EXPECT_NO_THROW(parse("behaviour: random_walk\nshape: " + block + "\n"));
  // Label 0 is where the robot nearest the origin starts. The triangle (3 rows, 5 columns, apex up) from a
  // robot 1.5 m under the north wall fits; from one 1 m from the west wall it does not (labels 4..8 reach
  // 2 m to the left of label 0).
  EXPECT_NO_THROW(
      parse("arena: {centre: [0, 0], width: 20, height: 12, walls: true}\nshape: triangle.txt\n"
            "robots:\n  poses:\n    - [0, 4.5]\n    - [0.5, 4.5]\n"));
  expect_rejected(
      "arena: {centre: [0, 0], width: 20, height: 12, walls: true}\nshape: triangle.txt\n"
      "robots:\n  poses:\n    - [-9.5, 0]\n    - [-9, 0]\n",
      2, "label 0 at (-9, 0), where the robot nearest the origin starts");
  std::filesystem::remove(block);
}

// `--param shape_heading=...` (swarm_inprocess, swarm sweep) was set after the loader's fit check,
// so a heading that turns the shape into a wall was accepted. The override is set before every check now.
TEST(Scenario, AParamOverrideIsSetBeforeTheShapeFitCheck) {
  // The triangle (apex up) from a robot 1.5 m under the north wall fits; turned upside down (heading -pi/2:
  // its rows run along +y) its last row is 1 m beyond that wall.
  const std::string text =
      "arena: {centre: [0, 0], width: 20, height: 12, walls: true}\nshape: triangle.txt\n"
      "robots:\n  poses:\n    - [0, 4.5]\n    - [0.5, 4.5]\n";
  ScenarioOverrides up;
  up.params.push_back({"shape_heading=1.5707963", "shape_heading", 1.5707963});
  EXPECT_NO_THROW(parse(text, up));
  ScenarioOverrides down;
  down.params.push_back({"shape_heading=-1.5707963", "shape_heading", -1.5707963});
  try {
    parse(text, down);
    ADD_FAILURE() << "an upside-down triangle 1.5 m under the north wall was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shape_heading -1.5708)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot fit inside the walls"), std::string::npos) << e.what();
  }
  // The value reaches the mission; an unknown name or a value out of bounds is the command line's error.
  ScenarioOverrides k;
  k.params.push_back({"k_goal=2", "k_goal", 2.0});
  EXPECT_EQ(parse(text, k).mission.params.at("k_goal"), 2.0);
  for (const auto& [text_given, name, value, says] :
       std::vector<std::tuple<std::string, std::string, double, std::string>>{
           {"k_wobble=1", "k_wobble", 1.0, "--param k_wobble=1: behaviour 'paper' parameter 'k_wobble'"},
           {"shape_heading=7", "shape_heading", 7.0,
            "--param shape_heading=7: behaviour 'paper' parameter"}}) {
    ScenarioOverrides bad;
    bad.params.push_back({text_given, name, value});
    try {
      parse(text, bad);
      ADD_FAILURE() << text_given << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "command line");
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

TEST(Scenario, EveryShippedShapeFitsEveryShippedScenario) {
  for (const auto& scenario : std::filesystem::directory_iterator(kRepo + "/scenarios")) {
    if (scenario.path().extension() != ".yaml") continue;
    for (const auto& shape : std::filesystem::directory_iterator(kRepo + "/shapes")) {
      if (shape.path().extension() != ".txt") continue;
      ScenarioOverrides ov;
      ov.shape_file = shape.path().string();
      EXPECT_NO_THROW(load_scenario(scenario.path().string(), ov, swarmform::controller::builtin_registry()))
          << scenario.path() << " " << shape.path();
    }
  }
}

TEST(Scenario, TheFullExampleOfTheFormatDocParses) {
  std::ifstream in(kRepo + "/docs/scenario-format.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string md = text.str();
  const auto begin = md.find("```yaml\n");
  ASSERT_NE(begin, std::string::npos);
  const auto end = md.find("```", begin + 8);
  const Scenario s = parse(md.substr(begin + 8, end - begin - 8));
  EXPECT_EQ(s.robots.size(), 9u);
  EXPECT_EQ(s.obstacles.size(), 2u);
  EXPECT_EQ(s.kills.size(), 1u);
  EXPECT_EQ(s.faults.size(), 4u);  // the Faults example: stall, wheel, loss, range
  EXPECT_EQ(s.mission.params.size(), 2u);
}

TEST(Scenario, PaperScenarioIsThePapersRun) {
  const Scenario s =
      load_scenario(kRepo + "/scenarios/paper.yaml", {}, swarmform::controller::builtin_registry());
  EXPECT_EQ(s.mode, Mode::Lockstep);
  EXPECT_EQ(s.robots.size(), static_cast<std::size_t>(s.mission.shape.label_count()));
  EXPECT_NEAR(std::hypot(s.mission.goal.x, s.mission.goal.y), 10.0, 1.0);
  bool big_box = false, small_post = false;
  for (const Obstacle& o : s.obstacles) {
    if (o.kind == Obstacle::Kind::Box && 2.0 * std::max(o.half_extents.x, o.half_extents.y) > 2.0)
      big_box = true;
    if (o.kind == Obstacle::Kind::Cylinder && o.radius < s.mission.grid_spacing / 2.0) small_post = true;
  }
  EXPECT_TRUE(big_box);
  EXPECT_TRUE(small_post);
}

TEST(Scenario, MinimalFileGetsDefaultsAndAConnectedRandomPlacement) {
  const Scenario s = parse("shape: triangle.txt\n");
  EXPECT_EQ(s.robots.size(), 9u);  // the triangle's labels
  EXPECT_EQ(s.mission.shape.label_count(), 9);
  EXPECT_EQ(s.comm_range, 3.0);
  EXPECT_TRUE(connected(s.robots, kLinkFraction * s.comm_range));
  for (std::size_t i = 0; i < s.robots.size(); ++i) {
    for (std::size_t j = i + 1; j < s.robots.size(); ++j) {
      EXPECT_GE(std::hypot(s.robots[i].x - s.robots[j].x, s.robots[i].y - s.robots[j].y), kMinSeparation);
    }
    EXPECT_LT(std::hypot(s.robots[i].x, s.robots[i].y), 3.0);  // near the origin
  }
}

TEST(Scenario, SeedAndRobotOverridesDecidePlacement) {
  const std::string text = "shape: triangle.txt\nrobots: {count: 20}\nseed: 4\n";
  const Scenario a = parse(text), b = parse(text);
  ASSERT_EQ(a.robots.size(), 20u);
  for (std::size_t i = 0; i < 20; ++i) EXPECT_EQ(a.robots[i].x, b.robots[i].x);
  ScenarioOverrides ov;
  ov.seed = 5;
  ov.robots = 300;
  const Scenario c = parse(text, ov);
  EXPECT_EQ(c.seed, 5u);
  EXPECT_EQ(c.mission.seed, 5u);
  ASSERT_EQ(c.robots.size(), 300u);
  EXPECT_TRUE(connected(c.robots, kLinkFraction * c.comm_range));
  EXPECT_NE(c.robots[0].x, a.robots[0].x);
}

TEST(Scenario, ListedPosesControllerAndEverySection) {
  const Scenario s = parse(R"(shape: ../shapes/square.txt
arena: {centre: [0, 0], width: 10, height: 8, walls: false}
obstacles:
  - {type: box, name: b, centre: [3, 0], size: [1, 2], yaw: 0.5}
  - {type: cylinder, centre: [-3, 1], radius: 0.25}
robots:
  poses:
    - [0, 0, 0]
    - [0.5, 0, 1.57]
    - [1.0, 0]
comm_range: 2.5
noise: {range: 0.01, bearing: 0.02, ultrasonic: 0.03}
packet_loss: 0.1
occlusion: true
mode: realtime
tick_rate: 20
substeps: 5
lockstep_deadline: 1.5
seed: 99
max_ticks: 1000
kills: [{id: 1, tick: 50}]
goal: {x: 4, y: 3, radius: 0.4}
grid_spacing: 1.4
max_speed: 0.2
behaviour: paper
max_message_bytes: 512
controller: {k_o: 2.0, neighbour_timeout: 30}
)");
  EXPECT_EQ(s.robots.size(), 3u);
  EXPECT_DOUBLE_EQ(s.robots[1].theta, 1.57);
  EXPECT_EQ(s.obstacles.size(), 2u);
  EXPECT_DOUBLE_EQ(s.obstacles[0].half_extents.y, 1.0);
  EXPECT_FALSE(s.walls);
  EXPECT_EQ(s.mode, Mode::Realtime);
  EXPECT_EQ(s.substeps, 5);
  EXPECT_TRUE(s.occlusion);
  EXPECT_EQ(s.kills.size(), 1u);
  EXPECT_EQ(s.mission.params.at("k_o"), 2.0);
  EXPECT_EQ(s.mission.behaviour, "paper");
  EXPECT_EQ(s.mission.tick_rate, 20.0);
  EXPECT_EQ(s.mission.comm_range, 2.5);
  EXPECT_EQ(s.mission.max_message_bytes, 512u);
}

TEST(Scenario, RejectsUnknownKeys) {
  expect_rejected("shape: triangle.txt\ncomm_rang: 3\n", 2, "comm_rang: unknown key");
  expect_rejected("shape: triangle.txt\narena:\n  width: 10\n  walls: true\n  colour: red\n", 5,
                  "arena.colour");
  expect_rejected(
      "shape: triangle.txt\nobstacles:\n  - {type: box, centre: [1, 1], size: [1, 1], radius: 2}\n", 3,
      "obstacles[0].radius: unknown key");
}

TEST(Scenario, ProximityNoiseIsReadAndChecked) {
  EXPECT_DOUBLE_EQ(parse("shape: triangle.txt\nnoise: {proximity: 0.1}\n").proximity_noise, 0.1);
  EXPECT_DOUBLE_EQ(parse("shape: triangle.txt\n").proximity_noise, 0.0);
  expect_rejected("shape: triangle.txt\nnoise:\n  proximity: 1.5\n", 3, "noise.proximity");
  expect_rejected("shape: triangle.txt\nnoise:\n  proximity: -0.1\n", 3, "noise.proximity");
}

TEST(Scenario, LightsAndSensorNoiseAreReadAndChecked) {
  const Scenario s = parse(
      "shape: triangle.txt\nlights:\n  - {position: [2, 1], height: 0.5, intensity: 2}\n"
      "noise: {light: 0.1, ground: 0.2}\n");
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_DOUBLE_EQ(s.lights[0].position.y, 1.0);
  EXPECT_DOUBLE_EQ(s.lights[0].height, 0.5);
  EXPECT_DOUBLE_EQ(s.lights[0].intensity, 2.0);
  EXPECT_DOUBLE_EQ(s.light_noise, 0.1);
  EXPECT_DOUBLE_EQ(s.ground_noise, 0.2);
  expect_rejected("shape: triangle.txt\nlights:\n  - {position: [2, 1], height: 0.5}\n", 3,
                  "missing 'intensity'");
  expect_rejected("shape: triangle.txt\nlights:\n  - {position: [2, 1], height: 0.5, intensity: 0}\n", 3,
                  "lights[0].intensity");
  expect_rejected("shape: triangle.txt\nlights:\n  - {position: [2, 1], height: -1, intensity: 1}\n", 3,
                  "lights[0].height");
  expect_rejected("shape: triangle.txt\nlights: {position: [2, 1]}\n", 2, "a list of light sources");
  expect_rejected("shape: triangle.txt\nnoise:\n  light: 2\n", 3, "noise.light");
}

TEST(Scenario, BatteryIsReadAndChecked) {
  const Scenario s =
      parse("shape: triangle.txt\nbattery: {capacity: 100, idle: 0.5, moving: 20, start: 0.8}\n");
  ASSERT_TRUE(s.battery.has_value());
  EXPECT_DOUBLE_EQ(s.battery->capacity, 100.0);
  EXPECT_DOUBLE_EQ(s.battery->idle, 0.5);
  EXPECT_DOUBLE_EQ(s.battery->moving, 20.0);
  EXPECT_DOUBLE_EQ(s.battery->start, 0.8);
  EXPECT_FALSE(parse("shape: triangle.txt\n").battery.has_value());
  expect_rejected("shape: triangle.txt\nbattery: {idle: 0.5}\n", 2, "missing 'capacity'");
  expect_rejected("shape: triangle.txt\nbattery:\n  capacity: 1\n  start: 0\n", 4, "battery.start");
  expect_rejected("shape: triangle.txt\nbattery:\n  capacity: 1\n  idle: -1\n", 4, "battery.idle");
  expect_rejected("shape: triangle.txt\nbattery:\n  capacity: 1\n  volts: 7\n", 4,
                  "battery.volts: unknown key");
}

TEST(Scenario, LidarIsReadAndChecked) {
  const Scenario d = parse("shape: triangle.txt\n");
  EXPECT_EQ(d.lidar.rays, 682u);  // ARGoS's fan when the scenario says nothing
  EXPECT_EQ(d.lidar.max_range, 4.0);
  const Scenario s = parse(
      "shape: triangle.txt\nlidar: {rays: 36, fov: 3.0, min_range: 0.05, max_range: 2.5}\nnoise: {lidar: "
      "0.01}\n");
  EXPECT_EQ(s.lidar.rays, 36u);
  EXPECT_DOUBLE_EQ(s.lidar.fov, 3.0);
  EXPECT_DOUBLE_EQ(s.lidar.min_range, 0.05);
  EXPECT_DOUBLE_EQ(s.lidar.max_range, 2.5);
  EXPECT_DOUBLE_EQ(s.lidar_noise, 0.01);
  expect_rejected("shape: triangle.txt\nlidar:\n  rays: 0\n", 3, "lidar.rays");
  expect_rejected("shape: triangle.txt\nlidar:\n  fov: 7\n", 3, "lidar.fov");
  expect_rejected("shape: triangle.txt\nlidar:\n  min_range: -1\n", 3, "lidar.min_range");
  expect_rejected("shape: triangle.txt\nlidar:\n  min_range: 1\n  max_range: 0.5\n", 4,
                  "lidar.max_range: min_range (1 m) must be below max_range (0.5 m)");
  expect_rejected("shape: triangle.txt\nlidar:\n  min_range: 5\n", 3, "lidar.min_range: min_range (5 m)");
  expect_rejected("shape: triangle.txt\nlidar:\n  range: 5\n", 3, "lidar.range: unknown key");
  expect_rejected("shape: triangle.txt\nnoise:\n  lidar: 2\n", 3, "noise.lidar");
}

TEST(Scenario, RejectsWrongTypes) {
  expect_rejected("shape: triangle.txt\ncomm_range: far\n", 2, "comm_range: expected a finite number");
  expect_rejected("shape: triangle.txt\noccurrence: 1\n", 2, "unknown key");
  expect_rejected("shape: triangle.txt\nocclusion: maybe\n", 2, "occlusion: expected true or false");
  expect_rejected("shape: triangle.txt\nsubsteps: 2.5\n", 2, "substeps: expected an integer");
  expect_rejected("shape: triangle.txt\narena: [1, 2]\n", 2, "arena: expected a map");
  expect_rejected("shape: triangle.txt\nseed: -3\n", 2, "seed: expected a non-negative integer");
  expect_rejected("shape: triangle.txt\ncomm_range: .nan\n", 2, "finite");
  expect_rejected("shape: triangle.txt\nmode: fast\n", 2, "mode: expected lockstep or realtime");
}

TEST(Scenario, RejectsOutOfRangeValues) {
  expect_rejected(
      "shape: triangle.txt\nobstacles:\n  - type: cylinder\n    centre: [1, 1]\n    radius: -0.3\n", 5,
      "obstacles[0].radius: must be > 0");
  expect_rejected("shape: triangle.txt\npacket_loss: 1.0\n", 2, "packet_loss: must be in [0, 1)");
  expect_rejected("shape: triangle.txt\nmax_speed: 0\n", 2, "max_speed: must be > 0");
  expect_rejected("shape: triangle.txt\ntick_rate: -10\n", 2, "tick_rate");
  expect_rejected("shape: triangle.txt\ngoal: {x: 40, y: 0}\n", 2, "goal: (40, 0) lies outside");
}

// packet_loss: a number (independent) or {rate, mean_burst} (bursty, burst_loss.hpp); each part checked.
TEST(Scenario, PacketLossIsANumberOrARateAndAMeanBurst) {
  const Scenario plain = parse("shape: triangle.txt\npacket_loss: 0.2\n");
  EXPECT_DOUBLE_EQ(plain.packet_loss, 0.2);
  EXPECT_EQ(plain.packet_loss_mean_burst, 0.0);
  const Scenario bursty = parse("shape: triangle.txt\npacket_loss: {rate: 0.2, mean_burst: 5}\n");
  EXPECT_DOUBLE_EQ(bursty.packet_loss, 0.2);
  EXPECT_DOUBLE_EQ(bursty.packet_loss_mean_burst, 5.0);
  const Scenario edge = parse("shape: triangle.txt\npacket_loss:\n  rate: 0.2\n  mean_burst: 1.25\n");
  EXPECT_DOUBLE_EQ(edge.packet_loss_mean_burst, 1.25);

  expect_rejected("shape: triangle.txt\npacket_loss: {rate: 1.0, mean_burst: 5}\n", 2,
                  "packet_loss.rate: must be in [0, 1)");
  expect_rejected("shape: triangle.txt\npacket_loss: {rate: -0.1, mean_burst: 5}\n", 2,
                  "packet_loss.rate: must be in [0, 1)");
  expect_rejected("shape: triangle.txt\npacket_loss:\n  rate: 0.2\n  mean_burst: 1\n", 4,
                  "packet_loss.mean_burst: must be in [1.25, 1e+06] ticks, got 1");
  expect_rejected("shape: triangle.txt\npacket_loss: {rate: 0.2, mean_burst: .nan}\n", 2,
                  "packet_loss.mean_burst");
  expect_rejected("shape: triangle.txt\npacket_loss: {rate: 0.2, mean_burst: 1e9}\n", 2,
                  "packet_loss.mean_burst: must be in [1.25, 1e+06]");
  expect_rejected("shape: triangle.txt\npacket_loss: {rate: 0.2, mean_burst: five}\n", 2,
                  "packet_loss.mean_burst: expected a finite number, got 'five'");
  expect_rejected("shape: triangle.txt\npacket_loss: {rate: 0.2}\n", 2,
                  "packet_loss: needs rate and mean_burst");
  expect_rejected("shape: triangle.txt\npacket_loss: {rate: 0.2, burst: 5}\n", 2,
                  "packet_loss.burst: unknown key (known here: rate, mean_burst)");
  expect_rejected("shape: triangle.txt\npacket_loss: [0.2, 5]\n", 2, "packet_loss: expected a number");
}

// --set KEY=VALUE: the field is set over the file's before it is read and checked as the file's are; an error
// in it names the flag, an error elsewhere stays at its line of the file.
TEST(Scenario, SetOverridesAFieldAndItsErrorsNameTheFlag) {
  auto with = [](const std::string& text, std::vector<std::string> sets) {
    ScenarioOverrides ov;
    for (const std::string& t : sets) ov.fields.push_back(parse_field_override(t));
    return parse(text, ov);
  };
  const Scenario s = with(
      "shape: triangle.txt\npacket_loss: 0.1\nnoise: {bearing: 0.02}\n",
      {"packet_loss={rate: 0.2, mean_burst: 5}", "noise.range=0.05", "comm_range=2.5", "arena.width=30"});
  EXPECT_DOUBLE_EQ(s.packet_loss, 0.2);
  EXPECT_DOUBLE_EQ(s.packet_loss_mean_burst, 5.0);
  EXPECT_DOUBLE_EQ(s.range_noise_sd, 0.05);
  EXPECT_DOUBLE_EQ(s.bearing_noise_sd, 0.02);  // the rest of the file's map stays
  EXPECT_DOUBLE_EQ(s.comm_range, 2.5);
  EXPECT_DOUBLE_EQ(s.arena_width, 30.0);
  EXPECT_DOUBLE_EQ(with("shape: triangle.txt\n", {"noise.ultrasonic=0.02"}).ultrasonic_noise_sd, 0.02);

  auto refused = [&](const std::string& text, std::vector<std::string> sets, const std::string& file,
                     int line, const std::string& what) {
    try {
      with(text, sets);
      ADD_FAILURE() << "accepted: " << sets.back();
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file) << e.what();
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string base = "shape: triangle.txt\n";
  refused(base, {"packet_loss=1.5"}, "command line", 0,
          "--set 'packet_loss=1.5': packet_loss: must be in [0, 1)");
  refused(base, {"packet_loss={rate: 0.2, mean_burst: 1}"}, "command line", 0,
          "--set 'packet_loss={rate: 0.2, mean_burst: 1}': packet_loss.mean_burst: must be in [1.25");
  refused(base, {"noise={range: 0.05, colour: red}"}, "command line", 0, "noise.colour: unknown key");
  refused(base, {"comm_rang=2"}, "command line", 0, "--set 'comm_rang=2': comm_rang: unknown key");
  refused("shape: triangle.txt\npacket_loss: 0.1\n", {"packet_loss.rate=0.2"}, "command line", 0,
          "--set 'packet_loss.rate=0.2': the scenario's packet_loss is not a map");
  refused(base, {"comm_range"}, "command line", 0, "--set 'comm_range': expected KEY=VALUE");
  refused(base, {"noise..range=1"}, "command line", 0, "'noise..range' is not a field name");
  refused(base, {"noise={range: 0.1"}, "command line", 0, "the value is not YAML");
  refused(base, {"comm_range="}, "command line", 0, "the value is empty");
  // The file's own error, beside a --set: still at its line.
  refused("shape: triangle.txt\nmax_speed: 0\n", {"comm_range=2"}, kOrigin, 2, "max_speed: must be > 0");
}

// Found by checking what the scenario fuzzer (tests/fuzz) accepts: centres and listed poses took any finite
// number, so robots at 1e308 reached the physics.
TEST(Scenario, RejectsCoordinatesBeyondTheLengthLimit) {
  expect_rejected("shape: triangle.txt\narena: {centre: [1e300, 0], walls: false}\n", 2,
                  "arena.centre[0]: must be in [-10000, 10000], got 1e+300");
  expect_rejected("shape: triangle.txt\nobstacles:\n  - {type: cylinder, centre: [1, -20000], radius: 0.2}\n",
                  3, "obstacles[0].centre[1]: must be in [-10000, 10000]");
  expect_rejected("shape: triangle.txt\nrobots: {region: {centre: [-1e6, 0], width: 3, height: 3}}\n", 2,
                  "robots.region.centre[0]: must be in [-10000, 10000]");
  expect_rejected(
      "shape: triangle.txt\narena: {walls: false}\nrobots:\n  poses:\n    - [0, 0]\n    - [1e308, 0]\n", 6,
      "robots.poses[1][0]: must be in [-10000, 10000]");
}

TEST(Scenario, RejectsOverlappingListedRobots) {
  expect_rejected("shape: triangle.txt\nrobots:\n  poses:\n    - [0, 0, 0]\n    - [0.1, 0, 0]\n", 5,
                  "robot 1 overlaps robot 0");
  expect_rejected(
      "shape: triangle.txt\nobstacles: [{type: cylinder, centre: [2, 0], radius: 0.5}]\n"
      "robots:\n  poses:\n    - [0, 0, 0]\n    - [2.3, 0, 0]\n",
      6, "robot 1 overlaps an obstacle");
}

TEST(Scenario, RejectsAMissingShapeFile) {
  expect_rejected("comm_range: 3\nshape: no_such_shape.txt\n", 2,
                  "shape: file 'no_such_shape.txt' not found");
  expect_rejected("comm_range: 3\n", 0, "shape: missing");
}

TEST(Scenario, RejectsBadControllerParameters) {
  expect_rejected("shape: triangle.txt\ncontroller:\n  k_o: 1.0\n  k_wobble: 2\n", 4,
                  "controller.k_wobble: unknown parameter of behaviour 'paper' (known: k_collision, r_o");
  expect_rejected("shape: triangle.txt\ncontroller:\n  r_o: 50\n", 3, "controller.r_o: must be in [0, 5]");
  expect_rejected("shape: triangle.txt\ncontroller:\n  k_o: lots\n", 3,
                  "controller.k_o: expected a finite number");
}

TEST(Scenario, TheBehavioursOwnTableChecksItsParameters) {
  // behaviour.params: the same table, the same file:line.
  expect_rejected("shape: triangle.txt\nbehaviour:\n  name: paper\n  params: {r_o: 50}\n", 4,
                  "behaviour.params.r_o: must be in [0, 5]");
  // The random walk has no parameter: any name is unknown, and its message says there are none.
  expect_rejected("behaviour: {name: random_walk, params: {r_o: 0.3}}\nrobots: {count: 3}\n", 1,
                  "behaviour.params.r_o: unknown parameter of behaviour 'random_walk' (known: none)");
  expect_rejected("shape: triangle.txt\nbehaviour: {name: paper, params: {k_o: 1}}\ncontroller: {k_o: 2}\n",
                  3, "controller: the parameters are already given in behaviour.params");
  const Scenario s = parse("shape: triangle.txt\nbehaviour: {name: paper, params: {k_o: 2.5}}\n");
  EXPECT_EQ(s.mission.params.at("k_o"), 2.5);
  ASSERT_NE(s.behaviour, nullptr);
  EXPECT_EQ(s.behaviour->name, "paper");
}

TEST(Scenario, ABehaviourOverrideKeepsOnlyTheParametersItHas) {
  // --behaviour random_walk on a paper scenario: the file's paper parameters are the paper's, not the walk's.
  ScenarioOverrides ov;
  ov.behaviour = "random_walk";
  const Scenario s = parse("shape: triangle.txt\ncontroller: {k_o: 2.0}\n", ov);
  EXPECT_EQ(s.mission.behaviour, "random_walk");
  EXPECT_TRUE(s.mission.params.empty());
  ov.behaviour = "dance";
  EXPECT_THROW(parse("shape: triangle.txt\n", ov), InputError);
}

TEST(Scenario, AnUnknownBehaviourListsTheRegisteredOnes) {
  expect_rejected("shape: triangle.txt\nbehaviour: dance\n", 2,
                  "behaviour: unknown behaviour 'dance' (built in: diffusion, paper, phototaxis, "
                  "random_walk; a plug-in is named by its "
                  "library");
  // A plug-in not found names every folder searched and how to add one.
  expect_rejected(
      "shape: triangle.txt\nbehaviour: {plugin: libnothing.so}\n", 2,
      "behaviour.plugin: plug-in 'libnothing.so' not found in the folders searched (" + kRepo +
          "/scenarios): the scenario's folder, each --plugin-dir DIR and SWARMFORM_PLUGIN_PATH; give "
          "the folder that holds it with --plugin-dir DIR");
  expect_rejected("behaviour: {}\nrobots: {count: 2}\n", 1,
                  "behaviour: expected name: (a built-in), plugin: (a shared library) or descriptor: (a JSON "
                  "file)");
}

// A behaviour described by a JSON file beside the scenario: its table checks the scenario's parameters with
// file:line, its name and the file's canonical path go into the mission.
TEST(Scenario, ADescriptorFileBehaviourChecksItsParametersWithFileAndLine) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("swarmform-described-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "gather.json")
      << R"({"api_version": 6, "name": "gather_py", "params": [)"
      << R"({"name": "spacing", "default": 0.45, "min": 0.1, "max": 2.0, "doc": "m"}],)"
      << R"( "states": [{"value": 0, "name": "alone", "colour": "#888888"}]})";
  const std::string origin = (dir / "gather.yaml").string();
  behaviour::Registry registry;
  controller::add_builtins(registry);
  const Scenario s = parse_scenario_text(
      "behaviour:\n  descriptor: gather.json\n  params: {spacing: 0.8}\nrobots: {count: 3}\n", origin, {},
      registry);
  ASSERT_NE(s.behaviour, nullptr);
  EXPECT_EQ(s.behaviour->name, "gather_py");
  EXPECT_EQ(s.behaviour->make, nullptr);
  EXPECT_EQ(s.mission.behaviour, "gather_py");
  EXPECT_EQ(s.mission.descriptor, std::filesystem::canonical(dir / "gather.json").string());
  EXPECT_TRUE(s.mission.plugin.empty());
  EXPECT_EQ(s.mission.params.at("spacing"), 0.8);
  auto refused = [&](const std::string& text, const std::string& says) {
    try {
      (void)parse_scenario_text(text, origin, {}, registry);
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), says);
    }
  };
  refused("robots: {count: 3}\nbehaviour:\n  descriptor: gather.json\n  params:\n    spacing: 5\n",
          origin + ":5: behaviour.params.spacing: must be in [0.1, 2]");
  refused(
      "robots: {count: 3}\nbehaviour:\n  descriptor: gather.json\n  params: {radius: 1}\n",
      origin + ":4: behaviour.params.radius: unknown parameter of behaviour 'gather_py' (known: spacing)");
  refused(
      "behaviour: {descriptor: none.json}\n",
      origin + ":1: behaviour.descriptor: descriptor file 'none.json' not found in the folders searched (" +
          dir.string() +
          "): the scenario's folder, each --plugin-dir DIR and SWARMFORM_PLUGIN_PATH; give the folder that "
          "holds it with --plugin-dir DIR");
  refused("behaviour: {descriptor: gather.json, name: paper}\n",
          origin +
              ":1: behaviour: give one of name (a built-in), plugin (a library) or descriptor (a JSON "
              "file), not two");
  std::ofstream(dir / "old.json") << R"({"api_version": 1, "name": "old_py"})";
  refused("behaviour: {descriptor: old.json}\n",
          origin + ":1: behaviour.descriptor: " + (dir / "old.json").string() +
              ": api_version: the file declares behaviour API version 1, this program has version 6 "
              "(docs/behaviour-api.md lists what changed)");
  std::filesystem::remove_all(dir);
}

TEST(Scenario, AShapeAndAGoalOnlyWhenTheBehaviourNeedsThem) {
  // The random walk forms no shape and goes to no goal: neither is required, a goal outside the walls is no
  // error.
  const Scenario s = parse(
      "behaviour: random_walk\nrobots: {count: 4}\narena: {centre: [0, 0], width: 6, height: 6}\n"
      "goal: {x: 40, y: 0}\n");
  EXPECT_EQ(s.robots.size(), 4u);
  EXPECT_EQ(s.mission.shape.label_count(), 0);
  EXPECT_TRUE(s.shape_file.empty());
  // A goal given is told, whatever the behaviour.
  EXPECT_TRUE(s.mission.has_goal);
  EXPECT_EQ(s.mission.goal.x, 40.0);
  // No goal: a behaviour that goes nowhere is told there is none, not the default (10, 0).
  const Scenario none = parse("behaviour: random_walk\nrobots: {count: 4}\n");
  EXPECT_FALSE(none.mission.has_goal);
  EXPECT_EQ(none.mission.goal.x, 0.0);
  EXPECT_EQ(none.mission.goal_radius, 0.0);
  // The paper goes somewhere: without goal: it is told the default.
  const Scenario paper = parse("shape: triangle.txt\n");
  EXPECT_TRUE(paper.mission.has_goal);
  EXPECT_EQ(paper.mission.goal.x, 10.0);
  EXPECT_EQ(paper.mission.goal_radius, 0.5);
  // Without a shape the robots must be counted.
  expect_rejected("behaviour: random_walk\nrobots: {region: {centre: [0, 0], width: 2, height: 2}}\n", 2,
                  "robots: give robots.count or robots.poses (behaviour 'random_walk' has no shape");
  // The paper's needs both.
  expect_rejected("behaviour: paper\nrobots: {count: 4}\n", 0,
                  "shape: missing (behaviour 'paper' forms a shape");
}

TEST(Scenario, RejectsSyntaxErrorsAndDuplicatesWithTheirLine) {
  expect_rejected("shape: triangle.txt\narena:\n  width: [1, 2\n", 4, "YAML syntax");
  expect_rejected("shape: triangle.txt\nseed: 1\nseed: 2\n", 3, "seed: duplicate key");
}

TEST(Scenario, RejectsKillsOfRobotsThatDoNotExist) {
  expect_rejected("shape: triangle.txt\nkills:\n  - {id: 3, tick: 10}\n  - {id: 9, tick: 10}\n", 4,
                  "kill of robot 9, but there are only 9 robots");
}

// A kill or fault after the run's last tick would never happen: refused, saying so. The file's own are held
// to the file's max_ticks; a --max-ticks that cuts the run short leaves them out on purpose (a probe, a short
// run).
TEST(Scenario, RejectsKillsAndFaultsAfterTheLastTick) {
  expect_rejected("shape: triangle.txt\nmax_ticks: 2000\nkills:\n  - {id: 3, tick: 3000}\n", 4,
                  "kill at tick 3000, after the run's last tick (max_ticks 2000): it would never happen");
  expect_rejected("shape: triangle.txt\nmax_ticks: 2000\nfaults: [stall:1@2500+10]\n", 3,
                  "it starts at tick 2500, after the run's last tick (max_ticks 2000)");
  ScenarioOverrides ov;
  ov.max_ticks = 2000;
  ov.kills.push_back(Kill{3, 3000});
  try {
    parse("shape: triangle.txt\n", ov);
    ADD_FAILURE() << "--kill 3@3000 with --max-ticks 2000 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line");
    EXPECT_NE(
        std::string(e.what()).find("--kill: kill at tick 3000, after the run's last tick (max_ticks 2000)"),
        std::string::npos)
        << e.what();
  }
  ScenarioOverrides fault;
  fault.max_ticks = 100;
  fault.faults.push_back("restart:2@150");
  EXPECT_THROW(parse("shape: triangle.txt\n", fault), InputError);
  // The file's kill at 900 in a run cut to 10 ticks: kept, never reached.
  ScenarioOverrides cut;
  cut.max_ticks = 10;
  EXPECT_EQ(parse("shape: triangle.txt\nkills:\n  - {id: 3, tick: 900}\n", cut).kills.size(), 1u);
}

TEST(Scenario, RejectsARegionTooSmallForItsRobots) {
  expect_rejected(
      "shape: triangle.txt\nrobots:\n  count: 50\n  region: {centre: [0, 0], width: 1, height: 1}\n", 3,
      "cannot place 50 robots");
}

TEST(Scenario, RandomRobotsKeepClearOfObstaclesAndWalls) {
  const Scenario s = parse(R"(shape: triangle.txt
arena: {centre: [0, 0], width: 6, height: 6}
obstacles: [{type: box, centre: [0, 0], size: [2, 2], yaw: 0.3}, {type: cylinder, centre: [2, 2], radius: 0.5}]
robots: {count: 60, region: {centre: [0, 0], width: 6, height: 6}}
goal: {x: 2, y: -2}
behaviour: random_walk
)");  // random_walk: the triangle could not form in so small an arena (the loader would refuse it)
  ASSERT_EQ(s.robots.size(), 60u);
  for (const Pose2D& p : s.robots) {
    EXPECT_LE(std::abs(p.x), 3.0 - kRobotRadius);
    EXPECT_LE(std::abs(p.y), 3.0 - kRobotRadius);
    EXPECT_GE(std::hypot(p.x - 2.0, p.y - 2.0), 0.5 + kRobotRadius);
    // Outside the rotated 2 x 2 box: its bounding circle is sqrt(2); inside that, check in the box frame.
    const double lx = std::cos(0.3) * p.x + std::sin(0.3) * p.y;
    const double ly = -std::sin(0.3) * p.x + std::cos(0.3) * p.y;
    EXPECT_TRUE(std::abs(lx) > 1.0 + kRobotRadius || std::abs(ly) > 1.0 + kRobotRadius) << p.x << " " << p.y;
  }
  EXPECT_TRUE(connected(s.robots, s.comm_range));
}

TEST(Scenario, CommandLineOverridesAreCheckedToo) {
  ScenarioOverrides ov;
  ov.kills.push_back(Kill{12, 5});
  try {
    parse("shape: triangle.txt\n", ov);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line");
    EXPECT_NE(std::string(e.what()).find("--kill"), std::string::npos);
  }
  ScenarioOverrides shape;
  shape.shape_file = "square.txt";  // found in the repository's shapes/
  const Scenario s = parse("shape: triangle.txt\n", shape);
  EXPECT_NE(s.shape_file.find("square.txt"), std::string::npos);
  EXPECT_EQ(s.robots.size(), static_cast<std::size_t>(s.mission.shape.label_count()));
  ScenarioOverrides missing;
  missing.shape_file = "nope.txt";
  EXPECT_THROW(parse("shape: triangle.txt\n", missing), InputError);
}

TEST(Scenario, LoadReportsAnUnreadableFile) {
  try {
    load_scenario(kRepo + "/scenarios/does-not-exist.yaml", {}, swarmform::controller::builtin_registry());
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace swarmform::world
