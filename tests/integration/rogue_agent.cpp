// A misbehaving participant for the integration tests, on swarmform's own wire (common/dds):
//
//   rogue_agent spoof --target K --domain D [--timeout SEC]
//       never claims anything; follows the world state and writes full-speed Commands for robot K for the
//       current and next few ticks; prints "spoof ready" once its writer has matched the world's command
//       reader (the test starts the run only then). The world must drop every one of them (they are not from
//       K's owner) and log them; the run must be bit-identical to one without the spoofer.
//   rogue_agent nan --id K --domain D [--timeout SEC]
//       claims K as an agent would, then answers every packet with NaN wheel speeds and an oversize message.
//       The world must reject/clamp and log them, and the run go on.
//   rogue_agent slow --id K --delay-ms MS [--realtime] --domain D [--timeout SEC]
//       claims K, then answers its newest packet MS after taking it (a standing command). In realtime mode
//       (--realtime: best-effort endpoints, as the mission would say) a delay over the period makes every
//       answer late: the world must count the misses and tell where the late commands' time went.
//   rogue_agent silent --id K --domain D [--timeout SEC]
//       claims K, keeps its writer's liveliness asserted, and never answers a packet: a live agent that says
//       nothing (a hung controller). Its robot stands where it was placed; its label must be given up.
//   rogue_agent forge --target K --domain D [--realtime] [--timeout SEC]
//       a second writer in partition robot/K, of another participant: it reads K's real packets (to learn the
//       run nonce, owner nonce and generation, as a forger on the host could), then from tick 20 on writes a
//       forged perception and an END packet for K every world tick. Agent K must refuse them all (they are
//       not from the world it bound to) and run to the end. Prints "forge sent=N" when the run finishes.
//   rogue_agent badwire --id K --domain D (--version V | --nonce HEX) [--timeout SEC]
//       claims K stamped with another wire version or another run's nonce, re-sent every 0.1 s. The world
//       must refuse every claim, say so at most once a second, and answer a claim of its own version with the
//       reason (printed as "rogue_agent: refused: <reason>", exit 4).
//
//   rogue_agent liar --id K --domain D [--timeout SEC]
//       claims K and drives it with the real controller (the mission's, as robot_agent would), so it moves
//       exactly as an honest agent; but every command's telemetry lies: state arrived, label and parent
//       2e9, a NaN net force, and a 20 KB event string, one with control bytes and an "arrived" among its
//       events. The world must drop and count the out-of-range fields and strings and record none of them;
//       the run's metrics (from the world's poses) must be those of the honest run.
//   rogue_agent deaf --id K [--tick T] --domain D [--timeout SEC]
//       claims K and drives it with the real controller, as robot_agent would, but takes the first packet of
//       tick T as lost on the wire (it neither steps nor answers): the lockstep world must write the round's
//       packet again, and the run be the honest one bit for bit. A packet of a tick it answered already is
//       answered with the same command, as robot_agent does.
//   rogue_agent flood --seconds S [--ids N] [--made-up] [--realtime] --domain D [--timeout SEC]
//       owns nothing; once its writer has matched the world's reader (prints "flood ready") it writes
//       commands for ids 0..N-1 (1 KB message, 4 event strings each) as fast as the wire takes them for S
//       seconds, for the world's current tick, then prints "flood sent=K" and exits 0. --made-up: after each
//       of those, one for a new made-up id (1000, 1001, ...: each a new instance for a reader that keeps
//       them); --claims: also a claim for an id outside the run (8, 9, ... as `claims` does). The run must
//       be as without it (lockstep: the same trajectory hash), the run directory and the
//       world's memory bounded.
//   rogue_agent claims --seconds S [--first ID] --domain D [--timeout SEC]
//       owns nothing; claims ids ID, ID+1, ... (default 1000: outside any test run) as fast as it can for S
//       seconds, then prints "claims sent=K" and exits 0. The world must refuse them, hold no channel per
//       refused id, and log them at most once a second.
//   rogue_agent stranger --id K --pid P --domain D [--timeout SEC]
//       a process that read the run nonce from the mission and claims K as robot_agent would, but with no
//       token from the run's starter, stating the pid P (anything: the world must not take it as who it is).
//       Prints "stranger participant=<GUID>" (its participant's GUID, as DDS discovery gives it to the world)
//       first. Exits 0 once the world accepts the claim, 4 when it refuses it ("rogue_agent: refused: ...").
//
// Exits 0 when the world announces the end (nan, slow, silent, liar, deaf) or finishes (spoof, forge), 3 on
// --timeout.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <thread>

