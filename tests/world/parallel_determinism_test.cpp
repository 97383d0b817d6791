// The worker pool (world_server/world/parallel_for.hpp) must not change a run: the same scenario stepped by
// the in-process harness with 1 and with 2 workers gives bit-identical poses, ultrasonic readings and
// received messages (sender, range, bearing, bytes) at every tick. The scenario has everything that draws
// random numbers or runs on the pool: ultrasonic noise, packet loss, range/bearing noise, occlusion, paper
// controllers that talk, an obstacle to sense. A race or a schedule-dependent draw would show as a
// difference within a few ticks. 200 robots: the world's sensing loops use the pool only from
// 2 x kMinRobotsPerWorker robots.
#include <array>
#include <atomic>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/world/parallel_for.hpp"
#include "world_server/world/perception_bytes.hpp"

namespace swarmform {
namespace {

constexpr const char* kScenario = R"(
shape: SHAPES/triangle.txt
arena: {centre: [0.0, 0.0], width: 16.0, height: 16.0, walls: true}
obstacles: [{type: box, centre: [1.0, 1.0], size: [0.6, 0.6]}]
robots: {count: 200, region: {centre: [0.0, 0.0], width: 11.0, height: 11.0}}
behaviour: paper
goal: {x: 4.0, y: 0.0, radius: 0.5}
seed: 11
max_ticks: 1000
packet_loss: 0.2
occlusion: true
noise: {range: 0.02, bearing: 0.05, ultrasonic: 0.01}
)";

// The optional sensors on the pool: 200 robots of each built-in that declares them, with every sensor's
// noise, among obstacles, a floor and lights.
constexpr const char* kSensorsScenario = R"(
behaviour: BEHAVIOUR
arena: {centre: [0.0, 0.0], width: 16.0, height: 16.0, walls: true}
obstacles: [{type: box, centre: [1.0, 1.0], size: [0.6, 0.6]}, {type: cylinder, centre: [-2, 0], radius: 0.3}]
robots: {count: 200, region: {centre: [0.0, 0.0], width: 11.0, height: 11.0}}
seed: 12
max_ticks: 1000
lights: [{position: [3, 3], height: 0.2, intensity: 2}, {position: [-4, -3], height: 0.1, intensity: 3}]
floor: {grey: 0.8, regions: [{type: circle, centre: [0, 0], radius: 2, grey: 0.1}]}
battery: {capacity: 5, idle: 0.05, moving: 10}
noise: {proximity: 0.05, light: 0.05, ground: 0.05, ultrasonic: 0.01}
)";

world::Scenario scenario(const char* yaml = kScenario, const std::string& behaviour = "") {
  std::string text = yaml;
  if (const auto at = text.find("BEHAVIOUR"); at != std::string::npos) text.replace(at, 9, behaviour);
  if (text.find("SHAPES") == std::string::npos) {
    return world::parse_scenario_text(text, "<parallel_determinism_test>", {},
                                      swarmform::controller::builtin_registry());
  }
  text.replace(text.find("SHAPES"), 6, std::string(SWARMFORM_REPO_DIR) + "/shapes");
  return world::parse_scenario_text(text, "<parallel_determinism_test>", {},
                                    swarmform::controller::builtin_registry());
}

// Every bit of what the world shows the robots, tick after tick, as raw bytes.
std::vector<unsigned char> trace(std::size_t workers, int ticks, const world::Scenario& s = scenario()) {
  parallel::set_worker_count(workers);
  harness::Harness h(s);
  std::vector<unsigned char> out;
  auto put = [&out](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    out.insert(out.end(), b, b + n);
  };
  for (int t = 0; t < ticks; ++t) {
    h.step();
    for (RobotId id = 0; id < h.world().robot_count(); ++id) {
      world::put_perception_bytes(h.world().perception(id), put);
    }
  }
  parallel::set_worker_count(0);
  return out;
}

TEST(ParallelDeterminism, OneAndTwoWorkersGiveTheSameRunBitForBit) {
  const auto serial = trace(1, 40);
  const auto two = trace(2, 40);
  static_assert(200 >= 2 * parallel::kMinRobotsPerWorker);
  ASSERT_GT(serial.size(), 100000u);  // messages flowed (not just poses)
  ASSERT_EQ(serial.size(), two.size());
  EXPECT_EQ(0, std::memcmp(serial.data(), two.data(), serial.size()));
  // And a second 2-worker run replays the first (no state left in the pool).
  EXPECT_EQ(two, trace(2, 40));
}

TEST(ParallelDeterminism, OptionalSensorsGiveTheSameRunBitForBitOnAnyWorkerCount) {
  for (const char* behaviour : {"diffusion", "phototaxis"}) {
    const world::Scenario s = scenario(kSensorsScenario, behaviour);
    const auto serial = trace(1, 40, s);
    const auto two = trace(2, 40, s);
    ASSERT_EQ(serial.size(), two.size()) << behaviour;
    EXPECT_EQ(0, std::memcmp(serial.data(), two.data(), serial.size())) << behaviour;
  }
}

TEST(ParallelFor, EveryIndexOnceAndExceptionsReachTheCaller) {
  parallel::set_worker_count(2);
  std::vector<int> hits(10007, 0);
  parallel::for_range(hits.size(), [&](std::size_t b, std::size_t e, std::size_t w) {
    ASSERT_LT(w, 2u);
    for (std::size_t i = b; i < e; ++i) ++hits[i];
  });
  for (int h : hits) ASSERT_EQ(h, 1);
  EXPECT_THROW(parallel::for_range(100,
                                   [](std::size_t b, std::size_t, std::size_t) {
                                     if (b == 0) throw std::runtime_error("body failed");
                                   }),
               std::runtime_error);
  parallel::set_worker_count(0);
}

TEST(ParallelFor, FewerIndicesThanTwoGrainsRunAsOneSerialCall) {
  parallel::set_worker_count(2);
  std::mutex m;  // were the range split after all, a worker would append too
  std::vector<std::array<std::size_t, 3>> calls;
  const auto record = [&](std::size_t b, std::size_t e, std::size_t w) {
    std::lock_guard lock(m);
    calls.push_back({b, e, w});
  };
  parallel::for_range(127, record, 64);
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_EQ(calls[0], (std::array<std::size_t, 3>{0, 127, 0}));
  // At two grains the pool splits the range into chunks (~8 per worker).
  std::atomic<std::size_t> chunks{0};
  parallel::for_range(
      128, [&](std::size_t, std::size_t, std::size_t) { ++chunks; }, 64);
  EXPECT_GT(chunks.load(), 1u);
  parallel::set_worker_count(0);
}

}  // namespace
}  // namespace swarmform
