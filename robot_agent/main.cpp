// robot_agent --id K: one robot's process. It takes the mission from the world's durable topic, makes its
// controller, claims its id, then each tick reads its own SensorPacket (partition robot/K), steps the
// controller and writes its Command, until the world announces the end (exit 0).
// robot_agent --id K --count N: robots K..K+N-1, each its own process forked from this one, which supervises
// them (common/dds/robot_block.hpp: the way to start many agents on one machine).
//
// Exit codes: common/exit_codes.json (printed by --help). A failed behaviour (exit kExitBehaviourFailed)
// makes the robot dead; the world goes on. The last stdout line is a summary a test can read:
//   agent id=K packets=P foreign_packets=F refused=R restarts=S
// (R: samples refused as not of this world, run or wire version; S: controller restarts after a rejoin).
// robot_agent --exec "CMD": the behaviour is the program CMD, one child process per robot, spoken to through
// the line protocol of docs/agent-protocol.md (robot_agent/exec/); the DDS side stays here.
#include <sys/types.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "behaviour/registry.hpp"
#include "common/dds/claim_proof.hpp"
#include "common/dds/robot_block.hpp"
#include "common/dds/robot_process.hpp"
#include "common/dds/security_config.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/exit_codes.hpp"
#include "common/input_error.hpp"
#include "robot_agent/answer_memory.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/dds_link.hpp"
#include "robot_agent/exec/exec_controller.hpp"

