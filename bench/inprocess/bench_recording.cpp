// The cost of recording the sensors' readings (readings.csv, docs/recording-format.md) per robot-tick,
// against the recording without them (robots.csv alone), measured alternating in the same run (BENCHMARKS.md;
// scripts/ bench --parts recording runs it). A world of the scenario's robots, with the behaviour's sensors,
// steps with fixed wheel speeds (no controllers: the step is the world's alone); each block of ticks is
// recorded by one of two writers into its own temporary folder, robots.csv alone (A) or robots.csv and
// readings.csv (B), the world stepping between the ticks either way. Blocks alternate A B, B A, ... so that
// the page cache, the disk and the other load fall on both alike.
//
//   bench_recording [--scenario bench/inprocess/sensors_field.yaml] [--behaviour diffusion] [--robots 256]
//                   [--ticks 100] [--rounds 6]
//
// Prints one JSON line on stdout: {"robots", "behaviour", "sensors" (readings.csv's columns), "ticks",
// "rounds", "us_per_robot_tick": {"step", "robots_csv", "with_readings"}, "ratio_recording" (B's recording /
// A's, the median of the rounds'), "ratio_tick" ((step + B) / (step + A), the median),
// "bytes_per_robot_tick":
// {"robots_csv", "readings_csv"}}.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "common/sensor_readings.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/recorder.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace {

using namespace swarmform;
using namespace swarmform::world;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Every robot drives a circle of its own radius: the readings change from tick to tick.
void drive(World& world) {
  for (RobotId id = 0; id < world.robot_count(); ++id) {
    Command c;
    c.left_speed = 0.05;
    c.right_speed = 0.02 + 0.0001 * static_cast<double>(id % 300);
    world.apply_command(id, c);
  }
}

struct Block {
  double step = 0.0;    // s, stepping the world
  double record = 0.0;  // s, the writer's calls
};

// `ticks` ticks of the world, each recorded by `writer` (with readings.csv when `readings`).
Block run_block(World& world, RecordingWriter& writer, bool readings, int ticks) {
  Block b;
  for (int t = 0; t < ticks; ++t) {
    drive(world);
    auto t0 = Clock::now();
    world.step();
    b.step += seconds_since(t0);
    t0 = Clock::now();
    if (readings) writer.write_readings(world.tick(), world);
    writer.write_rows(world.tick(), world.robots());
    b.record += seconds_since(t0);
  }
  const auto t0 = Clock::now();
  writer.flush();
  b.record += seconds_since(t0);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"the cost of recording the sensors' readings per robot-tick, against robots.csv alone"};
  std::string scenario_path = "bench/inprocess/sensors_field.yaml";
  std::string behaviour = "diffusion";
  std::size_t robots = 256;
  int ticks = 100;
  int rounds = 6;
  app.add_option("--scenario", scenario_path, "scenario file (its floor, lights, obstacles)");
  app.add_option("--behaviour", behaviour, "a built-in that declares sensors: diffusion or phototaxis");
  app.add_option("--robots", robots, "robot count")->check(CLI::Range(1, 100000));
  app.add_option("--ticks", ticks, "ticks a block")->check(CLI::Range(1, 100000));
  app.add_option("--rounds", rounds, "rounds of two blocks (A B or B A)")->check(CLI::Range(1, 1000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    ScenarioOverrides ov;
    ov.robots = robots;
    ov.behaviour = behaviour;
    Scenario scenario = load_scenario(scenario_path, ov, swarmform::controller::builtin_registry());
    scenario.kills.clear();
    const std::uint32_t sensors = scenario.behaviour->sensors;
    if (sensors == 0) {
      std::cerr << "bench_recording: behaviour '" << behaviour
                << "' declares no sensor: nothing to compare\n";
      return 2;
    }
    World world(scenario);
    const fs::path dir =
        fs::temp_directory_path() / ("swarmform-bench-recording-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    RecordingWriter plain((dir / "a").string());
    RecordingWriter with((dir / "b").string(), {}, sensors);
    run_block(world, plain, false, 5);  // warm: the pool, the buffers, the files
    run_block(world, with, true, 5);
    const auto size = [&](const char* sub, const char* name) { return fs::file_size(dir / sub / name); };
    const std::uintmax_t a0 = size("a", "robots.csv");
    const std::uintmax_t r0 = size("b", "readings.csv");
    std::vector<double> ratio_recording, ratio_tick;
    double step = 0.0, rec_a = 0.0, rec_b = 0.0;
    for (int r = 0; r < rounds; ++r) {
      Block a, b;
      if (r % 2 == 0) {
        a = run_block(world, plain, false, ticks);
        b = run_block(world, with, true, ticks);
      } else {
        b = run_block(world, with, true, ticks);
        a = run_block(world, plain, false, ticks);
      }
      ratio_recording.push_back(b.record / a.record);
      // The round's mean step under each: the two blocks' steps differ by the host's load, not by the
      // recording, and would otherwise swamp a difference of a few per cent.
      const double mean_step = 0.5 * (a.step + b.step);
      ratio_tick.push_back((mean_step + b.record) / (mean_step + a.record));
      step += a.step + b.step;
      rec_a += a.record;
      rec_b += b.record;
      std::fprintf(stderr,
                   "bench_recording: round %d: recording %.3f us (robots.csv) %.3f us (+ readings.csv) "
                   "a robot-tick, ratio %.2f; tick ratio %.3f\n",
                   r + 1, a.record * 1e6 / (ticks * static_cast<double>(robots)),
                   b.record * 1e6 / (ticks * static_cast<double>(robots)), ratio_recording.back(),
                   ratio_tick.back());
    }
    const double robot_ticks =
        static_cast<double>(ticks) * static_cast<double>(rounds) * static_cast<double>(robots);
    nlohmann::ordered_json j;
    j["robots"] = robots;
    j["behaviour"] = behaviour;
    j["sensors"] = sensor_reading_columns(sensors).size();
    j["ticks"] = ticks;
    j["rounds"] = rounds;
    j["us_per_robot_tick"] = {{"step", step * 1e6 / (2 * robot_ticks)},
                              {"robots_csv", rec_a * 1e6 / robot_ticks},
                              {"with_readings", rec_b * 1e6 / robot_ticks}};
    j["ratio_recording"] = median_of(ratio_recording);
    j["ratio_tick"] = median_of(ratio_tick);
    j["bytes_per_robot_tick"] = {
        {"robots_csv", static_cast<double>(size("a", "robots.csv") - a0) / robot_ticks},
        {"readings_csv", static_cast<double>(size("b", "readings.csv") - r0) / robot_ticks}};
    fs::remove_all(dir);
    std::cout << j.dump() << std::endl;
    return 0;
  } catch (const InputError& e) {
    std::cerr << "bench_recording: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bench_recording: " << e.what() << "\n";
    return 1;
  }
}
