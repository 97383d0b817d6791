// world_server: the world of a swarmform run as a DDS process. It loads the scenario, publishes the mission,
// waits for every robot's agent to claim its id, then ticks (lockstep or realtime) until the run is complete,
// and writes the run directory through RunSession. `--check` only loads and validates the scenario.
//
// Exit codes: common/exit_codes.json (printed by --help). After a failure once agents connected (the world
// failed, agents missing, a write failed) the agents are told to end and summary.json is written when the
// disk allows.
#include <fcntl.h>
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>

#include <filesystem>
#include "common/dds/claim_proof.hpp"
#include "common/dds/security_config.hpp"

#include "behaviour/registry.hpp"
#include "common/dds/robot_process.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/exit_codes.hpp"
#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "world_server/run/param_flags.hpp"
#include "world_server/run/record_every_flag.hpp"
#include "world_server/run/recording_format.hpp"
#include "world_server/server.hpp"
#include "world_server/world/scenario.hpp"

namespace {

using swarmform::RobotId;
using swarmform::Tick;

using swarmform::exit_codes::kExitBadInput;
using swarmform::exit_codes::kExitOk;

struct Options {
  std::string scenario;
  std::string shape;
  std::optional<std::size_t> robots;
  std::optional<std::uint64_t> seed;
  std::string mode;
  std::optional<Tick> max_ticks;
  std::string out;
  Tick record_every = 1;
  std::uint32_t domain = 0;
  std::string interface_address = "127.0.0.1";
  std::vector<std::string> kills;
  std::vector<std::string> faults;
  std::vector<std::string> agent_pids;
  std::optional<double> connect_timeout_s;  // default: default_connect_timeout(robots)
  Tick warmup_ticks = 100;
  std::string run_nonce;
  std::string agent_pids_file;
  std::string viewer_token;
  bool start_paused = false;
  std::vector<std::string> plugin_dirs;
  bool check = false;
  std::string dds_config;  // --dds-config FILE
  bool print_dds_config = false;
  std::string security_dir;
  std::optional<int> status_fd;
  bool open_rejoin = false;
  std::vector<std::string> params;  // --param NAME=VALUE
};

// "A<sep>B" with two unsigned integers; throws std::invalid_argument naming the flag.
std::pair<std::uint64_t, std::uint64_t> split_pair(const std::string& flag, const std::string& value,
                                                   char sep) {
  const auto at = value.find(sep);
  auto number = [&](const std::string& s) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 18) {
      throw std::invalid_argument(flag + " " + value + ": expected ID" + sep + "N with unsigned integers");
    }
    return std::stoull(s);
  };
  if (at == std::string::npos) throw std::invalid_argument(flag + " " + value + ": expected ID" + sep + "N");
  return {number(value.substr(0, at)), number(value.substr(at + 1))};
}

swarmform::world::ScenarioOverrides overrides_of(const Options& o) {
  swarmform::world::ScenarioOverrides ov;
  if (!o.shape.empty()) ov.shape_file = o.shape;
  ov.robots = o.robots;
  ov.seed = o.seed;
  ov.max_ticks = o.max_ticks;
  if (o.mode == "lockstep") ov.mode = swarmform::world::Mode::Lockstep;
  if (o.mode == "realtime") ov.mode = swarmform::world::Mode::Realtime;
  for (const std::string& k : o.kills) {
    const auto [id, tick] = split_pair("--kill", k, '@');
    ov.kills.push_back(swarmform::world::Kill{static_cast<RobotId>(id), tick});
  }
  ov.faults = o.faults;
  ov.params = swarmform::world::parse_param_flags(o.params);
  return ov;
}

swarmform::dds::DdsSettings dds_settings(const Options& o) {
  swarmform::dds::DdsSettings settings;
  settings.domain = o.domain;
  settings.role = swarmform::dds::Role::World;
  settings.interface_address = o.interface_address;
  settings.user = swarmform::dds::user_dds_config(o.dds_config, std::getenv("CYCLONEDDS_URI"));
  if (!o.security_dir.empty()) {
    settings.security = swarmform::dds::security_files(o.security_dir, swarmform::dds::world_identity());
  }
  return settings;
}

