// A behaviour's experiment run by RunSession on a real World (no controllers: the test applies the commands):
// it sees every tick from 0 with the truth and the deaths, and its metrics and outcome reach summary.json;
// one that breaks its declaration or throws is named in the summary, never taken at its word; a behaviour
// without one gets outcome none. Also the registry's refusal of inconsistent experiment declarations.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "behaviour/descriptor_check.hpp"
#include "behaviour/registry.hpp"
#include "world_server/run/run_end.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using Json = nlohmann::json;

// How the test experiment concludes.
enum class Ending { Honest, UndeclaredOutcome, Throws, DoneAtSeven };
Ending g_ending = Ending::Honest;

constexpr std::array kMetrics = {behaviour::MetricSpec{"ticks_seen", "observe calls"},
                                 behaviour::MetricSpec{"deaths_seen", "ids in Truth::died"},
                                 behaviour::MetricSpec{"first_x_of_robot_0", "m"},
                                 behaviour::MetricSpec{"never", "a metric not reached"}};
constexpr std::array<std::string_view, 2> kOutcomes = {"saw_a_death", "saw_none"};

class CountingExperiment final : public experiment::Experiment {
 public:
  void init(const Mission&, std::size_t robots) override { robots_ = robots; }
  void observe(const experiment::Truth& t) override {
    if (t.tick != ticks_) throw std::runtime_error("tick " + std::to_string(t.tick) + " out of order");
    if (t.robots.size() != robots_ || t.robots[0].telemetry == nullptr) throw std::runtime_error("no truth");
    if (ticks_ == 0) first_x_ = t.robots[0].pose.x;
    deaths_ += t.died.size();
    for (RobotId id : t.died) {
      if (t.robots[id].alive) throw std::runtime_error("a death of a live robot");
    }
    ++ticks_;
    if (g_ending == Ending::Throws && ticks_ == 5) throw std::runtime_error("on purpose");
  }
  bool done() const override { return g_ending == Ending::DoneAtSeven && ticks_ > 7; }
  experiment::Result conclude() override {
    experiment::Result r;
    r.metrics = {static_cast<double>(ticks_), static_cast<double>(deaths_), first_x_,
                 std::numeric_limits<double>::quiet_NaN()};
    r.outcome = g_ending == Ending::UndeclaredOutcome ? "great" : deaths_ > 0 ? "saw_a_death" : "saw_none";
    return r;
  }

 private:
  std::size_t robots_ = 0;
  Tick ticks_ = 0;
  std::size_t deaths_ = 0;
  double first_x_ = 0.0;
};

std::unique_ptr<controller::Controller> no_controller() {
  return nullptr;
}
std::unique_ptr<experiment::Experiment> make_counting() {
  return std::make_unique<CountingExperiment>();
}

const behaviour::Descriptor kJudged{
    .name = "judged",
    .summary = "",
    .params = {},
    .states = {},
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &no_controller,
    .sensors = 0,
    .experiment = {.metrics = kMetrics,
                   .outcomes = kOutcomes,
                   .success = "saw_a_death",
                   .make = &make_counting},
};
const behaviour::Descriptor kUnjudged{
    .name = "unjudged",
    .summary = "",
    .params = {},
    .states = {},
    .telemetry = {},
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &no_controller,
    .sensors = 0,
    .experiment = {},
};

// Up to 20 ticks (run_complete decides, as both front ends do) of 4 robots driving ahead; robot 1 dies at
// tick 10. Returns summary.json's content.
Json run(const std::string& behaviour) {
  behaviour::Registry registry;
  registry.add(kJudged);
  registry.add(kUnjudged);
  const Scenario s = parse_scenario_text("behaviour: " + behaviour + R"(
arena: {centre: [0.0, 0.0], width: 10.0, height: 10.0, walls: true}
robots: {count: 4, region: {centre: [0.0, 0.0], width: 4.0, height: 4.0}}
seed: 3
max_ticks: 20
)",
                                         "<experiment_runner_test>", {}, registry);
  World world(s);
  RunSession session(world, {});
  Command ahead;
  ahead.left_speed = ahead.right_speed = 0.05;
  for (Tick t = 0; !run_complete(session, world.tick(), s.max_ticks); ++t) {
    if (t == 10) {
      world.kill(1);
      session.record_death(1);
    }
    for (RobotId id = 0; id < 4; ++id) world.apply_command(id, ahead);
    world.step();
    session.record_tick();
  }
  return Json::parse(session.finish(0.0));
}

