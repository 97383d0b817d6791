// The shape formation in the real world library (Bullet, cone ultrasonics, the medium) with N controllers in
// one process: every shape of shapes/ forms from 5 random starts with shape error <= 0.1 grid units and no
// robot-robot contact; spares stay out of the way; a robot dying during formation, with and without a spare.
//
// The formation rows, each with a deadline: the would-be seed killed during the election, a robot dead
// before taking a label (no spare), a silent agent and a holder that falls silent, the square's symmetric
// deadlock (seed 13), no robot-obstacle contact while forming beside a dead body, the paper's pace.
//
// FORMATION_SIM_REPORT=1 prints one line per run (shape, seed, formation_tick, shape error) for the notes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"
#include "robot_agent/controller/robot_state.hpp"
#include "tests/sim/measured.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform {
namespace {

const std::string kRepo = SWARMFORM_REPO_DIR;

// Formation only: no obstacles, a roomy arena, a long ready_timeout (the motion phases must not start
// moving before the last robot is ready: the metric is taken at formation).
world::Scenario scenario(const std::string& shape, std::uint64_t seed, std::optional<std::size_t> robots,
                         Tick max_ticks, const std::string& extra_yaml = "") {
  std::string yaml = "shape: " + kRepo + "/shapes/" + shape +
                     "\n"
                     "arena: {centre: [0.0, 0.0], width: 16.0, height: 16.0}\n"
                     "goal: {x: 6.0, y: 0.0, radius: 0.5}\n"
                     "seed: " +
                     std::to_string(seed) + "\nmax_ticks: " + std::to_string(max_ticks) +
                     "\n"
                     "controller: {ready_timeout: 100000}\n";
  if (robots) yaml += "robots: {count: " + std::to_string(*robots) + "}\n";
  yaml += extra_yaml;
  return world::parse_scenario_text(yaml, "<formation_sim_test>", {},
                                    swarmform::controller::builtin_registry());
}

struct Outcome {
  std::optional<Tick> formation_tick;
  std::optional<double> shape_error;
  std::uint32_t robot_contacts = 0;
  std::uint32_t obstacle_contacts = 0;
  int conflicts = 0;  // label_lost events (a conflict settled by id)
  int frees = 0;      // label_freed events (a silent holder's label freed)
};

Outcome run_to_formation(harness::Harness& h, Tick max_ticks) {
  Outcome o;
  while (h.world().tick() < max_ticks && !measured(h).formation_tick) {
    h.step();
    for (const auto& r : h.world().robots()) {
      for (const auto& e : r.telemetry.events) {
        if (e.rfind("label_lost", 0) == 0) ++o.conflicts;
        if (e.rfind("label_freed", 0) == 0) ++o.frees;
      }
    }
  }
  o.formation_tick = measured(h).formation_tick;
  o.shape_error = measured(h).shape_error_at_formation;
  o.robot_contacts = h.metrics().collisions_robot_robot;
  o.obstacle_contacts = h.metrics().collisions_robot_obstacle;
  return o;
}

void report(const std::string& what, std::uint64_t seed, const Outcome& o) {
  if (!std::getenv("FORMATION_SIM_REPORT")) return;
  std::printf(
      "FORMATION %s seed %llu formation_tick %lld shape_error %.4f robot_contacts %u obstacle_contacts %u "
      "conflicts %d frees %d\n",
      what.c_str(), static_cast<unsigned long long>(seed),
      o.formation_tick ? static_cast<long long>(*o.formation_tick) : -1LL,
      o.shape_error ? *o.shape_error : -1.0, o.robot_contacts, o.obstacle_contacts, o.conflicts, o.frees);
}

// Where everyone stands: printed when a run did not form, to see why.
std::string snapshot(const harness::Harness& h) {
  std::string out;
  for (const auto& r : h.world().robots()) {
    char line[160];
    std::snprintf(line, sizeof line, "  robot %u %s state %d label %d at (%.2f, %.2f)\n", r.id,
                  r.alive ? "alive" : "dead", r.telemetry.state,
                  controller::kPaperColumns.label_of(r.telemetry), r.pose.x, r.pose.y);
    out += line;
  }
  return out;
}

int state_of(const harness::Harness& h, RobotId id) {
  return h.world().robots()[id].telemetry.state;
}
int label_of(const harness::Harness& h, RobotId id) {
  return controller::kPaperColumns.label_of(h.world().robots()[id].telemetry);
}

// ---- Every shape, five seeds ----

struct ShapeCase {
  std::string shape;
  std::uint64_t seed;
};

class EveryShape : public ::testing::TestWithParam<ShapeCase> {};

TEST_P(EveryShape, ReachesReadyWithSmallShapeErrorAndNoContact) {
  const auto& c = GetParam();
  constexpr Tick kMaxTicks = 6000;
  harness::Harness h(scenario(c.shape, c.seed, std::nullopt, kMaxTicks));
  const Outcome o = run_to_formation(h, kMaxTicks);
  report(c.shape, c.seed, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << c.shape << " seed " << c.seed << " never formed\n"
                                            << snapshot(h);
  ASSERT_TRUE(o.shape_error.has_value());
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
}

std::vector<ShapeCase> every_shape_cases() {
  std::vector<ShapeCase> out;
  std::vector<std::string> shapes;
  for (const auto& e : std::filesystem::directory_iterator(kRepo + "/shapes")) {
    if (e.path().extension() == ".txt") shapes.push_back(e.path().filename().string());
  }
  std::sort(shapes.begin(), shapes.end());
  for (const auto& s : shapes) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) out.push_back({s, seed});
  }
  return out;
}

