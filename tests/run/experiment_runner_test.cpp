// A behaviour's experiment run by RunSession on a real World (no controllers: the test applies the commands):
// it sees every tick from 0 with the truth and the deaths, and its metrics and outcome reach summary.json;
// one that breaks its declaration or throws is named in the summary, never taken at its word; a behaviour
// without one gets outcome none. Its own summary fields and its formation reach summary.json and the graph
// watch; the world measures no shape of its own: the paper's shape keys are its experiment's. Also the
// registry's refusal of inconsistent experiment declarations.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "behaviour/descriptor_check.hpp"
#include "behaviour/registry.hpp"
#include "behaviour/shape_metrics.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "tests/support/paper_columns.hpp"
#include "world_server/run/recording_format.hpp"
#include "world_server/run/run_end.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using Json = nlohmann::json;

// How the test experiment concludes.
enum class Ending {
  Honest,
  UndeclaredOutcome,
  Throws,
  DoneAtSeven,
  Fields,
  ClashingField,
  UndeclaredField,
  WrongKind
};
Ending g_ending = Ending::Honest;

constexpr std::array kMetrics = {behaviour::MetricSpec{"ticks_seen", "observe calls"},
                                 behaviour::MetricSpec{"deaths_seen", "ids in Truth::died"},
                                 behaviour::MetricSpec{"first_x_of_robot_0", "m"},
                                 behaviour::MetricSpec{"never", "a metric not reached"}};
constexpr std::array<std::string_view, 2> kOutcomes = {"saw_a_death", "saw_none"};
// In an order other than the one conclude returns them in (Ending::Fields): summary.json follows this one.
// `never_given` is never returned: null in every summary.
constexpr std::array kSummary = {
    behaviour::SummarySpec{"first_tick", behaviour::SummaryKind::Tick, "a tick"},
    behaviour::SummarySpec{"never_given", behaviour::SummaryKind::Count, "never returned"},
    behaviour::SummarySpec{"spread", behaviour::SummaryKind::Number, "m"},
    behaviour::SummarySpec{"trail", behaviour::SummaryKind::Series, "a series"},
    behaviour::SummarySpec{"not_reached", behaviour::SummaryKind::Tick, "returned null"},
    behaviour::SummarySpec{"lagging", behaviour::SummaryKind::Ids, "robot ids"},
};

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
  // Formed from tick 5 on (observed ticks 0..4 before it), with an error of 0.25.
  experiment::Formation formation() const override {
    if (g_ending != Ending::Fields || ticks_ < 6) return {};
    return {Tick{5}, 0.25};
  }
  experiment::Result conclude() override {
    experiment::Result r;
    r.metrics = {static_cast<double>(ticks_), static_cast<double>(deaths_), first_x_,
                 std::numeric_limits<double>::quiet_NaN()};
    r.outcome = g_ending == Ending::UndeclaredOutcome ? "great" : deaths_ > 0 ? "saw_a_death" : "saw_none";
    if (g_ending == Ending::Fields) {
      r.summary = {{"trail", std::vector<experiment::SeriesPoint>{{1, 0.5}, {2, 0.25}}},
                   {"first_tick", std::int64_t{3}},
                   {"spread", 1.5},
                   {"not_reached", std::monostate{}},
                   {"lagging", std::vector<std::int64_t>{2, 3}}};
    }
    if (g_ending == Ending::ClashingField) r.summary = {{"ticks", std::int64_t{1}}};
    if (g_ending == Ending::UndeclaredField) r.summary = {{"spread", 1.0}, {"surprise", std::int64_t{1}}};
    if (g_ending == Ending::WrongKind) r.summary = {{"first_tick", 3.0}};  // a tick given as a number
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
                   .summary = kSummary,
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

// Up to 20 ticks (run_complete decides, as both front ends do) of 4 robots driving ahead, each reporting its
// id as its label (so the communication graph has robots to watch); robot 1 dies at tick 10. Returns
// summary.json's text. `extra`: more lines of the scenario.
Scenario scenario(const std::string& behaviour, const std::string& extra = "") {
  // The scenario points into the registry's entries: it lives as long as the test program.
  static behaviour::Registry& registry = *[] {
    auto* r = new behaviour::Registry;
    r->add(kJudged);
    r->add(kUnjudged);
    return r;
  }();
  return parse_scenario_text("behaviour: " + behaviour + R"(
arena: {centre: [0.0, 0.0], width: 10.0, height: 10.0, walls: true}
robots: {count: 4, region: {centre: [0.0, 0.0], width: 4.0, height: 4.0}}
seed: 3
max_ticks: 20
)" + extra,
                             "<experiment_runner_test>", {}, registry);
}