int run(const Options& o) {
  if (o.print_dds_config) {
    std::cout << swarmform::dds::cyclone_config_listing(dds_settings(o), "world_server");
    return kExitOk;
  }
  // The behaviours the scenario may name: the built-ins, and plug-ins from the scenario's own folder,
  // --plugin-dir and SWARMFORM_PLUGIN_PATH only (behaviour/registry.hpp).
  swarmform::behaviour::Registry behaviours;
  swarmform::controller::add_builtins(behaviours);
  behaviours.add_folder(std::filesystem::absolute(o.scenario).parent_path());
  for (const std::string& d : o.plugin_dirs) {
    if (!std::filesystem::is_directory(d)) {
      throw swarmform::InputError("command line", 0, "--plugin-dir '" + d + "': not a folder");
    }
    behaviours.add_folder(d);
  }
  behaviours.add_folders_from_environment();
  const swarmform::world::Scenario scenario =
      swarmform::world::load_scenario(o.scenario, overrides_of(o), behaviours);
  swarmform::world::check_param_flags(o.params, scenario.mission, behaviours);
  // A group described by a JSON file would need its own --exec program beside the other groups' controllers:
  // one --exec runs every agent's behaviour, so a mixed swarm takes controllers only (docs/scenario-format.md
  // "Groups").
  for (const swarmform::world::RobotGroup& g : scenario.groups) {
    if (g.behaviour->make != nullptr) continue;
    throw swarmform::InputError(o.scenario, 0,
                                "groups: group '" + g.name + "': behaviour '" + g.mission.behaviour +
                                    "' is described by a file (" + g.mission.descriptor +
                                    ") and has no controller; a mixed swarm runs built-in and plug-in "
                                    "behaviours only (one --exec program cannot run beside other groups)");
  }
  for (const auto& k : scenario.kills) {
    if (k.id >= scenario.robots.size()) {
      throw std::invalid_argument("--kill " + std::to_string(k.id) + "@" + std::to_string(k.tick) +
                                  ": no robot " + std::to_string(k.id) + " in a run of " +
                                  std::to_string(scenario.robots.size()));
    }
  }
  if (o.check) {
    const nlohmann::ordered_json j = swarmform::world::check_info(scenario);
    std::cout << j.dump() << std::endl;
    return kExitOk;
  }
  if (o.out.empty()) throw std::invalid_argument("--out DIR is required for a run (the run directory)");

  swarmform::server::ServerOptions so;
  so.run_dir = o.out;
  so.record_every = o.record_every;
  so.dds = dds_settings(o);
  so.connect_timeout_s =
      o.connect_timeout_s.value_or(swarmform::server::default_connect_timeout(scenario.robots.size()));
  so.warmup_ticks = o.warmup_ticks;
  so.agent_pids_file = o.agent_pids_file;
  if (!o.run_nonce.empty()) {
    if (o.run_nonce.size() > 16 ||
        o.run_nonce.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos ||
        std::stoull(o.run_nonce, nullptr, 16) == 0) {
      throw std::invalid_argument("--run-nonce " + o.run_nonce + ": want 1 to 16 hex digits, not all zero");
    }
    so.run_nonce = std::stoull(o.run_nonce, nullptr, 16);
  }
  if (!o.viewer_token.empty()) {
    if (o.viewer_token.size() > 16 ||
        o.viewer_token.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos ||
        std::stoull(o.viewer_token, nullptr, 16) == 0) {
      throw std::invalid_argument("--viewer-token " + o.viewer_token +
                                  ": want 1 to 16 hex digits, not all zero");
    }
    so.viewer_token = std::stoull(o.viewer_token, nullptr, 16);
  }
  if (o.start_paused && so.viewer_token == 0) {
    throw std::invalid_argument("--start-paused needs --viewer-token (only the run's viewer can say go)");
  }
  so.start_paused = o.start_paused;
  // The run's secret comes only from the environment of whoever started the world (never its argv, which
  // every user of the host can read), and is removed from it at once.
  so.run_secret = swarmform::dds::take_key_from_env(swarmform::dds::kRunSecretEnv);
  so.open_rejoin = o.open_rejoin;
  if (o.status_fd) {
    if (*o.status_fd < 3 || ::fcntl(*o.status_fd, F_GETFL) == -1 ||
        (::fcntl(*o.status_fd, F_GETFL) & O_ACCMODE) == O_RDONLY) {
      throw std::invalid_argument("--status-fd " + std::to_string(*o.status_fd) +
                                  ": not an open file descriptor (3 or more) this process can write");
    }
    so.status_fd = *o.status_fd;
  }
  for (const std::string& p : o.agent_pids) {
    const auto [id, pid] = split_pair("--agent-pid", p, '=');
    if (pid == 0 || pid > 4194304) throw std::invalid_argument("--agent-pid " + p + ": not a process id");
    so.agent_pids[static_cast<RobotId>(id)] = static_cast<pid_t>(pid);
  }
  (void)swarmform::dds::keep_freed_heap();  // common/dds/robot_process.hpp
  swarmform::dds::SignalWatch signals;      // before any DDS thread: they inherit the blocked signal mask
  swarmform::server::Server server(scenario, std::move(so), signals);
  return server.run();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"world_server: the world of a swarmform run (Bullet physics, sensors, medium) over DDS"};
  CLI::Option* scenario =
      app.add_option("--scenario", o.scenario, "scenario file (YAML, docs/scenario-format.md)")->required();
  app.add_option("--shape", o.shape, "shape file, overrides the scenario's");
  app.add_option("--robots", o.robots, "number of robots, overrides the scenario's")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", o.seed, "seed, overrides the scenario's");
  app.add_option("--mode", o.mode, "lockstep or realtime, overrides the scenario's")
      ->check(CLI::IsMember({"lockstep", "realtime"}));
  app.add_option("--max-ticks", o.max_ticks, "ticks to run at most, overrides the scenario's")
      ->check(CLI::Range(Tick{1}, Tick{1000000000}));
  app.add_option(
      "--param", o.params,
      "NAME=VALUE: set the behaviour's parameter NAME over the scenario's value; repeatable; checked against "
      "the behaviour's parameter table (unknown name or out of bounds: exit 2 naming it)");
  app.add_option("--out", o.out, "run directory to write (required for a run)");
  swarmform::world::add_record_every_flag(app, o.record_every);
  app.add_option("--domain", o.domain, "DDS domain id (0..232)")->check(CLI::Range(0u, 232u));
  app.add_option("--interface", o.interface_address,
                 "local interface address (agents on other hosts: this "
                 "host's address; default loopback)");
  app.add_option("--kill", o.kills, "ID@TICK: SIGKILL agent ID at TICK (needs --agent-pid ID=PID)");
  app.add_option("--fault", o.faults,
                 std::string("a scheduled fault, added to the scenario's `faults`: ") +
                     swarmform::world::kFaultFormatHelp +
                     ". kill and stall signal the --agent-pid process (a stall without one withholds the "
                     "robot's packets); restart prints `restart id=ID tick=T` (and a --status-fd event) for "
                     "the launcher to start the agent");
  app.add_option("--agent-pid", o.agent_pids, "ID=PID: the process of agent ID, for --kill and stalls");
  app.add_option(
      "--agent-pids", o.agent_pids_file,
      "FILE: JSON object {\"ID\": PID} of the agents' processes, for --kill and stalls, read when one is due "
      "(the launcher starts the world first and writes it once the agents run)");
  app.add_option("--run-nonce", o.run_nonce,
                 "this run's nonce, 16 hex digits (default: drawn at random); agents started with the same "
                 "--run-nonce take only this world's mission (docs/wire.md)");
  app.add_option(
      "--viewer-token", o.viewer_token,
      "16 hex digits: publish sf_observe frames for the run's viewer and take sf_control (pause, step, "
      "speed, kill) from the one viewer that presents this token (docs/wire.md \"Observers\")");
  app.add_flag(
      "--start-paused", o.start_paused,
      "lockstep: hold tick 0 until the viewer says go (needs --viewer-token; runs anyway if no viewer "
      "binds within 30 s)");
  app.add_option("--connect-timeout", o.connect_timeout_s,
                 "seconds the start-up may stand still: the wait for every agent to claim its id ends when "
                 "no claim (nor matched reader) came for this long; then exit 3 naming the missing ids "
                 "(default 30 + 0.025 x robots: 55.6 s for 1024)")
      ->check(CLI::PositiveNumber);
  app.add_option("--warmup-ticks", o.warmup_ticks,
                 "ticks left out of summary.json's steady_ticks_per_second (default 100; the first ticks of "
                 "freshly started agents are slower)")
      ->check(CLI::Range(Tick{0}, Tick{1000000000}));
  app.add_option(
      "--security-dir", o.security_dir,
      "DDS Security: the run's security directory (made by `swarm run --secure`); the world "
      "authenticates as `world` (DIR/world.pem, .key, .permissions.p7s), talks only to participants "
      "of the same authority, and gives id K only to the participant authenticated as robot K "
      "(docs/security.md)");
  app.add_flag(
      "--open-rejoin", o.open_rejoin,
      "let any agent take a free or dead robot's id (an agent restarted by hand). Without it, a world given "
      "the run's secret in SWARMFORM_RUN_SECRET (64 hex digits; `swarm run` gives one) takes only claims its "
      "starter issued: a proof from the id's token, derived from the secret, or under --security-dir the "
      "id's certificate; a world without one takes a claim without a proof only for an id nobody has owned, "
      "before the run (docs/wire.md \"Claim proofs\")");
  app.add_option(
      "--plugin-dir", o.plugin_dirs,
      "a folder behaviour plug-ins may be loaded from, besides the scenario's own folder and those "
      "of SWARMFORM_PLUGIN_PATH (':'-separated); repeatable. A plug-in anywhere else is refused");
  app.add_option(
      "--status-fd", o.status_fd,
      "N: an inherited file descriptor (a pipe) to write the run's status on, one JSON object a line "
      "(ready, claimed, connected, gave_up, progress, restart, run_ended, done; docs/status-channel.md)");
  app.add_flag("--check", o.check, "load and validate the scenario, print a JSON line, exit");
  app.add_option("--dds-config", o.dds_config,
                 "FILE: a Cyclone DDS XML configuration merged on top of the built-in one (default: the file "
                 "CYCLONEDDS_URI names, if set); docs/dds-config.md says what may be overridden");
  app.add_flag("--print-dds-config", o.print_dds_config,
               "print the Cyclone DDS configuration in force (built-in, then --dds-config or CYCLONEDDS_URI) "
               "for these flags, and exit (--scenario not needed)");
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--print-dds-config") scenario->required(false);
  }
  app.footer(swarmform::exit_codes::kExitHelp_world_server);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    return run(o);
  } catch (const swarmform::InputError& e) {
    std::cerr << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    std::cerr << "world_server: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const swarmform::world::RecordingError& e) {  // before any agent connected: nobody to tell
    std::cerr << "world_server: run ended (" << swarmform::world::to_string(e.reason())
              << ") before it started: " << e.what() << "\n";
    return swarmform::server::kExitRecordingFailed;
  } catch (const std::exception& e) {
    std::cerr << "world_server: " << e.what() << "\n";
    return swarmform::exit_codes::kExitFailed;
  }
}
