// swarm_inprocess: a whole run in one process (the world library + N controllers, no DDS), writing the same
// run directory as `swarm run`. For users who want a quick answer and for the large-N benchmarks.
//
// Exit codes: common/exit_codes.json (printed by --help).
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "behaviour/registry.hpp"
#include "common/exit_codes.hpp"
#include "common/input_error.hpp"
#include "harness/harness.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/param_flags.hpp"
#include "world_server/run/record_every_flag.hpp"
#include "world_server/run/recording_format.hpp"
#include "world_server/run/run_end.hpp"
#include "world_server/world/robot_groups.hpp"

namespace {

using namespace swarmform;
namespace fs = std::filesystem;

using namespace swarmform::exit_codes;

std::atomic<bool> g_interrupted{false};

// A behaviour that crashes (SIGSEGV, SIGBUS, SIGFPE, SIGILL) takes the whole process: say which robot and
// which behaviour before it goes. Only async-signal-safe calls here (write, signal, raise); the text is made
// before the run.
char g_behaviour_text[1024] = "";
std::size_t g_behaviour_text_size = 0;

void say(const char* text, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(2, text, n);
    if (w <= 0) return;
    text += w;
    n -= static_cast<std::size_t>(w);
  }
}
void say(const char* text) {
  say(text, std::strlen(text));
}

extern "C" void on_crash(int sig) {
  say("swarm_inprocess: ");
  const std::int64_t robot = harness::robot_being_stepped();
  if (robot >= 0) {
    char digits[24];
    std::size_t n = 0;
    for (std::int64_t v = robot; n == 0 || v > 0; v /= 10) digits[n++] = static_cast<char>('0' + v % 10);
    say("robot ");
    for (; n > 0; --n) say(&digits[n - 1], 1);
    say("'s ");
  } else {
    say("the run (no robot's controller was stepping) with ");
  }
  say(g_behaviour_text, g_behaviour_text_size);
  say(sig == SIGSEGV  ? " crashed (SIGSEGV)"
      : sig == SIGBUS ? " crashed (SIGBUS)"
      : sig == SIGFPE ? " crashed (SIGFPE)"
                      : " crashed (SIGILL)");
  say("; the run ends here, summary.json is not written\n");
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}
extern "C" void on_signal(int) {
  g_interrupted = true;
}

// "ID@TICK" -> Kill; throws InputError naming the flag.
world::Kill parse_kill(const std::string& text) {
  const auto at = text.find('@');
  const auto bad = [&] {
    return InputError("command line", 0, "--kill '" + text + "': expected ID@TICK, e.g. 3@900");
  };
  if (at == std::string::npos || at == 0 || at + 1 == text.size()) throw bad();
  try {
    std::size_t used_id = 0;
    std::size_t used_tick = 0;
    const std::string id = text.substr(0, at);
    const std::string tick = text.substr(at + 1);
    if (id[0] == '-' || tick[0] == '-') throw bad();
    const unsigned long long id_value = std::stoull(id, &used_id);
    const unsigned long long tick_value = std::stoull(tick, &used_tick);
    if (used_id != id.size() || used_tick != tick.size() || id_value > 0xffffffffULL) throw bad();
    return {static_cast<RobotId>(id_value), static_cast<Tick>(tick_value)};
  } catch (const std::logic_error&) {
    throw bad();
  }
}

// runs/<UTC yyyymmdd-hhmmss>[-k], unused.
std::string default_run_dir() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", &utc);
  std::string dir = std::string("runs/") + stamp;
  for (int k = 2; fs::exists(dir); ++k) dir = std::string("runs/") + stamp + "-" + std::to_string(k);
  return dir;
}