std::string run_text(const std::string& behaviour, const std::string& extra = "") {
  const Scenario s = scenario(behaviour, extra);
  World world(s);
  RunSession session(world, {});
  Command ahead;
  ahead.left_speed = ahead.right_speed = 0.05;
  for (Tick t = 0; !run_complete(session, world.tick(), s.max_ticks); ++t) {
    if (t == 10) {
      world.kill(1);
      session.record_death(1);
    }
    for (RobotId id = 0; id < 4; ++id) {
      Command c = ahead;
      testing::set_label(c.telemetry, static_cast<std::int32_t>(id));
      world.apply_command(id, c);
    }
    world.step();
    session.record_tick();
  }
  return session.finish(0.0);
}

Json run(const std::string& behaviour, const std::string& extra = "") {
  return Json::parse(run_text(behaviour, extra));
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

// Done before the goal's last move (goal_events.hpp) is done at a goal that will move: the run goes on, and
// the experiment's done from the move's tick on ends it.
TEST(ExperimentRunner, DoneBeforeTheGoalsLastMoveDoesNotEndTheRun) {
  g_ending = Ending::DoneAtSeven;
  const Json j =
      run("judged", "goal: {x: 1.0, y: 1.0, radius: 0.5}\nevents: [{tick: 12, goal: [2.0, -2.0]}]\n");
  g_ending = Ending::Honest;
  EXPECT_EQ(j["ticks"], 13);
  EXPECT_EQ(j["end_reason"], "completed");
}

TEST(ExperimentRunner, ABehaviourWithoutOneHasOutcomeNone) {
  const Json j = run("unjudged");
  EXPECT_EQ(j["outcome"], "none");
  EXPECT_TRUE(j["success"].is_null());
  EXPECT_TRUE(j["behaviour_metrics"].is_object());
  EXPECT_TRUE(j["behaviour_metrics"].empty());
}

// The experiment's own keys come after the world's generic metrics (after max_components), in its order, its
// series last on one line; its formation switches the world's watch of the communication graph on.
TEST(ExperimentRunner, ItsSummaryFieldsAndFormationReachTheSummary) {
  g_ending = Ending::Fields;
  Json j = run("judged");
  EXPECT_EQ(j["first_tick"], 3);
  EXPECT_EQ(j["spread"], 1.5);
  EXPECT_TRUE(j.contains("not_reached") && j["not_reached"].is_null());
  EXPECT_EQ(j["lagging"], Json::parse("[2, 3]"));
  EXPECT_EQ(j["trail"], Json::parse("[[1, 0.5], [2, 0.25]]"));
  EXPECT_TRUE(j.contains("never_given") && j["never_given"].is_null());  // declared, not returned: null
  EXPECT_GE(j["max_components"], 1);                                     // watched from tick 5
  // The declared order (not the order returned), the series last; the same keys in the same order when
  // conclude returns none of them (Ending::Honest).
  const auto keys_of = [](const std::string& text) {
    const auto parsed = nlohmann::ordered_json::parse(text);  // not a temporary: items() refers to it
    std::vector<std::string> keys;
    for (const auto& [key, value] : parsed.items()) keys.push_back(key);
    return keys;
  };
  const std::vector<std::string> keys = keys_of(run_text("judged"));
  const auto at = [&](const std::string& k) { return std::find(keys.begin(), keys.end(), k) - keys.begin(); };
  EXPECT_EQ(at("first_tick"), at("max_components") + 1);
  EXPECT_EQ(at("never_given"), at("first_tick") + 1);
  EXPECT_EQ(at("spread"), at("never_given") + 1);
  EXPECT_EQ(at("not_reached"), at("spread") + 1);
  EXPECT_EQ(at("lagging"), at("not_reached") + 1);
  EXPECT_LT(at("lagging"), at("outcome"));
  EXPECT_EQ(keys.back(), "trail");
  g_ending = Ending::Honest;
  const std::string honest = run_text("judged");
  EXPECT_EQ(keys_of(honest), keys);
  for (const char* key : {"first_tick", "never_given", "spread", "trail", "not_reached", "lagging"}) {
    EXPECT_TRUE(Json::parse(honest)[key].is_null()) << key;
  }

  g_ending = Ending::ClashingField;
  j = run("judged");
  g_ending = Ending::Honest;
  EXPECT_EQ(j["outcome"], "experiment_failed");
  EXPECT_EQ(j["experiment_error"],
            "experiment of behaviour 'judged' returned summary field 'ticks', a key the world writes");
  EXPECT_EQ(j["ticks"], 20);                        // the world's, not the experiment's
  EXPECT_EQ(run("unjudged")["max_components"], 0);  // no experiment, no formation: the graph is never watched
}

// A summary field the descriptor does not declare, or a value of another kind than declared, is a broken
// declaration: experiment_failed naming the key and the behaviour, every declared key still there (null).
TEST(ExperimentRunner, AnUndeclaredSummaryFieldOrAWrongKindIsNamedNotTaken) {
  g_ending = Ending::UndeclaredField;
  Json j = run("judged");
  EXPECT_EQ(j["outcome"], "experiment_failed");
  EXPECT_EQ(
      j["experiment_error"],
      "experiment of behaviour 'judged' returned summary field 'surprise', which its descriptor does not "
      "declare (experiment.summary)");
  EXPECT_FALSE(j.contains("surprise"));
  EXPECT_TRUE(j.contains("spread") && j["spread"].is_null());  // not taken either: the verdict is void
  EXPECT_TRUE(j.contains("trail") && j["trail"].is_null());

  g_ending = Ending::WrongKind;
  j = run("judged");
  g_ending = Ending::Honest;
  EXPECT_EQ(j["outcome"], "experiment_failed");
  EXPECT_EQ(
      j["experiment_error"],
      "experiment of behaviour 'judged' returned summary field 'first_tick' as a number, declared tick");
  EXPECT_TRUE(j["first_tick"].is_null());
}

// The world measures no shape: a behaviour that needs a shape and a goal but brings no experiment gets no
// formation_tick, shape error, distortion, stuck robots or live formation; the paper gets them all from its
// experiment.
TEST(ExperimentRunner, TheShapeKeysAreThePaperExperimentsNotTheWorlds) {
  const behaviour::Descriptor& paper = controller::paper_descriptor();
  behaviour::Descriptor shaped = kUnjudged;
  shaped.name = "shaped";
  shaped.needs_shape = true;
  shaped.needs_goal = true;
  shaped.shape_rules = paper.shape_rules;
  shaped.params = paper.params;
  shaped.states = paper.states;
  const auto dir = std::filesystem::temp_directory_path() / "experiment_runner_test";
  std::filesystem::create_directories(dir);
  std::ofstream((dir / "line3.txt").string()) << "0 1 2\n";
  experiment::Formation formation;  // the run's last, as world_server hands it to the viewer's frame
  const auto summary = [&](const std::string& behaviour) {
    behaviour::Registry registry;
    registry.add(paper);
    registry.add(shaped);
    // Three robots standing on the line's places, still: formed once at rest (10 ticks), far from the goal.
    const Scenario s =
        parse_scenario_text("behaviour: " + behaviour + "\nshape: " + (dir / "line3.txt").string() + R"(
grid_spacing: 1.0
arena: {centre: [0.0, 0.0], width: 20.0, height: 10.0, walls: true}
robots: {poses: [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]}
goal: {x: 8.0, y: 0.0, radius: 0.5}
max_ticks: 20
)",
                            "<experiment_runner_test>", {}, registry);
    World world(s);
    RunSession session(world, {});
    while (!run_complete(session, world.tick(), s.max_ticks)) {
      for (RobotId id = 0; id < 3; ++id) {
        Command still;  // each holds its place's label (the communication graph's robots)
        testing::set_label(still.telemetry, static_cast<std::int32_t>(id));
        world.apply_command(id, still);
      }
      world.step();
      session.record_tick();
    }
    formation = session.formation();
    return Json::parse(session.finish(0.0));
  };
  const Json mine = summary("shaped");
  for (const char* key : {"formation_tick", "shape_error_at_formation", "goal_tick", "shape_error_at_goal",
                          "peak_distortion", "path_length", "arrived", "stuck_robots", "distortion"}) {
    EXPECT_FALSE(mine.contains(key)) << key;
  }
  EXPECT_EQ(mine["outcome"], "none");
  EXPECT_EQ(mine["max_components"], 0);
  EXPECT_FALSE(formation.tick);  // the view shows no formation either
  const Json p = summary("paper");
  EXPECT_EQ(p["formation_tick"], 10);
  EXPECT_LT(p["shape_error_at_formation"].get<double>(), 1e-9);
  EXPECT_TRUE(p["goal_tick"].is_null());
  EXPECT_EQ(p["outcome"], "formed_not_arrived");
  EXPECT_EQ(p["stuck_robots"], Json::array());
  EXPECT_EQ(p["distortion"].size(), 11u);              // ticks 10..20
  EXPECT_EQ(p["max_components"], 1);                   // watched from the experiment's formation tick
  EXPECT_EQ(formation.tick, std::optional<Tick>(10));  // the live view's formation line
  ASSERT_TRUE(formation.error);
  EXPECT_EQ(*formation.error, p["shape_error_at_formation"].get<double>());
}

