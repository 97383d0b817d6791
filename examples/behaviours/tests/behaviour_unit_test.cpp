// The example behaviours' controllers, each loaded from its plug-in through the registry exactly as
// robot_agent and swarm_inprocess load it, stepped on perceptions built here: each does what its rule says.
// Also the registry's refusals: a plug-in outside the allowed folders, a mission naming another behaviour, a
// plug-in of an older API version; the aggregation's and the avoidance's experiments on truths built here;
// the per-robot generator and behaviour::drive.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>

#include "behaviour/drive.hpp"
#include "behaviour/params.hpp"
#include "behaviour/random.hpp"
#include "behaviour/registry.hpp"
#include "common/input_error.hpp"

namespace {

using namespace swarmform;
namespace fs = std::filesystem;

Mission mission_of(const std::string& name, const std::string& dir) {
  Mission m;
  m.behaviour = name;
  m.plugin = dir + "/lib" + name + ".so";
  m.shape = {};
  m.max_speed = 0.1;
  return m;
}

std::unique_ptr<controller::Controller> load(const std::string& name, const std::string& dir,
                                             const std::map<std::string, double>& params = {}) {
  behaviour::Registry registry({dir});
  Mission m = mission_of(name, dir);
  m.params = params;
  return registry.make(m, 0);
}

Perception quiet() {
  Perception p;
  p.ultrasonic.fill(kUltrasonicMaxRange);
  return p;
}

RabReading heard(RobotId from, double range, double bearing, std::vector<std::uint8_t> data = {1}) {
  return RabReading{from, range, bearing, std::move(data)};
}

double turn(const Command& c) {
  return c.right_speed - c.left_speed;  // > 0: turning left (counter-clockwise)
}

TEST(Aggregation, TurnsTowardsTheCentroidOfItsNeighbours) {
  auto c = load("aggregation", AGGREGATION_DIR);
  Perception p = quiet();
  p.messages = {heard(1, 2.0, 1.2), heard(2, 2.0, 1.6)};  // both to the left
  const Command left = c->step(p);
  EXPECT_GT(turn(left), 0.0);
  p.messages = {heard(1, 2.0, -1.2), heard(2, 2.0, -1.6)};
  EXPECT_LT(turn(c->step(p)), 0.0);
  EXPECT_EQ(left.telemetry.state, 1);  // approaching
  ASSERT_EQ(left.telemetry.extra.size(), 2u);
  EXPECT_EQ(left.telemetry.extra[0], 2.0);
}

TEST(Aggregation, StopsOnceTheCentroidIsNear) {
  auto c = load("aggregation", AGGREGATION_DIR, {{"stop_distance", 0.5}});
  Perception p = quiet();
  p.messages = {heard(1, 0.3, 0.0), heard(2, 0.3, 0.5)};
  const Command cmd = c->step(p);
  EXPECT_EQ(cmd.left_speed, 0.0);
  EXPECT_EQ(cmd.right_speed, 0.0);
  EXPECT_EQ(cmd.telemetry.state, 2);  // gathered
}

TEST(Dispersion, BacksAwayFromANeighbourTooClose) {
  auto c = load("dispersion", DISPERSION_DIR, {{"spacing", 1.0}});
  Perception p = quiet();
  p.messages = {heard(1, 0.4, 0.0)};  // dead ahead
  const Command cmd = c->step(p);
  EXPECT_LT(cmd.left_speed + cmd.right_speed, 0.0);  // reverses
  EXPECT_EQ(cmd.telemetry.state, 0);
  ASSERT_EQ(cmd.telemetry.extra.size(), 1u);
  EXPECT_EQ(cmd.telemetry.extra[0], 0.4);
}

TEST(Dispersion, SettlesWhenEveryNeighbourIsFarEnough) {
  auto c = load("dispersion", DISPERSION_DIR, {{"spacing", 1.0}});
  Perception p = quiet();
  p.messages = {heard(1, 1.5, 0.0), heard(2, 2.0, 2.0)};
  const Command cmd = c->step(p);
  EXPECT_EQ(cmd.left_speed, 0.0);
  EXPECT_EQ(cmd.right_speed, 0.0);
  EXPECT_EQ(cmd.telemetry.state, 1);  // settled
}

std::vector<std::uint8_t> heading_bytes(double theta) {
  std::vector<std::uint8_t> b(sizeof theta);
  std::memcpy(b.data(), &theta, sizeof theta);
  return b;
}

TEST(Flocking, AlignsWithItsNeighboursHeadings) {
  auto c = load("flocking", FLOCKING_DIR, {{"w_cohesion", 0.0}, {"w_separation", 0.0}});
  Perception p = quiet();
  p.pose.theta = 0.0;
  // Two neighbours far enough not to repel, both heading up (+y): the robot turns left towards them.
  p.messages = {heard(1, 2.0, 0.0, heading_bytes(std::numbers::pi / 2)),
                heard(2, 2.0, 0.1, heading_bytes(std::numbers::pi / 2))};
  const Command cmd = c->step(p);
  EXPECT_GT(turn(cmd), 0.0);
  ASSERT_EQ(cmd.message.size(), sizeof(double));  // says its own heading
  EXPECT_EQ(cmd.telemetry.state, 1);
}

TEST(Flocking, SeparatesFromANeighbourTooClose) {
  auto c = load("flocking", FLOCKING_DIR, {{"w_cohesion", 0.0}, {"w_alignment", 0.0}});
  Perception p = quiet();
  p.messages = {heard(1, 0.2, 0.3, heading_bytes(0.0))};  // close, ahead-left
  EXPECT_LT(turn(c->step(p)), 0.0);                       // turns right, away
}

// The Khepera IV sensors the three sensor examples declare, equipped and quiet: no light, nothing near, a
// white floor.
Perception equipped() {
  Perception p = quiet();
  p.light = std::array<double, kLightCount>{};
  p.proximity = std::array<double, kProximityCount>{};
  p.ground = std::array<double, kGroundCount>{1.0, 1.0, 1.0, 1.0};
  return p;
}

bool all_leds(const Command& c, Rgb colour) {
  return std::all_of(c.leds.begin(), c.leds.end(), [&](const Rgb& l) { return l == colour; });
}

TEST(SeekLight, TurnsTowardsTheBrighterSideAndSearchesInTheDark) {
  auto c = load("seek_light", SEEK_LIGHT_DIR);
  Perception p = equipped();
  p.light =
      std::array<double, kLightCount>{0.1, 0.3, 0.5, 0.2, 0.0, 0.0, 0.0, 0.05};  // brightest at 90° left
  const Command left = c->step(p);
  EXPECT_GT(turn(left), 0.0);
  EXPECT_EQ(left.telemetry.state, 1);  // homing
  EXPECT_TRUE(all_leds(left, Rgb{255, 200, 0}));
  ASSERT_EQ(left.telemetry.extra.size(), 2u);
  EXPECT_EQ(left.telemetry.extra[0], 0.5);
  EXPECT_GT(left.telemetry.extra[1], 1.0);  // the bearing: left, pulled towards the 45° sensor's 0.3
  EXPECT_LT(left.telemetry.extra[1], std::numbers::pi / 2);
  p.light =
      std::array<double, kLightCount>{0.1, 0.05, 0.0, 0.0, 0.0, 0.2, 0.5, 0.3};  // brightest at 90° right
  EXPECT_LT(turn(c->step(p)), 0.0);
  p.light =
      std::array<double, kLightCount>{0.6, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.3};  // dead ahead: straight on
  const Command ahead = c->step(p);
  EXPECT_NEAR(turn(ahead), 0.0, 1e-12);
  EXPECT_GT(ahead.left_speed, 0.0);
  // Two lights, left and right, the right one brighter: towards it, not between them.
  p.light = std::array<double, kLightCount>{0.0, 0.0, 0.4, 0.0, 0.0, 0.0, 0.45, 0.0};
  EXPECT_LT(turn(c->step(p)), 0.0);
  p.light = std::array<double, kLightCount>{};
  const Command dark = c->step(p);
  EXPECT_EQ(dark.telemetry.state, 0);  // searching
  EXPECT_TRUE(all_leds(dark, Rgb{}));
  // An obstacle close ahead-right beats the light on the right: it turns left, away.
  p.light = std::array<double, kLightCount>{0.1, 0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.3};
  p.proximity = std::array<double, kProximityCount>{0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.6};
  const Command avoid = c->step(p);
  EXPECT_GT(turn(avoid), 0.0);
  EXPECT_EQ(avoid.telemetry.state, 2);  // avoiding
}

TEST(Foraging, TakesAnItemOnFoodAndDropsItAtTheNest) {
  auto c = load("foraging", FORAGING_DIR);
  Perception p = equipped();
  const Command bare = c->step(p);
  EXPECT_EQ(bare.telemetry.state, 0);  // searching
  EXPECT_TRUE(all_leds(bare, Rgb{0, 0, 255}));
  p.ground = std::array<double, kGroundCount>{0.15, 1.0, 1.0, 1.0};  // the front-left sensor on food
  const Command took = c->step(p);
  EXPECT_EQ(took.telemetry.state, 1);  // carrying
  EXPECT_TRUE(all_leds(took, Rgb{255, 200, 0}));
  // Carrying, it steers to the light (on its left) and keeps the item over bare floor and more food.
  p.ground = std::array<double, kGroundCount>{1.0, 1.0, 1.0, 1.0};
  p.light = std::array<double, kLightCount>{0.0, 0.1, 0.3, 0.1, 0.0, 0.0, 0.0, 0.0};
  const Command home = c->step(p);
  EXPECT_EQ(home.telemetry.state, 1);
  EXPECT_GT(turn(home), 0.0);
  p.ground = std::array<double, kGroundCount>{0.1, 0.1, 0.1, 0.1};
  EXPECT_EQ(c->step(p).telemetry.state, 1);
  EXPECT_EQ(c->step(p).telemetry.extra[0], 0.0);  // nothing delivered yet
  // The nest (mid grey), at (-1, 0): dropped and counted.
  p.pose = {-1.0, 0.0, 0.0};
  p.ground = std::array<double, kGroundCount>{0.55, 0.55, 1.0, 1.0};
  const Command dropped = c->step(p);
  EXPECT_EQ(dropped.telemetry.state, 0);
  EXPECT_TRUE(all_leds(dropped, Rgb{0, 0, 255}));
  ASSERT_EQ(dropped.telemetry.extra.size(), 2u);
  EXPECT_EQ(dropped.telemetry.extra[0], 1.0);
  EXPECT_EQ(dropped.telemetry.extra[1], 0.55);
  // Searching again over the nest, it takes nothing.
  EXPECT_EQ(c->step(p).telemetry.state, 0);
  // Loaded again at (1, 1) facing +x with the light hidden (readings below `dark`): it steers to where it
  // last stood on the nest, behind it on its right, not to the noise.
  p.pose = {1.0, 1.0, 0.0};
  p.ground = std::array<double, kGroundCount>{0.1, 1.0, 1.0, 1.0};
  p.light = std::array<double, kLightCount>{0.0, 0.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0};  // noise on the left
  const Command hidden = c->step(p);
  EXPECT_EQ(hidden.telemetry.state, 1);
  EXPECT_NEAR(turn(hidden), -0.2, 1e-12);  // on the spot, clockwise, at full speed (bearing -2.68 rad)
  EXPECT_NEAR(hidden.left_speed + hidden.right_speed, 0.0, 1e-12);
}

TEST(Avoidance, TurnsAwayFromANearBodyAndStopsForOneAhead) {
  auto c = load("avoidance", AVOIDANCE_DIR, {{"k_avoid", 8.0}});
  Perception p = equipped();
  const Command clear = c->step(p);
  EXPECT_EQ(clear.telemetry.state, 0);  // cruising
  EXPECT_TRUE(all_leds(clear, Rgb{0, 255, 0}));
  EXPECT_GT(clear.left_speed + clear.right_speed, 0.0);
  p.proximity = std::array<double, kProximityCount>{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.3, 0.5};  // on the right
  const Command right = c->step(p);
  EXPECT_GT(turn(right), 0.0);  // turns left, away
  EXPECT_EQ(right.telemetry.state, 1);
  EXPECT_TRUE(all_leds(right, Rgb{255, 0, 0}));
  ASSERT_EQ(right.telemetry.extra.size(), 1u);
  EXPECT_EQ(right.telemetry.extra[0], 0.5);
  p.proximity = std::array<double, kProximityCount>{0.0, 0.5, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0};  // on the left
  EXPECT_LT(turn(c->step(p)), 0.0);
  // Touching dead ahead: it backs off and turns (to a side of its own), never straight on.
  p.proximity = std::array<double, kProximityCount>{1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  const Command ahead = c->step(p);
  EXPECT_LT(ahead.left_speed + ahead.right_speed, 0.0);
  EXPECT_NE(turn(ahead), 0.0);
  // What is behind it is not in its way.
  p.proximity = std::array<double, kProximityCount>{0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(c->step(p).telemetry.state, 0);
}

// The avoidance experiment's contacts on the truth's geometry: a robot touching a turned box counts once per
// touch, and the gap is measured to the box's surface, not its centre.
TEST(AvoidanceExperiment, CountsTouchesOnTheTrueGeometry) {
  behaviour::Registry registry({AVOIDANCE_DIR});
  const behaviour::Descriptor& d = registry.load_plugin(std::string(AVOIDANCE_DIR) + "/libavoidance.so");
  ASSERT_NE(d.experiment.make, nullptr);
  Mission m = mission_of("avoidance", AVOIDANCE_DIR);
  m.params = {{"min_travel", 0.1}};  // 0.1 x 0.1 m/s x 0.3 s: not what decides here
  auto e = d.experiment.make();
  e->init(m, 1);
  const double yaw = std::numbers::pi / 4;
  const std::array box{
      experiment::ObstacleTruth{experiment::ObstacleTruth::Kind::Box, {0.0, 0.0}, yaw, {0.5, 0.1}, 0.0}};
  const Telemetry telemetry;
  // Along the box's short axis (its local +y, turned by yaw): body edge 0.05 m from the face, touching, away.
  const Vec2 normal{-std::sin(yaw), std::cos(yaw)};
  const double away = 0.1 + kRobotRadius;  // half depth + body
  Tick tick = 0;
  for (const double gap : {0.05, 0.0, 0.3, 0.0005}) {
    const std::array robots{experiment::RobotTruth{
        0, {normal.x * (away + gap), normal.y * (away + gap), 0.0}, true, &telemetry, {}}};
    experiment::Truth t;
    t.tick = tick++;
    t.robots = robots;
    t.obstacles = box;
    e->observe(t);
  }
  const auto r = e->conclude();
  EXPECT_EQ(r.metrics[0], 2.0);  // two touches
  EXPECT_NEAR(r.metrics[1], 0.0, 1e-9);
  EXPECT_NEAR(r.metrics[2], 0.05 + 0.3 + 0.2995, 1e-9);  // the path from the first pose
  EXPECT_EQ(r.outcome, "collided");
}

TEST(Registry, RefusesAPluginOutsideItsFolders) {
  behaviour::Registry registry({FLOCKING_DIR});  // not aggregation's folder
  Mission m = mission_of("aggregation", AGGREGATION_DIR);
  try {
    registry.make(m, 0);
    FAIL() << "loaded a plug-in outside the allowed folders";
  } catch (const behaviour::PluginError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the allowed plug-in folders"), std::string::npos)
        << e.what();
  }
  // A path that climbs out of an allowed folder is refused too (it is made canonical first).
  m.plugin = std::string(FLOCKING_DIR) + "/../aggregation/libaggregation.so";
  EXPECT_THROW(registry.make(m, 0), behaviour::PluginError);
}

TEST(Registry, RefusesAMissionNamingAnotherBehaviour) {
  behaviour::Registry registry({AGGREGATION_DIR});
  Mission m = mission_of("aggregation", AGGREGATION_DIR);
  m.behaviour = "paper";
  EXPECT_THROW(registry.make(m, 0), InputError);
}

TEST(Registry, ChecksParametersAgainstThePluginsTable) {
  behaviour::Registry registry({AGGREGATION_DIR});
  Mission m = mission_of("aggregation", AGGREGATION_DIR);
  m.params = {{"stop_distance", 50.0}};
  EXPECT_THROW(registry.make(m, 0), InputError);
  m.params = {{"k_wobble", 1.0}};
  EXPECT_THROW(registry.make(m, 0), InputError);
  const behaviour::Descriptor& d = registry.load_plugin(m.plugin);
  EXPECT_EQ(d.name, "aggregation");
  EXPECT_FALSE(d.needs_shape);
  EXPECT_EQ(d.telemetry.size(), 2u);
  EXPECT_NE(behaviour::check_param(d, "stop_distance", 50.0).find("must be in"), std::string::npos);
}

// A descriptor's shape rules must name its own parameter and state: the registry refuses one that does not
// (a plug-in with a PluginError naming the field, a built-in as a bug), so the world never looks up a
// parameter or waits for a state the behaviour does not have.
std::unique_ptr<controller::Controller> no_controller() {
  return nullptr;
}

TEST(Registry, RefusesShapeRulesThatNameAParameterOrStateTheBehaviourLacks) {
  static constexpr std::array params{behaviour::ParamSpec{"turn", 0.0, -4.0, 4.0, "rad"}};
  static constexpr std::array states{behaviour::StateSpec{0, "forming", "#000000"},
                                     behaviour::StateSpec{1, "moving", "#ffffff"}};
  behaviour::Descriptor d{.name = "shaper",
                          .summary = "",
                          .params = params,
                          .states = states,
                          .telemetry = {},
                          .needs_shape = true,
                          .needs_goal = true,
                          .shape_rules = {.anchor = behaviour::ShapeAnchor::NearestOrigin,
                                          .heading_param = "turn",
                                          .motion_state = 1},
                          .make = &no_controller,
                          .sensors = 0,
                          .experiment = {}};
  EXPECT_EQ(behaviour::check_shape_rules(d), "");
  Mission m;
  m.params = {{"turn", 0.5}};
  EXPECT_DOUBLE_EQ(behaviour::shape_heading(m, d), 0.5);

  d.shape_rules.heading_param = "shape_heading";
  EXPECT_NE(behaviour::check_shape_rules(d).find(
                "heading_param 'shape_heading' is not one of its parameters (turn)"),
            std::string::npos)
      << behaviour::check_shape_rules(d);
  behaviour::Registry registry;
  EXPECT_THROW(registry.add(d), std::logic_error);

  d.shape_rules.heading_param = {};
  EXPECT_DOUBLE_EQ(behaviour::shape_heading(m, d), behaviour::kShapeUp);  // none named: the shape as written
  d.shape_rules.motion_state = 5;
  EXPECT_NE(behaviour::check_shape_rules(d).find("motion_state 5 is not one of its states"),
            std::string::npos);
  d.shape_rules.motion_state = behaviour::ShapeRules::kNoState;
  EXPECT_EQ(behaviour::check_shape_rules(d), "");
  registry.add(d);
  EXPECT_EQ(registry.find("shaper"), &d);
}

// A plug-in built against API version 2 is refused by a version-4 program, naming both.
TEST(Registry, RefusesAPluginOfAnotherApiVersionNamingBoth) {
  behaviour::Registry registry({OLD_API_DIR});
  try {
    registry.load_plugin(std::string(OLD_API_DIR) + "/libold_api.so");
    FAIL() << "an API-2 plug-in was loaded";
  } catch (const behaviour::PluginError& e) {
    EXPECT_NE(std::string(e.what()).find("built against behaviour API version 2, this program has version 6"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(registry.find("old_api"), nullptr);
}

// The aggregation's experiment, made from its plug-in's descriptor, on truths built here: clusters by true
// distance (link 2 x stop_distance), the tick everyone first stood in one, and the outcome.
TEST(AggregationExperiment, CountsClustersAndJudgesGatheredOnTheTruth) {
  behaviour::Registry registry({AGGREGATION_DIR});
  const behaviour::Descriptor& d = registry.load_plugin(std::string(AGGREGATION_DIR) + "/libaggregation.so");
  ASSERT_NE(d.experiment.make, nullptr);
  ASSERT_EQ(d.experiment.metrics.size(), 5u);
  EXPECT_EQ(d.experiment.success, "gathered");
  Mission m = mission_of("aggregation", AGGREGATION_DIR);
  m.params = {{"stop_distance", 0.5}};  // link: 1 m
  auto run = [&](const std::vector<std::vector<Vec2>>& ticks, const std::vector<bool>& alive) {
    auto e = d.experiment.make();
    e->init(m, alive.size());
    const Telemetry telemetry;
    for (std::size_t t = 0; t < ticks.size(); ++t) {
      std::vector<experiment::RobotTruth> robots;
      for (std::size_t i = 0; i < ticks[t].size(); ++i)
        robots.push_back(
            {static_cast<RobotId>(i), {ticks[t][i].x, ticks[t][i].y, 0.0}, alive[i], &telemetry, {}});
      experiment::Truth truth;
      truth.tick = t;
      truth.robots = robots;
      e->observe(truth);
    }
    return e->conclude();
  };
  // Two pairs 5 m apart (a chain within a pair at 0.9 m), then all four within links of each other.
  const std::vector<Vec2> apart = {{0, 0}, {0.9, 0}, {5, 0}, {5.9, 0}};
  const std::vector<Vec2> together = {{0, 0}, {0.9, 0}, {1.8, 0}, {2.7, 0}};
  const auto scattered = run({apart, apart}, {true, true, true, true});
  EXPECT_EQ(scattered.outcome, "scattered");
  EXPECT_EQ(scattered.metrics[0], 2.0);           // clusters
  EXPECT_EQ(scattered.metrics[1], 2.0);           // largest_cluster
  EXPECT_TRUE(std::isnan(scattered.metrics[2]));  // never gathered
  const auto gathered = run({apart, apart, together, together}, {true, true, true, true});
  EXPECT_EQ(gathered.outcome, "gathered");
  EXPECT_EQ(gathered.metrics[0], 1.0);
  EXPECT_EQ(gathered.metrics[1], 4.0);
  EXPECT_EQ(gathered.metrics[2], 2.0);  // the first tick in one cluster
  EXPECT_NEAR(gathered.metrics[3], (1.35 + 0.45 + 0.45 + 1.35) / 4.0, 1e-12);
  // A dead robot far away is no cluster of its own.
  const auto dead_apart = run({{{0, 0}, {0.9, 0}, {1.8, 0}, {9, 9}}}, {true, true, true, false});
  EXPECT_EQ(dead_apart.outcome, "gathered");
  EXPECT_EQ(dead_apart.metrics[1], 3.0);
}

// behaviour::drive: a speed and turn rate to wheel speeds, scaled down together at the limit.
TEST(Drive, KeepsTheTurnsRadiusAtTheSpeedLimit) {
  Command c;
  behaviour::drive(0.05, 0.5, 0.1, c);  // within the limit: v -+ w x half the wheel spacing
  EXPECT_DOUBLE_EQ(c.left_speed, 0.05 - 0.5 * kWheelSpacing / 2.0);
  EXPECT_DOUBLE_EQ(c.right_speed, 0.05 + 0.5 * kWheelSpacing / 2.0);
  behaviour::drive(0.1, 1.0, 0.1, c);  // the right wheel would pass 0.1 m/s: both scaled by the same factor
  EXPECT_DOUBLE_EQ(c.right_speed, 0.1);
  EXPECT_NEAR(c.left_speed / c.right_speed, (0.1 - kWheelSpacing / 2.0) / (0.1 + kWheelSpacing / 2.0), 1e-12);
  behaviour::drive(0.0, -10.0, 0.1, c);  // on the spot, clockwise, at full speed
  EXPECT_DOUBLE_EQ(c.left_speed, 0.1);
  EXPECT_DOUBLE_EQ(c.right_speed, -0.1);
}

// The per-robot generator is the documented splitmix64 stream (docs/behaviour-api.md), so an agent in
// another language can reproduce it; streams differ by robot and by seed.
TEST(RobotRandom, IsTheDocumentedStreamOfTheSeedAndTheId) {
  constexpr std::uint64_t golden = 0x9e3779b97f4a7c15ULL;
  auto mix = [](std::uint64_t z) {  // splitmix64's finaliser, written out independently of the API's
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  const std::uint64_t seed = 42;
  const RobotId id = 7;
  std::uint64_t s = mix(seed + golden) ^ (std::uint64_t{id} * golden);
  behaviour::RobotRandom rng(seed, id);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(rng.next(), mix(s + golden));
    s += golden;
  }
  behaviour::RobotRandom a(seed, id), b(seed, id);
  EXPECT_EQ(a.uniform(), static_cast<double>(b.next() >> 11) * 0x1.0p-53);
  EXPECT_NE(behaviour::RobotRandom(seed, 8).next(), behaviour::RobotRandom(seed, 7).next());
  EXPECT_NE(behaviour::RobotRandom(seed + 1, 7).next(), behaviour::RobotRandom(seed, 7).next());
  for (int k = 0; k < 1000; ++k) {
    const double x = a.uniform(-2.0, 3.0);
    ASSERT_GE(x, -2.0);
    ASSERT_LT(x, 3.0);
  }
}

}  // namespace
