// P3 (BENCHMARKS.md): the world library with N robots and N controllers in one process, timed.
//
//   bench_inprocess [--scenario bench/inprocess/field.yaml] [--robots 1000] [--behaviour
//   paper|random_walk|...]
//                   [--ticks 100] [--warmup 10] [--samples 3] [--seed 1]
//
// Each sample builds a fresh in-process harness (harness: the same World, controllers and
// RunSession metrics as swarm_inprocess --no-record), runs `warmup` ticks, then times `ticks` ticks of
// Harness::step with a monotonic clock. Then one more timed pass drives the same parts by hand (World,
// controllers, RunSession: the harness's tick order) to split the tick into controllers, world and session.
// Prints one JSON line on stdout:
//   {"robots":N,"behaviour":...,"ticks":T,"samples":[robot-ticks/s...],"best":...,"median":...,
//    "split_us_per_robot_tick":{"controllers":..,"world":..,"session":..},"messages_per_robot":..}
// The harness is single-threaded: the figure is one core's.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/world/perception_bytes.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace {

using namespace swarmform;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Split {
  double controllers = 0.0, world = 0.0, session = 0.0;  // seconds
};

// The harness's tick, by hand, timed in three parts (no kills: the benchmark schedules none).
Split timed_split(const world::Scenario& scenario, int warmup, int ticks, double& messages_per_robot) {
  world::World w(scenario);
  w.defer_perceptions(true);  // as the harness does: the medium and the sonars are timed with the controllers
  world::RunSession session(w, world::RunOptions{"", "in-process"});
  std::vector<std::unique_ptr<controller::Controller>> controllers;
  controllers.reserve(scenario.robots.size());
  for (RobotId id = 0; id < scenario.robots.size(); ++id) {
    controllers.push_back(controller::make_controller(scenario.mission, id));
  }
  Split split;
  std::size_t heard = 0;
  std::vector<Command> commands(controllers.size());
  world::World::PerceptionCopy copy;  // as the harness's workers do
  for (int t = 0; t < warmup + ticks; ++t) {
    const bool timed = t >= warmup;
    auto t0 = Clock::now();
    for (RobotId id = 0; id < controllers.size(); ++id) {
      if (w.alive(id)) commands[id] = controllers[id]->step(w.copy_perception(id, copy));
    }
    const double c = seconds_since(t0);
    t0 = Clock::now();
    for (RobotId id = 0; id < controllers.size(); ++id) {
      if (!w.alive(id)) continue;
      const auto verdict = w.apply_command(id, commands[id]);
      if (verdict != world::CommandVerdict::Ok) session.record_command_verdict(id, verdict);
    }
    w.step();
    const double s = seconds_since(t0);
    t0 = Clock::now();
    session.record_tick();
    const double r = seconds_since(t0);
    if (timed) {
      split.controllers += c;
      split.world += s;
      split.session += r;
      for (RobotId id = 0; id < controllers.size(); ++id) heard += w.perception(id).messages.size();
    }
  }
  messages_per_robot =
      static_cast<double>(heard) / (static_cast<double>(ticks) * static_cast<double>(controllers.size()));
  return split;
}

// FNV-1a over every bit the world shows the robots (pose, ultrasonics, messages with their bytes) and the
// contact onsets at every tick of one fresh run: two builds that print the same digest ran the same
// simulation bit for bit.
std::uint64_t run_digest(const world::Scenario& scenario, int ticks, std::uint64_t& contact_onsets) {
  std::uint64_t h = 1469598103934665603ULL;
  auto put = [&h](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ULL;
  };
  harness::Harness run(scenario);
  for (int t = 0; t < ticks; ++t) {
    run.step();
    const world::ContactCounts contacts = run.world().last_contacts();
    put(&contacts, sizeof contacts);
    contact_onsets += contacts.robot_robot + contacts.robot_obstacle;
    for (RobotId id = 0; id < run.world().robot_count(); ++id) {
      world::put_perception_bytes(run.world().perception(id), put);
    }
  }
  return h;
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_inprocess: robot-ticks per second of the world library with N robots and N controllers in one "
      "process (BENCHMARKS.md, P3). Prints one JSON line."};
  std::string scenario_path = "bench/inprocess/field.yaml";
  std::size_t robots = 1000;
  std::string behaviour = "paper";
  int ticks = 100, warmup = 10, samples = 3;
  std::uint64_t seed = 1;
  bool no_split = false;
  bool digest = false;
  app.add_option("--scenario", scenario_path, "scenario file (YAML)")->capture_default_str();
  app.add_option("--robots", robots, "robots (random placement at the default density)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000}))
      ->capture_default_str();
  app.add_option("--behaviour", behaviour, "controller: paper, random_walk, diffusion or phototaxis")
      ->check(CLI::IsMember({"paper", "random_walk", "diffusion", "phototaxis"}))
      ->capture_default_str();
  app.add_option("--ticks", ticks, "timed ticks per sample")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--warmup", warmup, "untimed ticks first")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--samples", samples, "fresh runs timed")->check(CLI::Range(1, 100))->capture_default_str();
  app.add_option("--seed", seed, "placement seed")->capture_default_str();
  app.add_flag("--no-split", no_split, "skip the timed pass that splits controllers / world / session");
  app.add_flag(
      "--digest", digest,
      "also print \"digest\": a hash of everything the robots perceived over warmup + ticks ticks of "
      "one more run (compares two builds bit for bit)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    world::ScenarioOverrides ov;
    ov.robots = robots;
    ov.seed = seed;
    ov.behaviour = behaviour;
    world::Scenario scenario =
        world::load_scenario(scenario_path, ov, swarmform::controller::builtin_registry());
    scenario.kills.clear();

    std::vector<double> rates;
    for (int k = 0; k < samples; ++k) {
      harness::Harness h(scenario);
      for (int t = 0; t < warmup; ++t) h.step();
      const auto t0 = Clock::now();
      for (int t = 0; t < ticks; ++t) h.step();
      const double s = seconds_since(t0);
      rates.push_back(static_cast<double>(ticks) * static_cast<double>(robots) / s);
      std::fprintf(stderr, "bench_inprocess: N=%zu %s sample %d: %.0f robot-ticks/s\n", robots,
                   behaviour.c_str(), k + 1, rates.back());
    }
    nlohmann::ordered_json j;
    j["robots"] = robots;
    j["behaviour"] = behaviour;
    j["ticks"] = ticks;
    j["warmup"] = warmup;
    j["samples"] = rates;
    j["best"] = *std::max_element(rates.begin(), rates.end());
    j["median"] = median_of(rates);
    if (!no_split) {
      double messages = 0.0;
      const Split sp = timed_split(scenario, warmup, ticks, messages);
      const double per = 1e6 / (static_cast<double>(ticks) * static_cast<double>(robots));
      j["split_us_per_robot_tick"] = {
          {"controllers", sp.controllers * per}, {"world", sp.world * per}, {"session", sp.session * per}};
      j["messages_per_robot"] = messages;
    }
    if (digest) {
      char hex[17];
      std::uint64_t onsets = 0;
      std::snprintf(hex, sizeof hex, "%016llx",
                    static_cast<unsigned long long>(run_digest(scenario, warmup + ticks, onsets)));
      j["digest"] = hex;
      j["digest_contact_onsets"] = onsets;
    }
    std::cout << j.dump() << std::endl;
    return 0;
  } catch (const InputError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bench_inprocess: " << e.what() << "\n";
    return 1;
  }
}
