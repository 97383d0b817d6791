// The cost of each sensor per robot-tick (BENCHMARKS.md; scripts/bench --parts sensors runs it): the world
// library's sensors alone, each reading every robot of the scenario's placement on the world's worker pool
// (SWARMFORM_WORKERS, default 2) as World::step does, timed tick after tick with a monotonic clock.
//
//   bench_sensors [--scenario bench/inprocess/sensors_field.yaml] [--robots 1000] [--ticks 50] [--warmup 5]
//                 [--lidar-rays 682]
//
// Prints one JSON line on stdout: {"robots":N,"ticks":T,"lidar_rays":R,"us_per_robot_tick":{"ultrasonic":..,
// "proximity":..,"light":..,"ground":..,"lidar":..,"battery":..}}. The ultrasonics are every robot's; the
// others are paid only by a behaviour that declares them. The robots stand still: the figure is the reading's
// cost at the placement's density, not the physics'.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/world/battery.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/ground.hpp"
#include "world_server/world/lidar.hpp"
#include "world_server/world/light.hpp"
#include "world_server/world/proximity.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/spatial_grid.hpp"
#include "world_server/world/ultrasonic.hpp"

namespace {

using namespace swarmform;
using namespace swarmform::world;
using Clock = std::chrono::steady_clock;

// Microseconds a robot-tick of `sense` (one call reads every robot), over `ticks` calls after `warmup`.
double us_per_robot_tick(const std::function<void()>& sense, int warmup, int ticks, std::size_t robots) {
  for (int t = 0; t < warmup; ++t) sense();
  const auto t0 = Clock::now();
  for (int t = 0; t < ticks; ++t) sense();
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  return s * 1e6 / (static_cast<double>(ticks) * static_cast<double>(robots));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"the cost of each sensor per robot-tick"};
  std::string scenario_path = "bench/inprocess/sensors_field.yaml";
  std::size_t robots = 1000;
  int ticks = 50;
  int warmup = 5;
  std::uint32_t lidar_rays = LidarSpec{}.rays;
  app.add_option("--scenario", scenario_path, "scenario file (its floor, lights, obstacles)");
  app.add_option("--robots", robots, "robot count")->check(CLI::Range(1, 100000));
  app.add_option("--ticks", ticks, "timed ticks")->check(CLI::Range(1, 100000));
  app.add_option("--warmup", warmup, "untimed ticks first")->check(CLI::Range(0, 100000));
  app.add_option("--lidar-rays", lidar_rays, "the lidar's rays (default ARGoS's)")
      ->check(CLI::Range(1, 10000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    ScenarioOverrides ov;
    ov.robots = robots;
    Scenario s = load_scenario(scenario_path, ov, controller::builtin_registry());
    s.lidar.rays = lidar_rays;
    const std::vector<Obstacle> statics = static_obstacles(s);
    const std::vector<Pose2D>& poses = s.robots;
    const std::vector<char> alive(poses.size(), 1);
    SpatialGrid grid;
    grid.build(poses, 1.0);  // the world's cell (world.cpp kGridCell)

    Ultrasonic ultrasonic(statics, s.ultrasonic_noise_sd, s.seed);
    Proximity proximity(statics, s.proximity_noise, s.seed);
    LightSensors light(s.lights, statics, s.light_noise, s.seed);
    Ground ground(s.floor, s.arena_centre, s.arena_width, s.arena_height, s.ground_noise, s.seed);
    Lidar lidar(s.lidar, statics, s.lidar_noise, s.seed);
    Batteries batteries(s.battery.value_or(BatterySpec{.capacity = 1000.0}), poses.size(), s.tick_rate);
    std::vector<UltrasonicReading> sonar;
    std::vector<ProximityReading> infrared;
    std::vector<LightReading> lights;
    std::vector<GroundReading> floor_readings;
    std::vector<LidarScan> scans;

    nlohmann::json us;
    const std::size_t n = poses.size();
    us["ultrasonic"] =
        us_per_robot_tick([&] { ultrasonic.sense_all(poses, alive, grid, sonar); }, warmup, ticks, n);
    us["proximity"] =
        us_per_robot_tick([&] { proximity.sense_all(poses, alive, grid, infrared); }, warmup, ticks, n);
    us["light"] = us_per_robot_tick([&] { light.sense_all(poses, alive, grid, lights); }, warmup, ticks, n);
    us["ground"] =
        us_per_robot_tick([&] { ground.sense_all(poses, alive, floor_readings); }, warmup, ticks, n);
    us["lidar"] = us_per_robot_tick([&] { lidar.sense_all(poses, alive, grid, scans); }, warmup, ticks, n);
    us["battery"] = us_per_robot_tick(
        [&] {
          for (std::size_t i = 0; i < n; ++i) batteries.drain(i, poses[i], poses[i]);
        },
        warmup, ticks, n);
    const nlohmann::json out = {
        {"robots", n}, {"ticks", ticks}, {"lidar_rays", lidar_rays}, {"us_per_robot_tick", us}};
    std::cout << out.dump() << "\n";
    return 0;
  } catch (const InputError& e) {
    std::cerr << "bench_sensors: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bench_sensors: " << e.what() << "\n";
    return 1;
  }
}
