// The bare DDS bound of a lockstep round (P1's baseline, BENCHMARKS.md): a minimal world and N robot
// processes with exactly the emulator's wire (common/dds: same Cyclone config, same QoS, same partition per
// robot, same SensorPacket and Command types), and nothing else: no physics, no sensors, no controller, no
// recording.
//
//   bare_round [--domain D] [--interface ADDR] world --robots N [--rounds R] [--warmup W] [--timeout SEC]
//   bare_round [--domain D] [--interface ADDR] robot --id K [--count N] [--world-host ADDR]
//   (--count: robots K..K+N-1, forked from one process; --world-host/--interface: on other (emulated) hosts,
//   as world_server's and robot_agent's flags of the same names)
//   --security-dir DIR (before the subcommand): both sides with DDS Security, as `swarm run --secure`
//
// The world waits for N claims, then each round writes one SensorPacket per robot (with a few neighbour
// messages, as the random walk's) and waits for every robot's Command of that round. It prints one JSON line:
//   {"robots":N,"rounds":R,"seconds":S,"rounds_per_second":X}
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <vector>

#include "common/dds/agent_inbox.hpp"
#include "common/dds/command_reader.hpp"
#include "common/dds/command_writer.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/mission_endpoints.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/robot_block.hpp"
#include "common/dds/robot_channels.hpp"
#include "common/dds/robot_process.hpp"
#include "common/dds/security_config.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/dds/waiter.hpp"