// `world_server --check`'s summary_template has the keys of the run's summary.json, in its order (the
// launcher checks --expect against it), and every key but the experiment's declared ones is one the registry
// keeps an experiment from declaring (behaviour::world_summary_key): the reserved list cannot drift from
// make_summary.
TEST(ExperimentRunner, TheSummaryTemplateHasTheRunsKeys) {
  const auto keys_of = [](const nlohmann::ordered_json& j) {
    std::vector<std::string> keys;
    for (const auto& [key, value] : j.items()) keys.push_back(key);
    return keys;
  };
  for (const char* name : {"judged", "unjudged"}) {
    g_ending = Ending::Honest;
    const nlohmann::ordered_json run = nlohmann::ordered_json::parse(run_text(name));
    const nlohmann::ordered_json tmpl = summary_template(scenario(name), "in-process");
    EXPECT_EQ(keys_of(tmpl), keys_of(run)) << name;
    for (const std::string& key : keys_of(tmpl)) {
      const bool declared = std::any_of(kSummary.begin(), kSummary.end(),
                                        [&](const behaviour::SummarySpec& f) { return f.key == key; });
      EXPECT_TRUE(declared != behaviour::world_summary_key(key)) << key;
    }
  }
  // The paper's declaration is the shape measurement's table, in the order it returns its fields, each of the
  // declared kind.
  const auto& declared = controller::paper_descriptor().experiment.summary;
  shape_metrics::Measures m;
  m.formation_tick = 4;
  m.shape_error_at_formation = 0.5;
  m.motion_start_tick = 5;
  m.motion_ticks_minimum = 10.0;
  m.goal_tick = 9;
  m.shape_error_at_goal = 0.25;
  m.peak_distortion = m.mean_distortion = 0.3;
  m.distortion = {{4, 0.5}};
  m.stuck_robots = {1};
  const auto fields = shape_metrics::summary_fields(m);
  ASSERT_EQ(fields.size(), declared.size());
  for (std::size_t k = 0; k < fields.size(); ++k) {
    EXPECT_EQ(fields[k].key, declared[k].key);
    EXPECT_FALSE(std::holds_alternative<std::monostate>(fields[k].value)) << fields[k].key;
    EXPECT_TRUE(behaviour::summary_value_fits(declared[k].kind, fields[k].value)) << fields[k].key;
  }
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
  // Summary keys: empty, not lower_case, repeated, one the world writes, or declared without a make.
  const auto summary_refusal = [&](std::span<const behaviour::SummarySpec> summary) {
    behaviour::Descriptor bad = kJudged;
    bad.experiment.summary = summary;
    const std::string why = behaviour::check_experiment(bad);
    behaviour::Registry refusing;
    EXPECT_THROW(refusing.add(bad), std::logic_error) << why;
    return why;
  };
  static constexpr std::array kEmpty = {behaviour::SummarySpec{"", behaviour::SummaryKind::Tick, ""}};
  static constexpr std::array kUpper = {
      behaviour::SummarySpec{"Goal Tick", behaviour::SummaryKind::Tick, ""}};
  static constexpr std::array kRepeated = {
      behaviour::SummarySpec{"goal_tick", behaviour::SummaryKind::Tick, ""},
      behaviour::SummarySpec{"goal_tick", behaviour::SummaryKind::Count, ""}};
  static constexpr std::array kWorlds = {
      behaviour::SummarySpec{"alive_at_end", behaviour::SummaryKind::Count, ""}};
  static constexpr std::array kFront = {
      behaviour::SummarySpec{"input_dropped", behaviour::SummaryKind::Count, ""}};
  EXPECT_EQ(summary_refusal(kEmpty),
            "behaviour 'judged': experiment: summary key '' is not a lower_case name");
  EXPECT_EQ(summary_refusal(kUpper),
            "behaviour 'judged': experiment: summary key 'Goal Tick' is not a lower_case name");
  EXPECT_EQ(summary_refusal(kRepeated), "behaviour 'judged': experiment: summary key 'goal_tick' twice");
  EXPECT_EQ(summary_refusal(kWorlds),
            "behaviour 'judged': experiment: summary key 'alive_at_end' is one the world writes itself");
  EXPECT_EQ(summary_refusal(kFront),
            "behaviour 'judged': experiment: summary key 'input_dropped' is one the world writes itself");
  // In a mixed swarm a group's experiment writes its keys beside the group's first_id and count.
  static constexpr std::array kGroups = {behaviour::SummarySpec{"count", behaviour::SummaryKind::Count, ""}};
  EXPECT_EQ(summary_refusal(kGroups),
            "behaviour 'judged': experiment: summary key 'count' is one the world writes itself");
  d = kUnjudged;
  d.experiment.summary = kSummary;
  EXPECT_EQ(
      behaviour::check_experiment(d),
      "behaviour 'unjudged': experiment: metrics, summary keys, outcomes or success declared without a make");
  EXPECT_THROW(registry.add(d), std::logic_error);
  d = kJudged;
  EXPECT_EQ(behaviour::check_experiment(d), "");  // kSummary itself is fine
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
  // The known columns (behaviour/known_columns.hpp) may be declared, each with its meaning; a label only by a
  // behaviour that forms a shape.
  static constexpr std::array kKnown = {behaviour::TelemetryColumn{"leader", ""},
                                        behaviour::TelemetryColumn{"seen", ""},
                                        behaviour::TelemetryColumn{"parent", ""}};
  static constexpr std::array kLabel = {behaviour::TelemetryColumn{"label", ""}};
  d.telemetry = kKnown;
  EXPECT_EQ(behaviour::check_telemetry(d), "");
  const behaviour::KnownColumns known = behaviour::KnownColumns::of(&d);
  EXPECT_EQ(known.leader, 0);
  EXPECT_EQ(known.parent, 2);
  EXPECT_EQ(known.label, -1);
  EXPECT_EQ(known.net_force, -1);
  d.telemetry = kLabel;
  EXPECT_EQ(
      behaviour::check_telemetry(d),
      "behaviour 'unjudged': telemetry column 'label' is a place in a shape: the behaviour must declare "
      "needs_shape");
  d.needs_shape = true;
  EXPECT_EQ(behaviour::check_telemetry(d), "");
  // The paper's columns are where its controller writes them.
  const behaviour::KnownColumns paper = behaviour::KnownColumns::of(&controller::paper_descriptor());
  EXPECT_EQ(paper.label, controller::kPaperColumns.label);
  EXPECT_EQ(paper.parent, controller::kPaperColumns.parent);
  EXPECT_EQ(paper.leader, controller::kPaperColumns.leader);
  EXPECT_EQ(paper.net_force, controller::kPaperColumns.net_force);
  const Telemetry said{.state = 0, .extra = controller::paper_telemetry(3, 7, true, 0.25), .events = {}};
  EXPECT_EQ(paper.label_of(said), 3);
  EXPECT_EQ(paper.parent_of(said), 7);
  EXPECT_TRUE(paper.leader_of(said));
  EXPECT_EQ(paper.net_force_of(said), 0.25);
  // Nothing reported yet, or a value that is no id: none.
  EXPECT_EQ(paper.label_of(Telemetry{}), -1);
  EXPECT_FALSE(paper.leader_of(Telemetry{}));
  const Telemetry odd{.state = 0, .extra = {2.5, -3.0, 0.0, 0.0}, .events = {}};
  EXPECT_EQ(paper.label_of(odd), -1);
  EXPECT_EQ(paper.parent_of(odd), -1);
}

}  // namespace
}  // namespace swarmform::world