std::string case_name(const ::testing::TestParamInfo<ShapeCase>& param_info) {
  const auto& shape = param_info.param.shape;
  return shape.substr(0, shape.find('.')) + "_seed" + std::to_string(param_info.param.seed);
}

INSTANTIATE_TEST_SUITE_P(Shapes, EveryShape, ::testing::ValuesIn(every_shape_cases()), case_name);

// ---- Spares ----

TEST(FormationSim, ThreeSparesStaySearchingAndKeepClear) {
  constexpr Tick kMaxTicks = 6000;
  harness::Harness h(scenario("triangle.txt", 11, 12, kMaxTicks));
  const Outcome o = run_to_formation(h, kMaxTicks);
  report("triangle+3spares", 11, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  int searching = 0;
  for (RobotId id = 0; id < 12; ++id) {
    if (state_of(h, id) == static_cast<int>(RobotState::Searching)) {
      ++searching;
      EXPECT_EQ(label_of(h, id), -1);
    }
  }
  EXPECT_EQ(searching, 3);
}

// ---- A lossy, noisy medium ----

TEST(FormationSim, FormsUnderTwentyPercentLossAndSensorNoise) {
  constexpr Tick kMaxTicks = 6000;
  harness::Harness h(scenario("square.txt", 21, std::nullopt, kMaxTicks,
                              "packet_loss: 0.2\nnoise: {range: 0.02, bearing: 0.05, ultrasonic: 0.01}\n"));
  const Outcome o = run_to_formation(h, kMaxTicks);
  report("square,loss0.2+noise", 21, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
}

// ---- A robot dying during formation ----

// Steps until some robot other than the seed is moving to its label; returns it.
std::optional<RobotId> first_mover(harness::Harness& h, Tick max_ticks) {
  while (h.world().tick() < max_ticks) {
    h.step();
    for (RobotId id = 0; id < h.world().robot_count(); ++id) {
      if (state_of(h, id) == static_cast<int>(RobotState::Moving) && label_of(h, id) > 0) return id;
    }
  }
  return std::nullopt;
}

TEST(FormationSim, ADeadRobotsLabelIsTakenByASpare) {
  constexpr Tick kMaxTicks = 8000;
  harness::Harness h(scenario("triangle.txt", 12, 10, kMaxTicks));
  const auto victim = first_mover(h, kMaxTicks);
  ASSERT_TRUE(victim.has_value());
  const int label = label_of(h, *victim);
  h.kill(*victim);
  const Outcome o = run_to_formation(h, kMaxTicks);
  report("triangle+1spare,kill", 12, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  int holders = 0;
  for (RobotId id = 0; id < h.world().robot_count(); ++id) {
    if (id != *victim && label_of(h, id) == label) ++holders;
  }
  EXPECT_EQ(holders, 1) << "label " << label << " should have been taken over";
}

TEST(FormationSim, WithNoSpareTheShapeCompletesWithoutTheDeadRobot) {
  constexpr Tick kMaxTicks = 8000;
  harness::Harness h(scenario("triangle.txt", 13, std::nullopt, kMaxTicks));
  const auto victim = first_mover(h, kMaxTicks);
  ASSERT_TRUE(victim.has_value());
  const int label = label_of(h, *victim);
  h.kill(*victim);
  const Outcome o = run_to_formation(h, kMaxTicks);
  report("triangle,kill,no spare", 13, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  // The world judges formation from the poses (the survivors at rest in their places), which can come before
  // the controllers' barrier passes: the barrier must still pass without the dead robot's label, every
  // survivor reporting Ready, before the deadline.
  const auto survivors_ready = [&] {
    int ready = 0;
    for (RobotId id = 0; id < h.world().robot_count(); ++id) {
      if (id != *victim && state_of(h, id) >= static_cast<int>(RobotState::Ready)) ++ready;
    }
    return ready;
  };
  while (h.world().tick() < kMaxTicks && survivors_ready() < static_cast<int>(h.world().robot_count()) - 1) {
    h.step();
  }
  for (RobotId id = 0; id < h.world().robot_count(); ++id) {
    if (id != *victim) {
      EXPECT_NE(label_of(h, id), label);
    }
  }
  EXPECT_EQ(survivors_ready(), static_cast<int>(h.world().robot_count()) - 1) << snapshot(h);
}

// The V's arm ends in label 7, whose only grid neighbour is label 5 (shapes/v.txt). Both holders die on
// their way: label 3's holder frees 5, but nobody holds a label of 7's grid, so under the grid rule alone 7
// stayed held by a dead robot and the barrier never passed (seen under 20 % loss, where formation is slower
// and a random kill finds both arms' robots still moving: scenarios/untuned/slalom_loss20_noise.yaml
// --shape shapes/v.txt --seed 1103 --kill 8@366 --kill 1@817). A freed label passes its watch on.
TEST(FormationSim, ALabelBeyondAFreedOneIsFreedWhenItsHolderDies) {
  constexpr Tick kMaxTicks = 3000;
  harness::Harness h(scenario("v.txt", 1, std::nullopt, kMaxTicks));
  const auto mover_of = [&](int label) -> std::optional<RobotId> {
    for (RobotId id = 0; id < h.world().robot_count(); ++id) {
      if (state_of(h, id) == static_cast<int>(RobotState::Moving) && label_of(h, id) == label) return id;
    }
    return std::nullopt;
  };
  std::optional<RobotId> five, seven;
  while (h.world().tick() < kMaxTicks && !(five && seven)) {
    h.step();
    five = mover_of(5);
    seven = mover_of(7);
  }
  ASSERT_TRUE(five && seven) << snapshot(h);
  h.kill(*five);
  h.kill(*seven);
  const auto survivors_ready = [&] {
    int ready = 0;
    for (RobotId id = 0; id < h.world().robot_count(); ++id) {
      if (id != *five && id != *seven && state_of(h, id) >= static_cast<int>(RobotState::Ready)) ++ready;
    }
    return ready;
  };
  const int survivors = static_cast<int>(h.world().robot_count()) - 2;
  while (h.world().tick() < kMaxTicks && survivors_ready() < survivors) h.step();
  EXPECT_EQ(survivors_ready(), survivors) << snapshot(h);
}

// ---- A way out of every formation phase (robot_agent/README.md, shape formation) ----

world::Scenario paper_scenario() {
  return world::load_scenario(kRepo + "/scenarios/paper.yaml", {}, swarmform::controller::builtin_registry());
}

// Counts the events of one kind over a whole run.
int count_events(const harness::Harness& h, const std::string& kind) {
  int n = 0;
  for (const auto& r : h.world().robots()) {
    if (!r.alive) continue;  // a dead robot's last telemetry stays
    for (const auto& e : r.telemetry.events) {
      if (e.rfind(kind, 0) == 0) ++n;
    }
  }
  return n;
}

// True when every live robot that speaks (a silent one has no state to report) is Ready or beyond: the
// controllers' own barrier has passed.
bool speakers_ready(const harness::Harness& h) {
  for (const auto& r : h.world().robots()) {
    if (!r.alive || !r.last_broadcast_tick) continue;
    if (r.telemetry.state < static_cast<int>(RobotState::Ready)) return false;
  }
  return true;
}

// Runs to formation (the world's judgement from the poses) and until the controllers' barrier has passed
// (which can come later: the robots stand in place before they know it), counting events of `kind`.
Outcome run_counting(harness::Harness& h, Tick max_ticks, const std::string& kind, int& count) {
  Outcome o;
  while (h.world().tick() < max_ticks && !(measured(h).formation_tick && speakers_ready(h))) {
    h.step();
    count += count_events(h, kind);
  }
  o.formation_tick = measured(h).formation_tick;
  o.shape_error = measured(h).shape_error_at_formation;
  o.robot_contacts = h.metrics().collisions_robot_robot;
  o.obstacle_contacts = h.metrics().collisions_robot_obstacle;
  return o;
}

// Robot 5 is the would-be seed of the paper run (seed 1: the robot nearest the arena origin). Killed while
// the election floods, its minimum used to circulate among the survivors for ever.
class SeedKilled : public ::testing::TestWithParam<Tick> {};

TEST_P(SeedKilled, TheSurvivorsElectAnotherSeedAndForm) {
  const Tick kill_tick = GetParam();
  constexpr Tick kMaxTicks = 1500;
  harness::Harness h(paper_scenario());
  while (h.world().tick() < kill_tick) h.step();
  h.kill(5);
  int seeds = 0;
  const Outcome o = run_counting(h, kMaxTicks, "seed_elected", seeds);
  report("paper,kill 5@" + std::to_string(kill_tick), 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << "no formation by " << kMaxTicks << "\n" << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  EXPECT_GE(seeds, 1);
  int ready = 0;
  for (RobotId id = 0; id < 9; ++id) {
    if (id != 5 && state_of(h, id) >= static_cast<int>(RobotState::Ready)) ++ready;
  }
  EXPECT_EQ(ready, 8);
}

INSTANTIATE_TEST_SUITE_P(Issue17, SeedKilled, ::testing::Values(Tick{1}, Tick{10}, Tick{25}),
                         [](const ::testing::TestParamInfo<Tick>& i) {
                           return "at_tick_" + std::to_string(i.param);
                         });

// The seed dies at once after taking label 0. The robots that heard its offers in its first message took
// labels of its grid; they free label 0 after label_timeout and offer it again, and with no spare it is
// abandoned: the shape forms without it. (The seed dying before anyone joined is a unit test:
// paper_controller_test.cpp, the searchers free label 0 and re-elect.)
TEST(FormationSim, TheSeedDyingOnceElectedStillForms) {
  constexpr Tick kMaxTicks = 1500;
  harness::Harness h(paper_scenario());
  std::optional<RobotId> seed;
  while (!seed && h.world().tick() < kMaxTicks) {
    h.step();
    for (RobotId id = 0; id < 9; ++id) {
      if (label_of(h, id) == 0) seed = id;
    }
  }
  ASSERT_TRUE(seed.has_value());
  h.kill(*seed);
  int abandoned = 0;
  const Outcome o = run_counting(h, kMaxTicks, "label_abandoned 0", abandoned);
  report("paper,kill the seed once elected", 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  EXPECT_GE(abandoned, 1);
}

// Robot 2 dies at tick 10, before labels are given out, and there is no spare: one label is never taken.
// It is given up (freed untaken, then abandoned), and the barrier passes with the 8 live robots.
TEST(FormationSim, ALabelNobodyTakesIsAbandonedAndTheBarrierPasses) {
  constexpr Tick kMaxTicks = 1500;
  harness::Harness h(paper_scenario());
  while (h.world().tick() < 10) h.step();
  h.kill(2);
  int abandoned = 0;
  const Outcome o = run_counting(h, kMaxTicks, "label_abandoned", abandoned);
  report("paper,kill 2@10", 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  EXPECT_GE(abandoned, 1);
}

// A controller that behaves as the paper's until `silent_from`, then stays alive and says nothing: no
// wheel speeds, no message, no telemetry (a silent or broken agent).
class SilentAfter final : public controller::Controller {
 public:
  SilentAfter(const Mission& mission, RobotId self, Tick silent_from)
      : inner_(controller::make_controller(mission, self)), silent_from_(silent_from) {
    inner_->init(mission, self);
  }
  void init(const Mission& mission, RobotId self) override { inner_->init(mission, self); }
  Command step(const Perception& p) override {
    if (p.tick >= silent_from_) return Command{};
    return inner_->step(p);
  }
  void reset() override { inner_->reset(); }

 private:
  std::unique_ptr<controller::Controller> inner_;
  Tick silent_from_;
};

// A silent agent from the start (alive, a body in the world, never a word): its label is never taken.
TEST(FormationSim, ASilentAgentsLabelIsAbandoned) {
  constexpr Tick kMaxTicks = 1500;
  const auto sc = paper_scenario();
  harness::Harness h(sc);
  constexpr RobotId kSilent = 3;
  h.set_controller(kSilent, std::make_unique<SilentAfter>(sc.mission, kSilent, Tick{0}));
  int abandoned = 0;
  const Outcome o = run_counting(h, kMaxTicks, "label_abandoned", abandoned);
  report("paper,silent agent 3", 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  EXPECT_GE(abandoned, 1);
}

// A holder that falls silent on its way (alive, its body standing where it stopped): its label is freed
// after label_timeout and, with no spare, abandoned; the barrier passes with the others.
TEST(FormationSim, AHolderThatFallsSilentLosesItsLabel) {
  constexpr Tick kMaxTicks = 1500;
  const auto sc = paper_scenario();
  harness::Harness h(sc, {std::getenv("SILENT_DIR") ? std::getenv("SILENT_DIR") : ""});
  const auto victim = first_mover(h, kMaxTicks);
  ASSERT_TRUE(victim.has_value());
  h.set_controller(*victim, std::make_unique<SilentAfter>(sc.mission, *victim, Tick{0}));
  int freed = 0;
  const Outcome o = run_counting(h, kMaxTicks, "label_freed", freed);
  report("paper,holder falls silent", 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_GE(freed, 1);
}

// Two movers heading for one gap between reached robots mirrored each other (robots 1 and 6 swapped sides
// every other tick for ever): the yield rule gives one the right of way.
TEST(FormationSim, TheSquareSeed13FormsNoSymmetricDeadlock) {
  constexpr Tick kMaxTicks = 3000;
  world::ScenarioOverrides overrides;
  overrides.shape_file = kRepo + "/shapes/square.txt";
  overrides.seed = 13;
  harness::Harness h(world::load_scenario(kRepo + "/scenarios/paper.yaml", overrides,
                                          swarmform::controller::builtin_registry()));
  const Outcome o = run_to_formation(h, kMaxTicks);
  report("paper arena,square", 13, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
}

// A robot killed at tick 100, while the others move to their places: they keep clear of its body with the
// ultrasonic sensors (it is no neighbour they hear). No robot-obstacle contact before Ready.
TEST(FormationSim, MoversKeepClearOfADeadBody) {
  constexpr Tick kMaxTicks = 1500;
  harness::Harness h(paper_scenario());
  while (h.world().tick() < 100) h.step();
  h.kill(5);
  const Outcome o = run_to_formation(h, kMaxTicks);
  report("paper,kill 5@100", 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_EQ(o.obstacle_contacts, 0u);
  EXPECT_EQ(o.robot_contacts, 0u);
}

// A mover pinned in a pocket whose way out is a detour (the arrow, seed 2, robot 0 killed at tick 300: it
// stood for ever between the body and two reached robots): stuck with a side committed, it backs off to a
// random point and tries again.
TEST(FormationSim, AMoverPinnedInAPocketTakesADetour) {
  constexpr Tick kMaxTicks = 3000;
  world::ScenarioOverrides overrides;
  overrides.shape_file = kRepo + "/shapes/arrow.txt";
  overrides.seed = 2;
  harness::Harness h(world::load_scenario(kRepo + "/scenarios/paper.yaml", overrides,
                                          swarmform::controller::builtin_registry()));
  while (h.world().tick() < 300) h.step();
  h.kill(0);
  int detours = 0;
  const Outcome o = run_counting(h, kMaxTicks, "detour", detours);
  report("paper arena,arrow,kill 0@300", 2, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  EXPECT_EQ(o.obstacle_contacts, 0u);
  EXPECT_GE(detours, 1);
}

// The paper's pace: its motion starts at tick 607, so the shape must be formed by then.
TEST(FormationSim, ThePaperRunFormsByTick607) {
  harness::Harness h(paper_scenario());
  const Outcome o = run_to_formation(h, 1500);
  report("paper", 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.formation_tick, 607);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  EXPECT_EQ(o.obstacle_contacts, 0u);
}

// Scale: a 12 x 12 block (144 labels) with as many robots in an open arena. With the default label timeout
// (40 ticks) its 144 holders' heartbeats did not fit the messages and starved in key order: live robots'
// labels were freed as dead (the 20 x 20 block: ~50 times per 100 ticks) and the block had not formed after
// 6000 ticks. With the timeout scaled to the shape and the changed entries sent in turn
// (robot_agent/README.md, "Large shapes") it forms (tick 1634), and no live holder's label is freed.
TEST(FormationSim, ATwelveByTwelveBlockFormsWithNoLiveHoldersLabelFreed) {
  constexpr Tick kMaxTicks = 4000;
  const std::string yaml = "shape: " + kRepo +
                           "/scenarios/scale/block_12x12.txt\n"
                           "arena: {centre: [0.0, 0.0], width: 40.0, height: 40.0}\n"
                           "goal: {x: 10.0, y: 0.0, radius: 0.5}\n"
                           "seed: 1\nmax_ticks: 4000\n"
                           "controller: {ready_timeout: 100000}\n";
  harness::Harness h(world::parse_scenario_text(yaml, "<formation_sim_test>", {},
                                                swarmform::controller::builtin_registry()));
  int live_frees = 0;
  Outcome o;
  while (h.world().tick() < kMaxTicks && !measured(h).formation_tick) {
    h.step();
    for (const auto& r : h.world().robots()) {
      for (const auto& e : r.telemetry.events) {
        if (e.rfind("label_freed", 0) == 0 && e.find("holder") != std::string::npos) ++live_frees;
        if (e.rfind("label_lost", 0) == 0) ++o.conflicts;
      }
    }
  }
  o.formation_tick = measured(h).formation_tick;
  o.shape_error = measured(h).shape_error_at_formation;
  o.robot_contacts = h.metrics().collisions_robot_robot;
  o.frees = live_frees;
  report("block_12x12", 1, o);
  ASSERT_TRUE(o.formation_tick.has_value()) << snapshot(h);
  EXPECT_LE(*o.shape_error, 0.1);
  EXPECT_EQ(o.robot_contacts, 0u);
  EXPECT_EQ(live_frees, 0);
}

}  // namespace
}  // namespace swarmform
