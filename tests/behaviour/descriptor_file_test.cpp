// A behaviour described by a JSON file (behaviour/descriptor_file.hpp): a good file gives back every field;
// each kind of bad file is refused with `file: key.path: what`; the registry keeps it, refuses it a
// controller and tells an agent that meets it on the wire why.
#include "behaviour/descriptor_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>

#include "behaviour/descriptor_check.hpp"
#include "behaviour/params.hpp"
#include "behaviour/registry.hpp"
#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"

namespace swarmform::behaviour {
namespace {

namespace fs = std::filesystem;

const std::string kGood = R"({
  "api_version": 6,
  "name": "gather_py",
  "summary": "gathers at the neighbours' centroid",
  "params": [
    {"name": "spacing", "default": 0.45, "min": 0.1, "max": 2.0, "doc": "distance kept, m"},
    {"name": "gain", "default": 1.5, "min": 0, "max": 10, "doc": "turn gain, 1/s"}
  ],
  "states": [
    {"value": 0, "name": "alone", "colour": "#888888"},
    {"value": 2, "name": "spaced", "colour": "#2ca02c"}
  ],
  "telemetry": [{"name": "neighbours", "doc": "neighbours heard this tick"}],
  "needs_goal": true,
  "sensors": ["proximity", "battery"]
})";

class DescriptorFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("swarmform-descriptor-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }

  // `text` refused with exactly "<its path>: <says>".
  void expect_refused(const std::string& text, const std::string& says) {
    const std::string path = write("bad.json", text);
    try {
      (void)load_descriptor_file(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(std::string(e.what()), path + ": " + says) << text;
    }
  }

  // kGood with `from` replaced by `to`.
  static std::string good_with(const std::string& from, const std::string& to) {
    std::string s = kGood;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  }

  fs::path dir_;
};

TEST_F(DescriptorFile, AGoodFileGivesBackEveryField) {
  const auto b = load_descriptor_file(write("gather.json", kGood));
  const Descriptor& d = b->descriptor();
  EXPECT_EQ(d.api_version, kApiVersion);
  EXPECT_EQ(d.name, "gather_py");
  EXPECT_EQ(d.summary, "gathers at the neighbours' centroid");
  ASSERT_EQ(d.params.size(), 2u);
  EXPECT_EQ(d.params[0].name, "spacing");
  EXPECT_EQ(d.params[0].default_value, 0.45);
  EXPECT_EQ(d.params[0].min_value, 0.1);
  EXPECT_EQ(d.params[0].max_value, 2.0);
  EXPECT_EQ(d.params[0].doc, "distance kept, m");
  EXPECT_EQ(d.params[1].name, "gain");
  EXPECT_EQ(d.params[1].max_value, 10.0);
  ASSERT_EQ(d.states.size(), 2u);
  EXPECT_EQ(d.states[1].value, 2);
  EXPECT_EQ(d.states[1].name, "spaced");
  EXPECT_EQ(d.states[1].colour, "#2ca02c");
  ASSERT_EQ(d.telemetry.size(), 1u);
  EXPECT_EQ(d.telemetry[0].name, "neighbours");
  EXPECT_EQ(d.telemetry[0].doc, "neighbours heard this tick");
  EXPECT_TRUE(d.needs_goal);
  EXPECT_FALSE(d.needs_shape);
  EXPECT_EQ(d.sensors, kProximity | kBattery);
  EXPECT_EQ(d.make, nullptr);
  EXPECT_EQ(d.experiment.make, nullptr);
  // The table checks a scenario's values as a plug-in's does.
  EXPECT_EQ(check_param(d, "spacing", 3.0), "must be in [0.1, 2]");
  EXPECT_EQ(check_param(d, "gain", 2.0), "");
  // Only api_version and name are required.
  const auto minimal = load_descriptor_file(write("min.json", R"({"api_version": 6, "name": "quiet"})"));
  EXPECT_EQ(minimal->descriptor().name, "quiet");
  EXPECT_TRUE(minimal->descriptor().params.empty());
  EXPECT_FALSE(minimal->descriptor().needs_goal);
}

TEST_F(DescriptorFile, EachKindOfBadFileIsRefusedNamingTheKey) {
  const std::string missing = (dir_ / "none.json").string();
  try {
    (void)load_descriptor_file(missing);
    ADD_FAILURE() << "a missing file was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              missing + ": cannot read the behaviour's descriptor file (no such file, or not readable)");
  }
  {
    const std::string path = write("bad.json", "{\"name\": ");
    try {
      (void)load_descriptor_file(path);
      ADD_FAILURE() << "bad JSON was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": not JSON: parse error at line 1", 0), 0u) << e.what();
    }
  }
  expect_refused("[1, 2]", "expected an object, got array");
  expect_refused(R"({"name": "x"})", "api_version: missing");
  expect_refused(R"({"api_version": 2, "name": "x"})",
                 "api_version: the file declares behaviour API version 2, this program has version 6 "
                 "(docs/behaviour-api.md lists what changed)");
  expect_refused(R"({"api_version": "3", "name": "x"})", "api_version: expected an integer, got string");
  expect_refused(good_with("\"needs_goal\"", "\"needs_gaol\""),
                 "needs_gaol: unknown key (known: api_version, name, summary, params, states, telemetry, "
                 "needs_goal, sensors)");
  expect_refused(good_with("\"needs_goal\": true", "\"needs_goal\": 1"),
                 "needs_goal: expected true or false, got number");
  expect_refused(good_with("\"gather_py\"", "\"Gather Py\""),
                 "name: 'Gather Py' is not a lower_case name (a-z, 0-9, _)");
  expect_refused(good_with("\"max\": 10", "\"max\": -1"), "params[1].max: below min (-1 < 0)");
  expect_refused(good_with("\"default\": 1.5", "\"default\": 12"),
                 "params[1].default: 12 is outside [min, max] = [0, 10]");
  expect_refused(good_with("\"name\": \"gain\"", "\"name\": \"spacing\""),
                 "params[1].name: 'spacing' is already a parameter");
  expect_refused(good_with(", \"doc\": \"turn gain, 1/s\"", ""), "params[1].doc: missing");
  expect_refused(good_with("\"min\": 0,", "\"min\": 0, \"step\": 1,"),
                 "params[1].step: unknown key (known: name, default, min, max, doc)");
  expect_refused(good_with("\"min\": 0,", "\"min\": \"zero\","),
                 "params[1].min: expected a number, got string");
  expect_refused(good_with("\"#2ca02c\"", "\"green\""),
                 "states[1].colour: 'green' is not a colour \"#rrggbb\"");
  expect_refused(good_with("\"value\": 2", "\"value\": 0"), "states[1].value: 0 is already state 'alone'");
  expect_refused(good_with("\"name\": \"spaced\"", "\"name\": \"alone\""),
                 "states[1].name: 'alone' is already a state");
  expect_refused(good_with("\"value\": 2", "\"value\": -2"), "states[1].value: -2 is outside 0..2147483647");
  expect_refused(
      good_with("\"telemetry\": [{", "\"telemetry\": [{\"name\": \"neighbours\", \"doc\": \"again\"}, {"),
      "telemetry[1].name: 'neighbours' is already a column");
  expect_refused(good_with("\"battery\"", "\"sonar\""),
                 "sensors[1]: unknown sensor 'sonar' (known: proximity, light, ground, lidar, battery)");
  expect_refused(
      good_with("\"needs_goal\": true", "\"experiment\": {}"),
      "experiment: not supported: a behaviour described by a file has no experiment (its outcome is "
      "\"none\"; judge its runs with --expect)");
}

TEST_F(DescriptorFile, TheRegistryKeepsItAndRefusesItAController) {
  Registry registry;
  controller::add_builtins(registry);
  const std::string path = write("gather.json", kGood);
  const Descriptor& d = registry.load_descriptor(path);
  EXPECT_EQ(&registry.load_descriptor(path), &d) << "loaded once";
  EXPECT_EQ(registry.find("gather_py"), &d);
  Mission m;
  m.behaviour = "gather_py";
  m.descriptor = fs::canonical(path).string();
  EXPECT_EQ(&registry.resolve(m), &d);
  const std::string says =
      "<mission>: behaviour 'gather_py' is described by gather.json and has no controller: its agents run it "
      "with robot_agent --exec / swarm run --exec";
  try {
    (void)registry.make(m, 0);
    ADD_FAILURE() << "a controller was made for a described behaviour";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), says);
  }
  // A mission that does not say which file (another behaviour's run, overridden): the message still says why.
  Mission plain = m;
  plain.descriptor.clear();
  try {
    (void)make_controller(d, plain, 0);
    ADD_FAILURE() << "a controller was made for a described behaviour";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("'gather_py' is described by a descriptor file and has no controller"),
        std::string::npos)
        << e.what();
  }
  // An agent's registry never loads the file: the mission's descriptor alone gets it the same answer.
  Registry agent;
  controller::add_builtins(agent);
  try {
    (void)agent.make(m, 0);
    ADD_FAILURE() << "an agent made a controller for a described behaviour";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), says);
  }
  // A name already registered is refused, naming the file.
  const std::string clash = write("walk.json", R"({"api_version": 6, "name": "random_walk"})");
  try {
    (void)registry.load_descriptor(clash);
    ADD_FAILURE() << "a descriptor took a built-in's name";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              clash +
                  ": name: behaviour 'random_walk' is already registered (a built-in, a "
                  "plug-in or another descriptor file)");
  }
}