TEST(ExperimentRunner, SeesEveryTickAndTheDeathsAndItsResultReachesTheSummary) {
  g_ending = Ending::Honest;
  const Json j = run("judged");
  EXPECT_EQ(j["outcome"], "saw_a_death");
  EXPECT_EQ(j["success"], true);
  const Json& m = j["behaviour_metrics"];
  EXPECT_EQ(m["ticks_seen"], 21);  // tick 0 and the 20 steps
  EXPECT_EQ(m["deaths_seen"], 1);
  EXPECT_TRUE(m["first_x_of_robot_0"].is_number());
  EXPECT_TRUE(m["never"].is_null());
  EXPECT_FALSE(j.contains("experiment_error"));
}

TEST(ExperimentRunner, AnUndeclaredOutcomeOrAThrowIsNamedNotTaken) {
  g_ending = Ending::UndeclaredOutcome;
  Json j = run("judged");
  EXPECT_EQ(j["outcome"], "experiment_failed");
  EXPECT_EQ(j["success"], false);
  EXPECT_TRUE(j["behaviour_metrics"]["ticks_seen"].is_null());
  EXPECT_EQ(j["experiment_error"],
            "experiment of behaviour 'judged' returned outcome 'great', not one of: saw_a_death, saw_none");

  g_ending = Ending::Throws;
  j = run("judged");
  g_ending = Ending::Honest;
  EXPECT_EQ(j["outcome"], "experiment_failed");
  EXPECT_EQ(j["experiment_error"], "experiment of behaviour 'judged' threw at tick 4: on purpose");
  EXPECT_EQ(j["ticks"], 20);  // the run itself went on
}

TEST(ExperimentRunner, AnExperimentThatSaysDoneEndsTheRunAtTheNextTick) {
  g_ending = Ending::DoneAtSeven;
  const Json j = run("judged");
  g_ending = Ending::Honest;
  EXPECT_EQ(j["ticks"], 8);
  EXPECT_EQ(j["end_reason"], "completed");
  EXPECT_EQ(j["behaviour_metrics"]["ticks_seen"], 9);
  EXPECT_EQ(run("judged")["end_reason"], "max_ticks");
}

TEST(ExperimentRunner, ABehaviourWithoutOneHasOutcomeNone) {
  const Json j = run("unjudged");
  EXPECT_EQ(j["outcome"], "none");
  EXPECT_TRUE(j["success"].is_null());
  EXPECT_TRUE(j["behaviour_metrics"].is_object());
  EXPECT_TRUE(j["behaviour_metrics"].empty());
}

TEST(ExperimentRunner, TheRegistryRefusesAnInconsistentDeclaration) {
  behaviour::Descriptor d = kJudged;
  d.experiment.success = "won";
  EXPECT_EQ(
      behaviour::check_experiment(d),
      "behaviour 'judged': experiment: success 'won' is not one of its outcomes (saw_a_death, saw_none)");
  behaviour::Registry registry;
  EXPECT_THROW(registry.add(d), std::logic_error);
  static constexpr std::array kBadName = {behaviour::MetricSpec{"Ticks Seen", ""}};
  d = kJudged;
  d.experiment.metrics = kBadName;
  EXPECT_NE(behaviour::check_experiment(d).find("metric 'Ticks Seen' is not a lower_case name"),
            std::string::npos);
  d = kUnjudged;
  // The modelled sensors are taken; a bit no sensor has is refused, named.
  d.sensors = behaviour::kProximity | behaviour::kGround | behaviour::kLight | behaviour::kLidar |
              behaviour::kBattery;
  EXPECT_EQ(behaviour::check_sensors(d), "");
  d.sensors = behaviour::kProximity | (1U << 5);
  EXPECT_EQ(behaviour::check_sensors(d),
            "behaviour 'unjudged' declares sensor bit 5, which this world does not model yet "
            "(docs/behaviour-api.md, \"Sensors and actuators\")");
  EXPECT_THROW(registry.add(d), std::logic_error);
  // A telemetry column named as one of robots.csv's own, twice, or not lower_case would make the file
  // ambiguous: refused, named.
  static constexpr std::array kLeds = {behaviour::TelemetryColumn{"leds", ""}};
  static constexpr std::array kTwice = {behaviour::TelemetryColumn{"seen", ""},
                                        behaviour::TelemetryColumn{"seen", ""}};
  static constexpr std::array kFine = {behaviour::TelemetryColumn{"seen", ""},
                                       behaviour::TelemetryColumn{"heard_2", ""}};
  d = kUnjudged;
  d.telemetry = kLeds;
  EXPECT_EQ(behaviour::check_telemetry(d),
            "behaviour 'unjudged': telemetry column 'leds' is one of robots.csv's own columns");
  EXPECT_THROW(registry.add(d), std::logic_error);
  d.telemetry = kTwice;
  EXPECT_EQ(behaviour::check_telemetry(d), "behaviour 'unjudged': telemetry column 'seen' twice");
  d.telemetry = kFine;
  EXPECT_EQ(behaviour::check_telemetry(d), "");
}

}  // namespace
}  // namespace swarmform::world