#include "common/dds/agent_inbox.hpp"
#include "common/dds/command_writer.hpp"
#include "common/dds/dds_error.hpp"
#include "common/dds/matching.hpp"
#include "common/dds/mission_endpoints.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/robot_channels.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/dds/waiter.hpp"
#include "common/dds/wire_version.hpp"
#include "common/dds/world_state_endpoints.hpp"
#include "robot_agent/answer_memory.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"

namespace {

using namespace swarmform;

dds_time_t after(double s) {
  return dds_time() + static_cast<dds_duration_t>(s * 1e9);
}

int spoof(dds::Participant& participant, RobotId target, double timeout_s) {
  dds::Waiter waiter(participant);
  dds::WorldStateReader state(participant);
  dds::CommandWriter commands(participant);
  waiter.attach(state.condition());
  const dds_time_t deadline = after(timeout_s);
  // Ready once the world's command reader is matched (its state writer is announced with it): the test
  // starts the run's agents only then, or a short lockstep run could end before the spoofer has joined.
  while (!dds::writer_matched(commands.get())) {
    if (dds_time() >= deadline) return 3;
    waiter.wait_until(std::min(deadline, after(0.05)));
  }
  std::cout << "spoof ready" << std::endl;
  Command fake;
  fake.left_speed = fake.right_speed = 0.1;
  fake.message = {0xde, 0xad};
  std::uint64_t sent = 0;
  while (dds_time() < deadline) {
    if (auto s = state.take()) {
      if (s->finished) {
        std::cout << "spoof sent=" << sent << std::endl;
        return 0;
      }
      commands.set_stamp(s->run_nonce);  // of this run: only the ownership check may stop them
      for (Tick t = s->tick; t < s->tick + 4; ++t, ++sent) commands.step(target, t, fake);
    }
    waiter.wait_until(deadline);
  }
  std::cout << "spoof sent=" << sent << " (timeout)" << std::endl;
  return 3;
}

// The run nonce of the world's mission (0 at `deadline`): these rogues misbehave inside the run.
std::uint64_t run_nonce_of(dds::Participant& participant, dds_time_t deadline) {
  dds::Waiter waiter(participant);
  dds::MissionReader mission(participant);
  dds::RefusalLog refusals("rogue_agent", std::cerr);
  waiter.attach(mission.condition());
  while (dds_time() < deadline) {
    if (auto m = mission.take(std::nullopt, refusals)) return m->run_nonce;
    waiter.wait_until(deadline);
  }
  return 0;
}

// Claims `id` as an agent would (resent every second until answered): 0 once the world accepted it, 4 if it
// refused, 3 at `deadline`.
int claim_id(RobotId id, dds::AgentInbox& inbox, dds::CommandWriter& commands, dds::Waiter& waiter,
             dds_time_t deadline) {
  const std::uint64_t nonce = 0x5eed0000u + id;
  dds_time_t resend = 0;
  for (;;) {
    if (dds_time() >= deadline) return 3;
    if (auto a = inbox.take_claim_reply(); a && a->nonce == nonce) {
      if (a->accepted) return 0;
      std::cerr << "rogue_agent: refused: " << a->reason << "\n";
      return 4;
    }
    if (dds_time() >= resend) {
      commands.claim(id, nonce, 0);
      resend = after(1.0);
    }
    waiter.wait_until(std::min(deadline, resend));
  }
}

// Claims `id`, then answers every packet it takes with answer(tick) (nothing when it gives none) until the
// world announces the end (prints
// "<name> sent=K" and returns 0); 3 at the timeout, 4 if the claim was refused. `realtime`: best-effort
// endpoints, as the mission of a realtime run says.
int answering_agent(dds::Participant& participant, RobotId id, bool realtime, double timeout_s,
                    const char* name,
                    const std::function<std::optional<Command>(const Perception&)>& answer) {
  dds::Waiter waiter(participant);
  dds::AgentInbox inbox(participant, id, waiter, realtime);
  dds::CommandWriter commands(participant, realtime);
  waiter.attach(inbox.packet_condition());
  const dds_time_t deadline = after(timeout_s);
  commands.set_stamp(run_nonce_of(participant, deadline));
  if (const int rc = claim_id(id, inbox, commands, waiter, deadline); rc != 0) return rc;
  dds::SensorSample packet;
  std::uint64_t foreign = 0;
  std::uint64_t sent = 0;
  for (;;) {
    if (inbox.take_packet(packet, foreign)) {
      if (packet.status == dds::PacketStatus::End) {
        std::cout << name << " sent=" << sent << std::endl;
        return 0;
      }
      if (const auto command = answer(packet.perception)) {
        commands.step(id, packet.perception.tick, *command);
        ++sent;
      }
      continue;
    }
    if (dds_time() >= deadline) return 3;
    waiter.wait_until(std::min(deadline, commands.keep_alive(dds_time())));
  }
}

int nan_agent(dds::Participant& participant, RobotId id, double timeout_s) {
  Command bad;
  bad.left_speed = std::numeric_limits<double>::quiet_NaN();
  bad.right_speed = std::numeric_limits<double>::infinity();
  // Every other tick an oversize message with finite but excessive speeds instead of NaN.
  Command big;
  big.left_speed = big.right_speed = 50.0;
  big.message.assign(100000, 0x55);
  return answering_agent(participant, id, false, timeout_s, "nan", [&](const Perception& p) {
    return std::optional<Command>(p.tick % 2 == 1 ? big : bad);
  });
}

// The mission as an agent gets it (durable): nullopt at `deadline`.
std::optional<dds::MissionAnnouncement> wait_mission(dds::Participant& participant, dds_time_t deadline) {
  dds::Waiter waiter(participant);
  dds::MissionReader reader(participant);
  dds::RefusalLog refusals("rogue_agent", std::cerr);
  waiter.attach(reader.condition());
  while (dds_time() < deadline) {
    if (auto m = reader.take(std::nullopt, refusals)) return m;
    waiter.wait_until(deadline);
  }
  return std::nullopt;
}

int liar_agent(dds::Participant& participant, RobotId id, double timeout_s) {
  const auto mission = wait_mission(participant, after(timeout_s));
  if (!mission) return 3;
  const auto controller = controller::make_controller(mission->mission, id);
  const std::string huge(20000, 'x');
  const std::string control = std::string("arrived\x01\x1b[2J") + '\xff';
  return answering_agent(participant, id, mission->realtime, timeout_s, "liar", [&](const Perception& p) {
    Command c = controller->step(p);
    c.telemetry.state = 6;  // arrived, in range: recorded as what it says
    // The paper's columns (kPaperTelemetry): label and parent 2e9, its own leader flag, a net force of 1e300.
    const bool leader = c.telemetry.extra.size() > 2 && c.telemetry.extra[2] != 0.0;
    c.telemetry.extra = controller::paper_telemetry(2000000000, 2000000000, leader, 1e300);
    c.telemetry.events = {huge, control, "formed"};
    return std::optional<Command>(c);
  });
}

int deaf_agent(dds::Participant& participant, RobotId id, Tick deaf_tick, double timeout_s) {
  const auto mission = wait_mission(participant, after(timeout_s));
  if (!mission) return 3;
  const auto controller = controller::make_controller(mission->mission, id);
  bool lost = false;
  agent::AnswerMemory answers;  // as robot_agent's (one generation: this agent never rejoins)
  return answering_agent(participant, id, mission->realtime, timeout_s, "deaf", [&](const Perception& p) {
    if (p.tick == deaf_tick && !lost) {
      lost = true;
      std::cerr << "rogue_agent: the packet of tick " << p.tick << " taken as lost\n";
      return std::optional<Command>();
    }
    switch (answers.judge(p.tick, 1)) {
      case agent::AnswerMemory::Verdict::Repeat:
        return std::optional<Command>(answers.last());
      case agent::AnswerMemory::Verdict::Stale:
        return std::optional<Command>();
      case agent::AnswerMemory::Verdict::Step:
        break;
    }
    answers.answered(p.tick, 1, controller->step(p));
    return std::optional<Command>(answers.last());
  });
}

int flood(dds::Participant& participant, double seconds, std::uint32_t ids, bool made_up, bool claims,
          bool realtime, double timeout_s) {
  dds::Waiter waiter(participant);
  dds::WorldStateReader state(participant);
  dds::CommandWriter commands(participant, realtime);
  waiter.attach(state.condition());
  const dds_time_t deadline = after(timeout_s);
  // Stamped with this run's nonce and version: the flood comes from inside the run, past the wire check.
  commands.set_stamp(run_nonce_of(participant, deadline));
  while (!dds::writer_matched(commands.get())) {
    if (dds_time() >= deadline) return 3;
    waiter.wait_until(std::min(deadline, after(0.05)));
  }
  std::cout << "flood ready" << std::endl;
  Command fake;
  fake.left_speed = 0.1;
  fake.right_speed = -0.1;
  fake.message.assign(1000, 0xab);
  fake.telemetry.events = {"flood 1", "flood 2", "flood 3", "flood 4"};
  Tick tick = 0;
  std::uint64_t sent = 0, refused = 0;
  RobotId next_made_up = 1000;
  auto write = [&](RobotId id) {
    try {
      commands.step(id, tick, fake);
      ++sent;
    } catch (const dds::DdsError&) {  // the writer's history is full (reliable): the wire pushes back
      ++refused;
    }
  };
  const dds_time_t end = after(seconds);
  while (dds_time() < end) {
    if (auto s = state.take()) tick = s->tick;
    for (std::uint32_t k = 0; k < ids; ++k) {
      write(k);
      if (made_up) write(next_made_up++);
      if (claims) {
        try {
          commands.claim(static_cast<RobotId>(ids + (sent % 100000)), 0xbad0000 + sent, 0);
        } catch (const dds::DdsError&) {
          ++refused;
        }
      }
    }
  }
  std::cout << "flood sent=" << sent << " refused=" << refused << std::endl;
  return 0;
}

int claim_storm(dds::Participant& participant, double seconds, std::uint32_t first, double timeout_s) {
  dds::Waiter waiter(participant);
  dds::CommandWriter commands(participant);
  const dds_time_t deadline = after(timeout_s);
  commands.set_stamp(run_nonce_of(participant, deadline));  // claims of this run: refused for their ids only
  while (!dds::writer_matched(commands.get())) {
    if (dds_time() >= deadline) return 3;
    waiter.wait_until(std::min(deadline, after(0.05)));
  }
  std::cout << "claims ready" << std::endl;
  std::uint64_t sent = 0;
  const dds_time_t end = after(seconds);
  while (dds_time() < end) {
    try {
      commands.claim(static_cast<RobotId>(first + sent % 100000), 0xbad0000 + sent, 0);
      ++sent;
    } catch (const dds::DdsError&) {
    }
  }
  std::cout << "claims sent=" << sent << std::endl;
  return 0;
}

int slow_agent(dds::Participant& participant, RobotId id, int delay_ms, bool realtime, double timeout_s) {
  const Command stand;  // zero wheel speeds, nothing said
  return answering_agent(participant, id, realtime, timeout_s, "slow", [&](const Perception&) {
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    return std::optional<Command>(stand);
  });
}

int forge(dds::Participant& participant, RobotId target, bool realtime, double timeout_s) {
  dds::Waiter waiter(participant);
  dds::WorldStateReader state(participant);
  dds::AgentInbox spy(participant, target, waiter, realtime);  // unbound: reads whatever comes to robot/K
  dds::RobotChannels channels(participant, target + 1, realtime);
  waiter.attach(state.condition());
  waiter.attach(spy.packet_condition());
  const dds_time_t deadline = after(timeout_s);
  dds::SensorSample real;
  std::uint64_t foreign = 0;
  std::uint64_t sent = 0;
  bool learned = false;
  Perception fake;
  fake.pose = Pose2D{9.0, 9.0, 1.0};
  fake.ultrasonic.fill(0.01);  // a wall everywhere
  while (dds_time() < deadline) {
    if (spy.take_packet(real, foreign) && real.status == dds::PacketStatus::Run && !learned) {
      channels.set_owner(target, real.owner_nonce, real.generation);
      learned = true;
    }
    if (auto s = state.take()) {
      if (s->finished) {
        std::cout << "forge sent=" << sent << std::endl;
        return 0;
      }
      channels.set_run_nonce(s->run_nonce);
      if (learned && s->tick >= 20) {
        fake.tick = s->tick + 1;
        channels.write_packet(target, dds::PacketStatus::Run, fake);
        channels.write_packet(target, dds::PacketStatus::End, fake);
        sent += 2;
      }
    }
    waiter.wait_until(std::min(deadline, after(0.05)));
  }
  std::cout << "forge sent=" << sent << " (timeout)" << std::endl;
  return 3;
}

int badwire(dds::Participant& participant, RobotId id, std::uint16_t version, std::uint64_t nonce,
            double timeout_s) {
  dds::Waiter waiter(participant);
  dds::AgentInbox inbox(participant, id, waiter);
  dds::CommandWriter commands(participant);
  commands.set_stamp(nonce, version);
  waiter.attach(inbox.packet_condition());
  const dds_time_t deadline = after(timeout_s);
  const std::uint64_t attempt = 0xbad0000u + id;
  std::uint64_t sent = 0;
  for (;;) {
    if (auto a = inbox.take_claim_reply(); a && a->nonce == attempt) {
      std::cerr << "rogue_agent: " << (a->accepted ? "accepted" : "refused: " + a->reason) << "\n";
      std::cout << "badwire sent=" << sent << std::endl;
      return a->accepted ? 0 : 4;
    }
    if (dds_time() >= deadline) {
      std::cout << "badwire sent=" << sent << " (timeout)" << std::endl;
      return 3;
    }
    commands.claim(id, attempt, 0);
    ++sent;
    waiter.wait_until(std::min(deadline, after(0.1)));
  }
}

int stranger(dds::Participant& participant, RobotId id, std::uint32_t pid, double timeout_s) {
  dds_guid_t guid{};
  if (dds_get_guid(participant.get(), &guid) != DDS_RETCODE_OK) return 1;
  dds::ParticipantKey key{};
  std::copy(std::begin(guid.v), std::end(guid.v), key.begin());
  std::cout << "stranger participant=" << dds::to_string(key) << std::endl;
  dds::Waiter waiter(participant);
  dds::AgentInbox inbox(participant, id, waiter);
  dds::CommandWriter commands(participant);
  waiter.attach(inbox.packet_condition());
  const dds_time_t deadline = after(timeout_s);
  commands.set_stamp(run_nonce_of(participant, deadline));
  const std::uint64_t attempt = 0x57a0000u + id;
  for (;;) {
    if (auto a = inbox.take_claim_reply(); a && a->nonce == attempt) {
      std::cerr << "rogue_agent: " << (a->accepted ? "accepted" : "refused: " + a->reason) << "\n";
      return a->accepted ? 0 : 4;
    }
    if (dds_time() >= deadline) return 3;
    commands.claim(id, attempt, pid);
    waiter.wait_until(std::min(deadline, after(0.2)));
  }
}

int silent_agent(dds::Participant& participant, RobotId id, double timeout_s) {
  return answering_agent(participant, id, false, timeout_s, "silent",
                         [](const Perception&) { return std::optional<Command>(); });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "rogue_agent: a spoofing, NaN-sending, slow, silent, lying, deaf, flooding or claim-storming "
      "participant for "
      "the integration tests"};
  app.require_subcommand(1);
  std::uint32_t domain = 0;
  double timeout_s = 60.0;
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0u, 232u));
  app.add_option("--timeout", timeout_s, "give up after this many seconds");
  std::vector<std::string> peers;
  app.add_option("--peer", peers,
                 "HOST:PORT: another discovery peer beside the world (forge: the target agent's "
                 "ports, as a forger on the host would find them)");
  auto* sp = app.add_subcommand("spoof", "write commands for another robot's id");
  std::uint32_t target = 0;
  sp->add_option("--target", target, "the robot to impersonate")->required();
  auto* na = app.add_subcommand("nan", "own an id and send NaN/oversize commands");
  std::uint32_t id = 0;
  na->add_option("--id", id, "the id to claim")->required();
  auto* sl = app.add_subcommand("slow", "own an id and answer every packet late");
  sl->add_option("--id", id, "the id to claim")->required();
  int delay_ms = 150;
  sl->add_option("--delay-ms", delay_ms, "how long after taking a packet it answers")
      ->check(CLI::Range(0, 10000));
  auto* si = app.add_subcommand("silent", "own an id, stay alive, and never answer a packet");
  si->add_option("--id", id, "the id to claim")->required();
  bool realtime = false;
  sl->add_flag("--realtime", realtime, "best-effort endpoints, for a world in realtime mode");
  auto* fo = app.add_subcommand("forge", "write forged perceptions and END packets into robot/K");
  fo->add_option("--target", target, "the robot whose partition it writes into")->required();
  fo->add_flag("--realtime", realtime, "best-effort endpoints, for a world in realtime mode");
  auto* bw = app.add_subcommand("badwire", "claim an id with another wire version or run nonce");
  bw->add_option("--id", id, "the id to claim")->required();
  std::uint16_t version = dds::kWireVersion;
  std::string nonce_hex = "0";
  bw->add_option("--version", version, "the wire version to stamp");
  bw->add_option("--nonce", nonce_hex, "the run nonce to stamp (hex)");
  auto* li = app.add_subcommand("liar", "own an id, move honestly, report out-of-range telemetry");
  li->add_option("--id", id, "the id to claim")->required();
  auto* de = app.add_subcommand("deaf", "own an id, move honestly, take one tick's first packet as lost");
  de->add_option("--id", id, "the id to claim")->required();
  std::uint64_t deaf_tick = 40;
  de->add_option("--tick", deaf_tick, "the tick whose first packet is taken as lost");
  double seconds = 5.0;
  std::uint32_t ids = 8;
  auto* fl = app.add_subcommand("flood", "own nothing; write commands for every id as fast as possible");
  fl->add_option("--seconds", seconds, "how long to flood")->check(CLI::PositiveNumber);
  fl->add_option("--ids", ids, "ids 0..N-1 to write commands for")->check(CLI::Range(1u, 100000u));
  fl->add_flag("--realtime", realtime, "best-effort writer, for a world in realtime mode");
  bool made_up = false;
  fl->add_flag("--made-up", made_up, "also a command for a new made-up id after each one");
  bool with_claims = false;
  fl->add_flag("--claims", with_claims, "also a claim for an id outside the run after each one");
  auto* cs = app.add_subcommand("claims", "own nothing; claim made-up ids as fast as possible");
  cs->add_option("--seconds", seconds, "how long to claim")->check(CLI::PositiveNumber);
  std::uint32_t first = 1000;
  cs->add_option("--first", first, "the first id claimed");
  auto* st = app.add_subcommand("stranger", "claim an id with no token, stating any pid");
  st->add_option("--id", id, "the id to claim")->required();
  std::uint32_t stated_pid = 1;
  st->add_option("--pid", stated_pid, "the pid its claims state");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    dds::SignalWatch signals;
    dds::DdsSettings settings;
    settings.domain = domain;
    settings.role = dds::Role::Agent;
    settings.extra_peers = peers;
    dds::Participant participant(settings);
    if (sp->parsed()) return spoof(participant, target, timeout_s);
    if (sl->parsed()) return slow_agent(participant, id, delay_ms, realtime, timeout_s);
    if (si->parsed()) return silent_agent(participant, id, timeout_s);
    if (fo->parsed()) return forge(participant, target, realtime, timeout_s);
    if (bw->parsed())
      return badwire(participant, id, version, std::stoull(nonce_hex, nullptr, 16), timeout_s);
    if (li->parsed()) return liar_agent(participant, id, timeout_s);
    if (de->parsed()) return deaf_agent(participant, id, static_cast<Tick>(deaf_tick), timeout_s);
    if (fl->parsed()) return flood(participant, seconds, ids, made_up, with_claims, realtime, timeout_s);
    if (cs->parsed()) return claim_storm(participant, seconds, first, timeout_s);
    if (st->parsed()) return stranger(participant, id, stated_pid, timeout_s);
    return nan_agent(participant, id, timeout_s);
  } catch (const std::exception& e) {
    std::cerr << "rogue_agent: " << e.what() << "\n";
    return 1;
  }
}