namespace {

using namespace swarmform;

// What each packet carries (world) and each reply (robot). By default a few neighbours' 4-byte messages and
// an empty reply.
struct Payload {
  std::uint32_t readings = 4;       // world: neighbours' messages in each packet
  std::uint32_t message_bytes = 4;  // world: bytes of each of them
  std::uint32_t reply_bytes = 0;    // robot: bytes of the message in its Command
};

int run_world(std::uint32_t robots, std::uint32_t rounds, std::uint32_t warmup, const Payload& payload,
              dds::DdsSettings settings, const std::string& security_dir, double timeout_s,
              dds::SignalWatch& signals) {
  settings.role = dds::Role::World;
  if (!security_dir.empty()) settings.security = dds::security_files(security_dir, dds::world_identity());
  dds::Participant participant(settings);
  dds::Waiter waiter(participant);
  dds::RobotChannels channels(participant, robots);
  dds::CommandReader commands(participant, waiter);
  waiter.attach(commands.condition());
  signals.notify(&waiter);

  std::vector<dds::CommandSample> samples;
  std::vector<std::uint8_t> seen(robots, 0);
  std::uint32_t claimed = 0;
  const dds_time_t connect_deadline = dds_time() + static_cast<dds_duration_t>(timeout_s * 1e9);
  while (claimed < robots) {
    if (signals.stop_requested()) return 130;
    if (dds_time() >= connect_deadline) {
      std::cerr << "bare_round world: " << robots - claimed << " robots missing after " << timeout_s
                << " s\n";
      return 3;
    }
    waiter.wait_until(connect_deadline);
    const std::size_t n = commands.take(samples);
    for (std::size_t i = 0; i < n; ++i) {
      const RobotId id = samples[i].robot_id;
      if (samples[i].kind == dds::CommandKind::Claim && id < robots && !seen[id]) {
        seen[id] = 1;
        ++claimed;
      }
    }
  }

  // A packet: pose, ultrasonics and `payload.readings` neighbours' messages.
  Perception p;
  p.ultrasonic.fill(2.0);
  for (RobotId k = 0; k < payload.readings; ++k) {
    p.messages.push_back(RabReading{k, 1.0, 0.5, std::vector<std::uint8_t>(payload.message_bytes, 0)});
  }

  dds_time_t start = 0;
  for (std::uint32_t round = 0; round < warmup + rounds; ++round) {
    if (round == warmup) start = dds_time();
    p.tick = round;
    for (RobotId id = 0; id < robots; ++id) channels.write_packet(id, dds::PacketStatus::Run, p);
    std::uint32_t replies = 0;
    const dds_time_t deadline = dds_time() + DDS_SECS(5);
    while (replies < robots) {
      if (signals.stop_requested()) return 130;
      if (dds_time() >= deadline) {
        std::cerr << "bare_round world: round " << round << " incomplete after 5 s\n";
        return 1;
      }
      const std::size_t n = commands.take(samples);
      for (std::size_t i = 0; i < n; ++i) {
        if (samples[i].kind == dds::CommandKind::Step && samples[i].tick == round) ++replies;
      }
      if (replies < robots) waiter.wait_until(deadline);
    }
  }
  const double seconds = static_cast<double>(dds_time() - start) * 1e-9;
  p.tick = warmup + rounds;
  for (RobotId id = 0; id < robots; ++id) channels.write_packet(id, dds::PacketStatus::End, p);
  channels.wait_for_acks(DDS_SECS(2));
  std::printf("{\"robots\":%u,\"rounds\":%u,\"seconds\":%.4f,\"rounds_per_second\":%.2f}\n", robots, rounds,
              seconds, rounds / seconds);
  return 0;
}

int run_robot(RobotId id, const Payload& payload, dds::DdsSettings settings, const std::string& security_dir,
              double timeout_s, dds::SignalWatch& signals) {
  settings.role = dds::Role::Agent;
  if (!security_dir.empty()) settings.security = dds::security_files(security_dir, dds::robot_identity(id));
  dds::Participant participant(settings);
  dds::Waiter waiter(participant);
  dds::AgentInbox inbox(participant, id, waiter);
  dds::CommandWriter commands(participant, /*realtime=*/false,
                              participant.secure() ? std::optional<RobotId>(id) : std::nullopt);
  // Against world_server: its mission names the run, whose nonce every claim and command must carry (the
  // bare world publishes none, and takes anything).
  dds::MissionReader mission(participant);
  dds::RefusalLog refusals("bare_round robot " + std::to_string(id), std::cerr);
  waiter.attach(inbox.packet_condition());
  waiter.attach(mission.condition());
  signals.notify(&waiter);

  dds::SensorSample packet;
  std::uint64_t foreign = 0;
  bool started = false;
  dds_time_t resend = 0;
  const dds_time_t give_up = dds_time() + static_cast<dds_duration_t>(timeout_s * 1e9);
  Command reply;
  reply.message.assign(payload.reply_bytes, 0);
  for (;;) {
    if (signals.stop_requested()) return 130;
    if (auto m = mission.take(std::nullopt, refusals)) {
      commands.set_stamp(m->run_nonce);
      inbox.bind(dds::WorldBinding{m->world, m->run_nonce}, "bare_round robot " + std::to_string(id));
    }
    if (inbox.take_packet(packet, foreign)) {
      started = true;
      if (packet.status == dds::PacketStatus::End) return 0;
      commands.step(id, packet.perception.tick, reply);
      continue;
    }
    const dds_time_t now = dds_time();
    if (!started && now >= give_up) return 3;
    if (started && inbox.world_writers_alive() == 0) return 3;
    if (!started && now >= resend) {
      commands.claim(id, 0, 0);
      resend = now + DDS_MSECS(500);
    }
    // Kept alive as an agent keeps itself (its command writer's liveliness is manual, common/dds/qos.hpp),
    // so both sides of P1's ratio carry the same liveliness traffic.
    waiter.wait_until(std::min(started ? now + DDS_SECS(1) : resend, commands.keep_alive(now)));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bare_round: the bare DDS lockstep round rate with swarmform's wire (world + N robots)"};
  app.require_subcommand(1);
  std::uint32_t domain = 0;
  double timeout_s = 60.0;
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0u, 232u));
  app.add_option("--timeout", timeout_s, "seconds to wait for the other side")->check(CLI::PositiveNumber);
  dds::DdsSettings net;
  app.add_option("--interface", net.interface_address,
                 "local interface address (default: loopback for the world, and for robots whose world is on "
                 "loopback)");
  std::string security_dir;
  app.add_option("--security-dir", security_dir,
                 "DDS Security with the identities of this directory (made by `swarm run --secure` or "
                 "scripts/bench-lockstep --secure): the world as `world`, robot K as `robot-K`");
  auto* world = app.add_subcommand("world", "the world side");
  std::uint32_t robots = 16, rounds = 2000, warmup = 100;
  world->add_option("--robots", robots, "robot processes to wait for")->check(CLI::Range(1u, 1024u));
  world->add_option("--rounds", rounds, "measured rounds")->check(CLI::Range(1u, 100000000u));
  world->add_option("--warmup", warmup, "rounds before measuring");
  Payload payload;
  world->add_option("--readings", payload.readings, "neighbours' messages in each packet (default 4)")
      ->check(CLI::Range(0u, 1000u));
  world->add_option("--message-bytes", payload.message_bytes, "bytes of each neighbour's message (default 4)")
      ->check(CLI::Range(0u, 65536u));
  auto* robot = app.add_subcommand("robot", "one robot");
  std::uint32_t id = 0;
  robot->add_option("--id", id, "robot id")->required();
  robot
      ->add_option(
          "--reply-bytes", payload.reply_bytes,
          "bytes of the message in each reply (default 0). Against world_server the world delivers it "
          "to the neighbours in range, as a robot's broadcast")
      ->check(CLI::Range(0u, 65536u));
  std::uint32_t count = 1;
  robot
      ->add_option("--count", count,
                   "robots --id..--id+count-1, each its own process forked from this one (as robot_agent "
                   "--count, so that P1 compares like with like)")
      ->check(CLI::Range(1u, dds::kMaxRobotBlock));
  robot->add_option("--world-host", net.world_host, "address of the world's host (default 127.0.0.1)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  net.domain = domain;
  // Robots are scheduled as robot_agent schedules itself (common/dds/robot_process.hpp), so P1's ratio
  // compares like with like.
  if (robot->parsed()) (void)dds::yield_to_world_on_wakeup();
  (void)dds::keep_freed_heap();  // both sides, world and robots, as world_server and robot_agent
  if (robot->parsed() && count > 1) {
    try {
      return dds::run_robot_block(
          "bare_round", id, count,
          [&](std::uint32_t one) {
            try {
              dds::SignalWatch signals;
              return run_robot(one, payload, net, security_dir, timeout_s, signals);
            } catch (const std::exception& e) {
              std::cerr << "bare_round: " << e.what() << "\n";
              return 1;
            }
          },
          std::cout);
    } catch (const std::exception& e) {
      std::cerr << "bare_round: " << e.what() << "\n";
      return 1;
    }
  }
  try {
    dds::SignalWatch signals;
    if (world->parsed())
      return run_world(robots, rounds, warmup, payload, net, security_dir, timeout_s, signals);
    return run_robot(id, payload, net, security_dir, timeout_s, signals);
  } catch (const std::exception& e) {
    std::cerr << "bare_round: " << e.what() << "\n";
    return 1;
  }
}
