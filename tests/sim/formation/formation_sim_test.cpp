// The shape formation in the real world library (Bullet, cone ultrasonics, the medium) with N controllers in
// one process: every shape of shapes/ forms from 5 random starts with shape error <= 0.1 grid units and no
// robot-robot contact; spares stay out of the way; a robot dying during formation, with and without a spare.
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

#include "common/robot_state.hpp"
#include "world_server/harness/harness.hpp"
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
  return world::parse_scenario_text(yaml, "<formation_sim_test>");
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
  while (h.world().tick() < max_ticks && !h.metrics().formation_tick) {
    h.step();
    for (const auto& r : h.world().robots()) {
      for (const auto& e : r.telemetry.events) {
        if (e.rfind("label_lost", 0) == 0) ++o.conflicts;
        if (e.rfind("label_freed", 0) == 0) ++o.frees;
      }
    }
  }
  o.formation_tick = h.metrics().formation_tick;
  o.shape_error = h.metrics().shape_error_at_formation;
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
                  r.alive ? "alive" : "dead", r.telemetry.state, r.telemetry.label, r.pose.x, r.pose.y);
    out += line;
  }
  return out;
}

int state_of(const harness::Harness& h, RobotId id) {
  return h.world().robots()[id].telemetry.state;
}
int label_of(const harness::Harness& h, RobotId id) {
  return h.world().robots()[id].telemetry.label;
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

}  // namespace
}  // namespace swarmform