namespace {

using swarmform::agent::AgentLink;
using swarmform::agent::WaitResult;

struct Options {
  std::uint32_t id = 0;
  std::uint32_t domain = 0;
  std::string world_host = "127.0.0.1";
  std::string interface_address;
  double timeout_s = 60.0;
  double world_timeout_s = 10.0;
  pid_t world_pid = 0;  // 0: not known
  double world_stall_limit_s = 300.0;
  std::string run_nonce;
  std::uint32_t count = 1;
  std::string dds_config;                                 // --dds-config FILE
  std::optional<swarmform::dds::UserDdsConfig> user_dds;  // resolved from it or CYCLONEDDS_URI
  bool print_dds_config = false;
  std::string security_dir;
  std::string exec_command;  // --exec: the behaviour as a child process; empty: the mission's built-in one
  double exec_timeout_s = 5.0;
  std::vector<std::string> plugin_dirs;  // with SWARMFORM_PLUGIN_PATH's: where plug-ins may load from
  std::optional<swarmform::dds::ClaimToken> claim_token;  // SWARMFORM_CLAIM_TOKEN (claim_proof.hpp)
};

swarmform::dds::DdsSettings dds_settings(const Options& o) {
  swarmform::dds::DdsSettings settings;
  settings.domain = o.domain;
  settings.face =
      swarmform::dds::face_of(o.id);  // the world's participant for this id (docs/wire.md "Faces")
  settings.role = swarmform::dds::Role::Agent;
  settings.world_host = o.world_host;
  settings.interface_address = o.interface_address;
  settings.user = o.user_dds;
  if (!o.security_dir.empty()) {
    settings.security = swarmform::dds::security_files(o.security_dir, swarmform::dds::robot_identity(o.id));
  }
  return settings;
}

using namespace swarmform::exit_codes;

// The robot's controller: the mission's built-in behaviour, or the --exec program behind the same interface.
std::unique_ptr<swarmform::controller::Controller> make_robot_controller(
    const Options& o, const swarmform::Mission& mission, AgentLink& link,
    swarmform::behaviour::Registry& behaviours) {
  if (o.exec_command.empty()) return behaviours.make(mission, o.id);
  swarmform::agent::ExecOptions eo;
  eo.command = o.exec_command;
  eo.reply_timeout = std::chrono::milliseconds(static_cast<long long>(o.exec_timeout_s * 1000.0));
  eo.hello_timeout = std::max(eo.hello_timeout, eo.reply_timeout);
  eo.keep_alive = [&link] { link.keep_alive(); };  // a slow behaviour is not a dead robot
  auto c = std::make_unique<swarmform::agent::ExecController>(eo);
  c->init(mission, o.id);
  return c;
}

int run(const Options& o, swarmform::dds::SignalWatch& signals) {
  const std::string me = "robot_agent " + std::to_string(o.id);
  const swarmform::dds::DdsSettings settings = dds_settings(o);
  swarmform::agent::LinkOptions lo;
  lo.world_timeout_s = o.world_timeout_s;
  if (o.world_pid > 0) lo.world_pid = o.world_pid;
  lo.world_stall_limit_s = o.world_stall_limit_s;
  lo.claim_token = o.claim_token;
  if (!o.run_nonce.empty()) lo.run_nonce = std::stoull(o.run_nonce, nullptr, 16);  // checked in main
  AgentLink link(settings, o.id, signals, lo);
  std::uint64_t restarts = 0;

  auto stopped = [&](int code) {
    std::cout << "agent id=" << o.id << " packets=" << link.packets()
              << " foreign_packets=" << link.foreign_packets() << " refused=" << link.refused_samples()
              << " restarts=" << restarts << std::endl;
    return code;
  };

  swarmform::dds::MissionAnnouncement mission;
  switch (link.wait_mission(o.timeout_s, mission)) {
    case WaitResult::Ok:
      break;
    case WaitResult::Stopped:
      return stopped(kExitSignalBase + signals.signal());
    case WaitResult::WorldGone:
      std::cerr << me << ": the world's process (pid " << o.world_pid << ") exited before its mission came\n";
      return stopped(kExitNoWorld);
    default:
      std::cerr << me << ": no world on DDS domain " << o.domain << " (peer " << o.world_host << ") within "
                << link.claim_wait_s(o.timeout_s) << " s; is world_server running"
                << (o.security_dir.empty()
                        ? std::string("?")
                        : " with DDS Security, from the same run's directory as --security-dir " +
                              o.security_dir + "?")
                << "\n";
      return stopped(kExitNoWorld);
  }

  if (o.id >= mission.robots) {
    // The world drops samples for ids far outside the run before reading them (it would not answer).
    std::cerr << me << ": no robot " << o.id << " in this run (ids 0.." << mission.robots - 1 << ")\n";
    return stopped(kExitIdRefused);
  }

  // The behaviours this agent may run: the built-ins, and plug-ins from its own --plugin-dir and
  // SWARMFORM_PLUGIN_PATH folders only. The mission names a plug-in's path; it is loaded only when it lies
  // in one of those folders (behaviour/registry.hpp), never because the wire said so.
  swarmform::behaviour::Registry behaviours;
  swarmform::controller::add_builtins(behaviours);
  for (const std::string& d : o.plugin_dirs) {
    if (!std::filesystem::is_directory(d)) {
      std::cerr << me << ": --plugin-dir '" << d << "': not a folder\n";
      return stopped(kExitBadInput);
    }
    behaviours.add_folder(d);
  }
  behaviours.add_folders_from_environment();
  std::unique_ptr<swarmform::controller::Controller> controller;
  // An --exec child starts (an interpreter may take a second) before the claim, so that it cannot stall the
  // agent past its liveliness lease between the claim and the first command; a child that fails its hello is
  // said after the claim, so that it is a dead robot of the run, not an agent the world waits for.
  std::optional<swarmform::agent::BehaviourFailure> failed_start;
  try {
    controller = make_robot_controller(o, mission.mission, link, behaviours);
  } catch (const swarmform::agent::BehaviourFailure& e) {
    failed_start = e;
  } catch (const swarmform::InputError& e) {
    std::cerr << me << ": unusable mission: " << e.what() << "\n";
    return stopped(kExitBadInput);
  } catch (const swarmform::behaviour::PluginError& e) {
    std::cerr << me << ": " << e.what() << "\n";
    return stopped(kExitBadInput);
  }

  swarmform::dds::ClaimAnswer answer;
  switch (link.claim(o.timeout_s, answer)) {
    case WaitResult::Ok:
      break;
    case WaitResult::Stopped:
      return stopped(kExitSignalBase + signals.signal());
    case WaitResult::WorldGone:
      std::cerr << me << ": the world's process (pid " << o.world_pid
                << ") exited before it answered the claim of id " << o.id << "\n";
      return stopped(kExitNoWorld);
    default:
      std::cerr << me << ": the world did not answer the claim of id " << o.id << " within "
                << link.claim_wait_s(o.timeout_s) << " s\n";
      return stopped(kExitNoWorld);
  }
  if (!answer.accepted) {
    std::cerr << me << ": refused: " << answer.reason << "\n";
    return stopped(kExitIdRefused);
  }

  const auto behaviour_failed = [&](const swarmform::agent::BehaviourFailure& e) {
    std::cerr << me << ": " << e.what() << "; robot " << o.id << " is dead (its agent exits "
              << kExitBehaviourFailed << ")\n";
    return stopped(kExitBehaviourFailed);
  };
  if (failed_start) return behaviour_failed(*failed_start);

  swarmform::dds::SensorSample packet;
  std::uint32_t generation = 0;     // of the controller: the world's generation of the robot when it was made
  std::uint64_t own_packets = 0;    // perceptions stamped with our claim nonce
  std::uint32_t stale_packets = 0;  // perceptions of the previous owner skipped before the first own one
  constexpr std::uint32_t kStalePackets = 2;  // a round in flight, one more for a realtime world's timing
  swarmform::agent::AnswerMemory answers;     // the last tick answered; a repeat of it gets the same answer
  for (;;) {
    switch (link.next_packet(o.timeout_s, packet)) {
      case WaitResult::Ok:
        break;
      case WaitResult::Stopped:
        return stopped(kExitSignalBase + signals.signal());
      case WaitResult::WorldGone:
        if (link.world_process_gone())
          std::cerr << me << ": the world went away before announcing the end (its process, pid "
                    << o.world_pid << ", is gone)\n";
        else
          std::cerr << me << ": the world went away before announcing the end (silent for "
                    << link.world_silence_limit_s(o.timeout_s) << " s of this agent's own time)\n";
        return stopped(kExitNoWorld);
      case WaitResult::Timeout:
        std::cerr << me << ": no packet and no world for " << o.timeout_s << " s\n";
        return stopped(kExitNoWorld);
    }
    if (packet.owner_nonce != link.claim_nonce() && own_packets == 0 && ++stale_packets <= kStalePackets) {
      // Before our first own packet, one written before the world took our claim (a take-over of an owner
      // that died just as the run began: the round in flight was still its) is stale, not news.
      continue;
    }
    if (packet.owner_nonce != link.claim_nonce()) {
      // The world names another owner: this agent was taken for dead (stalled past its lease) and a
      // restarted agent claimed the id meanwhile (docs/wire.md "Identity and the claim protocol").
      std::cerr
          << me << ": lost id " << o.id
          << " to another agent: this one was taken for dead (stalled or cut off) and a restarted agent "
             "claimed the id; exiting\n";
      return stopped(kExitIdLost);
    }
    ++own_packets;
    if (packet.status == swarmform::dds::PacketStatus::End) {
      // An END after rounds stepped without this robot comes to an agent the world took for dead (stopped or
      // starved past its liveliness lease) that was not back before the run ended: it says so, or its log
      // would say nothing of why its robot stopped. Lockstep steps no round without a live robot's command;
      // realtime does, and a slow agent skips a perception now and then: there a second's worth of ticks.
      // (Not wall time: the perceptions written before its death come in with the END when it resumes.)
      const swarmform::Tick end_tick = packet.perception.tick;
      const auto allowed = static_cast<swarmform::Tick>(
          mission.realtime ? std::max(2.0, std::ceil(mission.mission.tick_rate)) : 1.0);
      const std::optional<swarmform::Tick> last_tick = answers.last_tick();
      if (last_tick && end_tick > *last_tick + allowed) {
        std::cerr
            << me << ": the run ended at tick " << end_tick
            << " without this robot: its last packet was for tick " << *last_tick
            << " (the world took it for dead meanwhile: this process was stopped, starved or cut off past "
               "its liveliness lease, and the run ended before it was back)\n";
      }
      return stopped(kExitOk);
    }
    if (const auto verdict = answers.judge(packet.perception.tick, packet.generation);
        verdict != swarmform::agent::AnswerMemory::Verdict::Step) {
      if (verdict == swarmform::agent::AnswerMemory::Verdict::Repeat)
        link.send(packet.perception.tick, answers.last());
      continue;
    }
    if (generation == 0) {
      generation = packet.generation;
    } else if (packet.generation > generation) {
      // The world took this robot for dead and brought it back (docs/wire.md): its controller starts
      // afresh from the mission, as a restarted agent's would, rather than act on a state that went stale.
      controller.reset();  // an --exec child ends before its successor starts
      try {
        controller = make_robot_controller(o, link.mission().mission, link, behaviours);
      } catch (const swarmform::agent::BehaviourFailure& e) {
        return behaviour_failed(e);
      }
      generation = packet.generation;
      ++restarts;
      std::cerr << me << ": rejoined at tick " << packet.perception.tick
                << " after the world took this robot for dead; controller started afresh\n";
    }
    swarmform::Command command;
    try {
      command = controller->step(packet.perception);
    } catch (const swarmform::agent::BehaviourFailure& e) {
      return behaviour_failed(e);
    }
    if (!std::isfinite(command.left_speed) || !std::isfinite(command.right_speed)) {
      // A behaviour that lost its numbers: this robot stops (the world takes it for dead once its lease
      // lapses), the world and the other robots go on.
      std::cerr << me << ": behaviour '" << mission.mission.behaviour << "' returned a non-finite wheel speed"
                << " (left " << command.left_speed << ", right " << command.right_speed << ") at tick "
                << packet.perception.tick << "; this robot stops\n";
      return stopped(kExitBehaviourFailed);
    }
    link.send(packet.perception.tick, command);
    answers.answered(packet.perception.tick, generation, std::move(command));
  }
}

// One agent, in this process.
int run_agent(const Options& o) {
  try {
    swarmform::dds::SignalWatch signals;  // first: every DDS thread inherits the blocked signal mask
    return run(o, signals);
  } catch (const std::invalid_argument& e) {
    std::cerr << "robot_agent: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "robot_agent " << o.id << ": " << e.what() << "\n";
    return kExitFailed;
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"robot_agent: one robot of a swarmform run, as its own process over DDS"};
  CLI::Option* id_option = app.add_option("--id", o.id, "this robot's id (0..N-1)")->required();
  app.add_option("--domain", o.domain, "DDS domain id (0..232)")->check(CLI::Range(0u, 232u));
  app.add_option("--world-host", o.world_host, "address of the world server's host (its discovery peer)");
  app.add_option("--interface", o.interface_address,
                 "local interface address to use (default: loopback when the world is on loopback)");
  app.add_option("--timeout", o.timeout_s, "seconds to wait for the world (mission, claim answer, packets)")
      ->check(CLI::PositiveNumber);
  app.add_option("--world-timeout", o.world_timeout_s,
                 "seconds of this agent's own time the world may stay silent mid-run before it is taken for "
                 "gone (default 10; a stalled world is not a dead one; before the run, --timeout if longer)")
      ->check(CLI::Range(0.5, 86400.0));
  app.add_option("--world-pid", o.world_pid,
                 "the world server's process on this host (swarm run gives it): the world is gone as soon as "
                 "it is, and while it is there its silence (and an unanswered claim) is waited out for "
                 "--world-stall-limit instead of --world-timeout (--timeout for the claim)")
      ->check(CLI::PositiveNumber);
  app.add_option("--world-stall-limit", o.world_stall_limit_s,
                 "with --world-pid: seconds of this agent's own time a world whose process is there may stay "
                 "silent (default 300)")
      ->check(CLI::Range(0.5, 86400.0));
  app.add_option("--run-nonce", o.run_nonce,
                 "take only the mission of this run (16 hex digits, as given to world_server --run-nonce); "
                 "default: the first mission seen")
      ->check([](const std::string& v) {
        const bool ok = !v.empty() && v.size() <= 16 &&
                        v.find_first_not_of("0123456789abcdefABCDEF") == std::string::npos;
        return ok ? std::string() : std::string("want 1 to 16 hex digits");
      });
  app.add_option("--count", o.count,
                 "run this many robots, ids --id..--id+count-1, each its own process forked from this one "
                 "(faster to start than as many executables); this process supervises them and prints "
                 "'robot_agent: id K pid P' for each")
      ->check(CLI::Range(1u, swarmform::dds::kMaxRobotBlock));
  app.add_option("--dds-config", o.dds_config,
                 "FILE: a Cyclone DDS XML configuration merged on top of the built-in one (default: the file "
                 "CYCLONEDDS_URI names, if set); docs/dds-config.md says what may be overridden");
  app.add_flag("--print-dds-config", o.print_dds_config,
               "print the Cyclone DDS configuration in force (built-in, then --dds-config or CYCLONEDDS_URI) "
               "for these flags, and exit (--id not needed)");
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--print-dds-config") id_option->required(false);
  }
  app.add_option(
      "--security-dir", o.security_dir,
      "DDS Security: the run's security directory (made by `swarm run --secure`); this robot "
      "authenticates as robot-K with DIR/robot-K.pem, .key and .permissions.p7s, and talks only to "
      "participants of the same authority (docs/security.md)");
  app.add_option(
         "--exec", o.exec_command,
         "run the robot's behaviour as this program instead of the mission's built-in one: one child "
         "process per robot, started by /bin/sh -c 'exec CMD' with SWARMFORM_ROBOT_ID set, speaking the "
         "JSON line protocol of docs/agent-protocol.md on its stdin/stdout (its stderr goes to this "
         "agent's). A child that exits, hangs past --exec-timeout or writes garbage or NaN makes the robot "
         "dead (exit " +
             std::to_string(kExitBehaviourFailed) + ", saying what the child did)")
      ->check([](const std::string& v) {
        return v.find_first_not_of(" \t") == std::string::npos ? std::string("want a command")
                                                               : std::string();
      });
  app.add_option("--exec-timeout", o.exec_timeout_s,
                 "seconds the --exec behaviour may take to answer each perception (default 5; the hello gets "
                 "at least 10)")
      ->check(CLI::Range(0.001, 3600.0));
  app.add_option("--plugin-dir", o.plugin_dirs,
                 "a folder behaviour plug-ins may be loaded from (with those of SWARMFORM_PLUGIN_PATH, "
                 "':'-separated); repeatable. A mission naming a plug-in anywhere else is refused (exit " +
                     std::to_string(kExitBadInput) + ")");
  app.footer(kExitHelp_robot_agent);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return e.get_exit_code() == 0 ? app.exit(e) : (app.exit(e), kExitBadInput);
  }
  try {
    o.user_dds = swarmform::dds::user_dds_config(o.dds_config, std::getenv("CYCLONEDDS_URI"));
    // Taken out of the environment before an --exec child or a block's robot could inherit it.
    o.claim_token = swarmform::dds::take_key_from_env(swarmform::dds::kClaimTokenEnv);
    if (o.claim_token && o.count > 1) {
      throw std::invalid_argument(std::string(swarmform::dds::kClaimTokenEnv) +
                                  " is one robot's token: it cannot go with --count " +
                                  std::to_string(o.count));
    }
    if (o.print_dds_config) {
      std::cout << swarmform::dds::cyclone_config_listing(dds_settings(o), "robot_agent");
      return kExitOk;
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "robot_agent: " << e.what() << "\n";
    return kExitBadInput;
  }
  // Before any thread exists, and before a block forks: every thread and every forked robot inherits both.
  (void)swarmform::dds::yield_to_world_on_wakeup();
  (void)swarmform::dds::keep_freed_heap();
  if (o.count == 1) return run_agent(o);
  try {
    return swarmform::dds::run_robot_block(
        "robot_agent", o.id, o.count,
        [&o](std::uint32_t id) {
          Options one = o;
          one.id = id;
          one.count = 1;
          return run_agent(one);
        },
        std::cout);
  } catch (const std::exception& e) {
    std::cerr << "robot_agent: " << e.what() << "\n";
    return kExitFailed;
  }
}