void point_latest_at(const std::string& run_dir) {
  const fs::path dir(run_dir);
  const fs::path latest = dir.parent_path() / "latest";
  std::error_code ec;
  fs::remove(latest, ec);
  fs::create_directory_symlink(dir.filename(), latest, ec);
  if (ec)
    std::cerr << "swarm_inprocess: could not point " << latest.string() << " at the run: " << ec.message()
              << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "swarm_inprocess: one run of the swarm in a single process (the world with every robot's controller, "
      "no "
      "DDS, no agent processes). Writes the run directory of `swarm run` (robots.csv, readings.csv "
      "when the behaviour declares sensors, events.jsonl, world.json, "
      "world.log, summary.json; format in docs/recording-format.md) and prints summary.json on stdout."};
  std::string scenario_path = "scenarios/paper.yaml";
  std::string shape;
  std::size_t robots = 0;
  std::uint64_t seed = 0;
  Tick max_ticks = 0;
  std::string out;
  std::string behaviour;
  std::vector<std::string> plugin_dirs;
  std::vector<std::string> kill_texts;
  std::vector<std::string> fault_texts;
  std::vector<std::string> param_texts;
  std::vector<std::string> set_texts;
  double fragment_range = 0.0;
  bool no_record = false;
  bool quiet = false;
  bool check = false;
  Tick record_every = 1;
  app.add_option("--scenario", scenario_path, "scenario file (YAML)")->capture_default_str();
  app.add_option("--shape", shape, "shape file, instead of the scenario's");
  app.add_option("--robots", robots, "number of robots (random placement), instead of the scenario's");
  app.add_option("--seed", seed, "seed, instead of the scenario's");
  app.add_option("--max-ticks", max_ticks, "stop after this many ticks at the latest");
  app.add_option("--behaviour", behaviour,
                 "a built-in behaviour (paper, random_walk) or an already named plug-in's, instead of the "
                 "scenario's (the scenario's parameters it does not have are left out)");
  app.add_option("--plugin-dir", plugin_dirs,
                 "a folder plug-ins may be loaded from, besides the scenario's own folder and those of "
                 "SWARMFORM_PLUGIN_PATH (':'-separated); repeatable. A plug-in anywhere else is refused");
  app.add_option(
      "--param", param_texts,
      "NAME=VALUE: set the behaviour's parameter NAME (a scenario `controller:` key) over the "
      "scenario's value; repeatable; checked against the behaviour's parameter table (unknown name or "
      "out of bounds: exit 2 naming it)");
  app.add_option(
      "--set", set_texts,
      "KEY=VALUE: set the scenario field KEY (dotted for a nested one: noise.range) to VALUE "
      "(YAML: packet_loss={rate: 0.2, mean_burst: 5}) over the file's; repeatable; checked like the "
      "file's fields (docs/scenario-format.md; a bad one: exit 2 naming the flag)");
  app.add_option("--out", out, "run directory (default runs/<UTC time>, and runs/latest points at it)");
  app.add_option("--kill", kill_texts, "kill robot ID at tick TICK (ID@TICK); repeatable");
  app.add_option(
      "--fault", fault_texts,
      std::string("a scheduled fault, added to the scenario's `faults`: ") + world::kFaultFormatHelp +
          ". In-process a stall is the robot's controller not stepped, a restart a fresh controller");
  app.add_option("--fragment-range", fragment_range,
                 "m: range of the shape robots' graph for fragment events (default: the comm range)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--no-record", no_record, "write nothing (metrics only; for benchmarks)");
  swarmform::world::add_record_every_flag(app, record_every);
  app.add_flag("--quiet", quiet, "no progress lines on stderr");
  app.add_flag("--check", check,
               "load and validate the scenario, print world_server --check's JSON line (with the keys the "
               "run's summary.json will have), run nothing");
  app.footer(kExitHelp_swarm_inprocess);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;  // CLI11's own codes are not ours
  }

  try {
    world::ScenarioOverrides overrides;
    if (!shape.empty()) overrides.shape_file = shape;
    if (app.count("--robots") > 0) {
      if (robots == 0) throw InputError("command line", 0, "--robots: must be at least 1");
      overrides.robots = robots;
    }
    if (app.count("--seed") > 0) overrides.seed = seed;
    if (app.count("--max-ticks") > 0) overrides.max_ticks = max_ticks;
    for (const auto& k : kill_texts) overrides.kills.push_back(parse_kill(k));
    overrides.faults = fault_texts;
    if (!behaviour.empty()) overrides.behaviour = behaviour;
    overrides.params = world::parse_param_flags(param_texts);
    for (const std::string& t : set_texts) overrides.fields.push_back(world::parse_field_override(t));
    // Plug-ins load from the scenario's folder, --plugin-dir and SWARMFORM_PLUGIN_PATH only.
    behaviour::Registry behaviours;
    controller::add_builtins(behaviours);
    behaviours.add_folder(fs::absolute(scenario_path).parent_path());
    for (const std::string& d : plugin_dirs) {
      if (!fs::is_directory(d)) throw InputError("command line", 0, "--plugin-dir '" + d + "': not a folder");
      behaviours.add_folder(d);
    }
    behaviours.add_folders_from_environment();
    world::Scenario scenario = world::load_scenario(scenario_path, overrides, behaviours);
    world::check_param_flags(param_texts, scenario.mission, behaviours);
    // A behaviour described by a file is a program its agents run (--exec): nothing here can run it.
    for (std::size_t k = 0; k < world::group_count(scenario); ++k) {
      const world::GroupView g = world::group_view(scenario, k);
      if (g.behaviour->make != nullptr) continue;
      throw InputError(scenario_path, 0,
                       (g.name.empty() ? "" : "group '" + std::string(g.name) + "': ") +
                           behaviour::no_controller_message(g.mission->behaviour, g.mission->descriptor));
    }

    if (check) {
      std::cout << world::check_info(scenario).dump() << std::endl;
      return kExitOk;
    }

    const bool default_out = out.empty();
    const std::string run_dir = no_record ? std::string() : (default_out ? default_run_dir() : out);

    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const std::string described =
        "behaviour '" + scenario.mission.behaviour + "'" +
        (scenario.mission.plugin.empty() ? "" : " (plug-in " + scenario.mission.plugin + ")");
    g_behaviour_text_size = described.copy(g_behaviour_text, sizeof(g_behaviour_text));
    for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, on_crash);

    const auto start = std::chrono::steady_clock::now();
    harness::Harness harness(scenario, {run_dir, fragment_range, record_every});
    if (!run_dir.empty() && default_out) point_latest_at(run_dir);
    auto last_print = start;
    Tick last_tick = 0;
    std::optional<world::RecordingError> failed;
    std::optional<harness::BehaviourFailure> behaviour_failed;
    try {
      harness.run([&](const harness::Harness& h) {
        const auto now = std::chrono::steady_clock::now();
        if (!quiet && now - last_print >= std::chrono::seconds(1)) {
          const double dt = std::chrono::duration<double>(now - last_print).count();
          const Tick tick = h.world().tick();
          std::size_t alive = 0;
          for (const auto& r : h.world().robots()) alive += r.alive ? 1 : 0;
          std::fprintf(stderr, "tick %llu/%llu  alive %zu/%zu  %.0f ticks/s\n",
                       static_cast<unsigned long long>(tick),
                       static_cast<unsigned long long>(scenario.max_ticks), alive, h.world().robot_count(),
                       static_cast<double>(tick - last_tick) / dt);
          last_print = now;
          last_tick = tick;
        }
        return g_interrupted.load();
      });
    } catch (const world::RecordingError& e) {
      failed = e;
    } catch (const harness::BehaviourFailure& e) {
      behaviour_failed = e;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (behaviour_failed) {
      std::string written;
      try {
        harness.finish(wall, world::EndReason::BehaviourFailed);
        written = harness.summary_written();
      } catch (const std::exception& e) {
        written = std::string("summary.json not written: ") + e.what();
      }
      std::cerr << "swarm_inprocess: run ended (behaviour_failed): " << behaviour_failed->what() << "; "
                << written << "\n";
      return kExitBehaviourFailed;
    }
    if (failed) {
      std::string written;
      try {
        harness.finish(wall, failed->reason());
        written = harness.summary_written();
      } catch (const std::exception& e) {
        written = std::string("summary.json not written: ") + e.what();
      }
      std::cerr << "swarm_inprocess: run ended (" << world::to_string(failed->reason()) << ") at tick "
                << harness.world().tick() << ": " << failed->what() << "; " << written << "\n";
      return kExitRecordingFailed;
    }
    const std::string summary =
        harness.finish(wall, g_interrupted ? std::optional(world::EndReason::Interrupted) : std::nullopt);
    std::cout << summary << "\n";
    if (!quiet) {
      if (g_interrupted) std::cerr << "swarm_inprocess: interrupted; the run directory holds what was done\n";
      if (!run_dir.empty()) std::cerr << "swarm_inprocess: run directory " << run_dir << "\n";
    }
    // Last, even with --quiet: a run that used up max_ticks without its experiment's success says so.
    const std::string why = g_interrupted ? std::string()
                                          : world::max_ticks_line(harness.session().verdict(),
                                                                  harness.world().tick(), scenario.max_ticks);
    if (!why.empty()) std::cerr << "swarm_inprocess: " << why << "\n";
    return g_interrupted ? kExitInterrupted : kExitOk;
  } catch (const world::RecordingError& e) {  // the run directory could not even be started
    std::cerr << "swarm_inprocess: run ended (" << world::to_string(e.reason())
              << ") before it started: " << e.what() << "\n";
    return kExitRecordingFailed;
  } catch (const InputError& e) {
    std::cerr << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "swarm_inprocess: " << e.what() << "\n";
    return kExitFailed;
  }
}
