// The example behaviours' controllers, each loaded from its plug-in through the registry exactly as
// robot_agent and swarm_inprocess load it, stepped on perceptions built here: each does what its rule says.
// Also the registry's refusals: a plug-in outside the allowed folders, and a mission naming another
// behaviour.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>

#include "behaviour/params.hpp"
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
                          .make = &no_controller};
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

}  // namespace