// A descriptor made in code (a plug-in's, a built-in's) is held to what a file is: its parameter table and
// its states are checked when it is registered, the first problem named with the behaviour.
TEST(DescriptorChecks, APluginsParameterTableAndStatesAreCheckedAsAFilesAre) {
  static constexpr ParamSpec kParams[] = {{"gain", 1.0, 0.0, 2.0, "1/s"}, {"spacing", 3.0, 0.1, 2.0, "m"}};
  static constexpr StateSpec kStates[] = {{0, "alone", "#888888"}, {1, "near", "#2ca02c"}};
  Descriptor d;
  d.name = "code_made";
  d.make = controller::builtin_registry().find("random_walk")->make;
  d.params = kParams;
  d.states = kStates;
  EXPECT_EQ(check_descriptor(d),
            "behaviour 'code_made': parameter 'spacing': default 3.000000 is outside [min, max] = [0.100000, "
            "2.000000]");
  Registry registry;
  EXPECT_THROW(registry.add(d), std::logic_error);
  d.params = std::span<const ParamSpec>(kParams, 1);
  EXPECT_EQ(check_descriptor(d), "");
  static constexpr ParamSpec kTwice[] = {{"gain", 1.0, 0.0, 2.0, ""}, {"gain", 1.0, 0.0, 2.0, ""}};
  d.params = kTwice;
  EXPECT_EQ(check_param_table(d), "behaviour 'code_made': parameter 'gain' twice");
  d.params = std::span<const ParamSpec>(kParams, 1);
  static constexpr StateSpec kBadColour[] = {{0, "alone", "grey"}};
  d.states = kBadColour;
  EXPECT_EQ(check_states(d), "behaviour 'code_made': state 'alone': colour 'grey' is not \"#rrggbb\"");
  static constexpr StateSpec kSameValue[] = {{0, "alone", "#888888"}, {0, "near", "#2ca02c"}};
  d.states = kSameValue;
  EXPECT_EQ(check_states(d), "behaviour 'code_made': state value 0 twice");
  static constexpr StateSpec kNegative[] = {{-1, "alone", "#888888"}};
  d.states = kNegative;
  EXPECT_EQ(check_states(d), "behaviour 'code_made': state 'alone' has value -1 (< 0)");
  // Every built-in passes.
  for (const char* name : {"paper", "random_walk"}) {
    const Descriptor* b = controller::builtin_registry().find(name);
    ASSERT_NE(b, nullptr) << name;
    EXPECT_EQ(check_descriptor(*b), "") << name;
  }
}

}  // namespace
}  // namespace swarmform::behaviour
