// A participant that does not belong to a `swarm run --secure` run, for its tests (tests/scripts/
// test_secure_e2e.py; docs/security.md):
//
//   outsider listen --domain D --robots N --seconds S [--security-dir DIR --identity NAME]
//       joins domain D as an agent would (the world on 127.0.0.1 as its discovery peer) with no certificate,
//       or with NAME's of DIR (a directory of another run's authority: a stranger with a certificate). For S
//       seconds, or until SIGTERM/SIGINT (a test lets it listen through a whole run, then stops it), it reads
//       the mission, the world state and the sensor packets of robots 0..N-1 (a subscriber in each robot/K),
//       and claims every id K from a writer in robot/K every 0.2 s. It prints one line
//         outsider samples=X readers_matched=R writers_matched=W participants_seen=P
//       X: samples taken on all its readers; R, W: the most writers its readers matched and readers its
//       writers matched at any moment; P: the most other participants its discovery saw at once (DDS Security
//       does not hide discovery: the world is seen, P >= 1, whatever else is refused); A, B: the readers and
//       writers it made; C: those its own permissions refused (with a certificate). Exit 0.
//   outsider impostor --domain D --security-dir DIR --identity robot-J --robots N --seconds S
//       robot J of this run, authenticated, reads the mission (for the run's nonce), then claims the other
//       ids K (0..N-1, K != J) in turn, one every 0.3 s, from its own writer in robot/J for S seconds counted
//       from the mission's arrival (a world slow to start under load still meets S seconds of claims); prints
//       "impostor sent=X writers_matched=W" (W >= 1: the claims reached the world, which must refuse each:
//       "the claimant is authenticated as robot J, not robot K").
//   outsider peek --domain D --security-dir DIR --identity NAME --partition-of K
//       as NAME of DIR, subscribes to robot K's sensor packets (a subscriber in robot/K). Prints
//       "subscribed robot/K" and exits 0 if DDS allowed it, or "refused: <why>" and exits 4.
//
// Exit 2 on bad flags, 1 on any other failure.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <memory>
#include <set>
#include <vector>

#include "common/dds/agent_inbox.hpp"
#include "common/dds/command_writer.hpp"
#include "common/dds/dds_error.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/mission_endpoints.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/security_config.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/dds/waiter.hpp"
#include "common/dds/world_state_endpoints.hpp"

namespace {

using namespace swarmform;
using dds::check;
using dds::DdsError;

// Takes (and returns the loan of) everything on `reader`; returns the valid samples. Type-free: loans.
std::uint64_t drain(dds_entity_t reader) {
  std::uint64_t got = 0;
  for (;;) {
    void* ptrs[16] = {};
    dds_sample_info_t infos[16];
    const dds_return_t n = dds_take(reader, ptrs, infos, 16, 16);
    if (n <= 0) return got;
    for (int i = 0; i < n; ++i) got += infos[i].valid_data ? 1 : 0;
    dds_return_loan(reader, ptrs, n);
  }
}

std::uint32_t readers_matched(dds_entity_t reader) {
  dds_subscription_matched_status_t st{};
  check(dds_get_subscription_matched_status(reader, &st), "dds_get_subscription_matched_status");
  return st.current_count;
}

std::uint32_t writers_matched(dds_entity_t writer) {
  dds_publication_matched_status_t st{};
  check(dds_get_publication_matched_status(writer, &st), "dds_get_publication_matched_status");
  return st.current_count;
}

int listen(dds::Participant& participant, std::uint32_t robots, double seconds, dds::SignalWatch& signals) {
  dds::Waiter waiter(participant);
  signals.notify(&waiter);
  // Every endpoint its own permissions allow (with a certificate, DDS Security refuses the others locally:
  // counted as skipped); none with no certificate.
  std::uint32_t skipped = 0;
  auto tolerant = [&skipped](auto make) {
    try {
      return make();
    } catch (const DdsError&) {
      ++skipped;
      return decltype(make())();
    }
  };
  auto mission = tolerant([&] { return std::make_unique<dds::MissionReader>(participant); });
  auto state = tolerant([&] { return std::make_unique<dds::WorldStateReader>(participant); });
  std::vector<dds_entity_t> readers;
  if (mission) readers.push_back(dds_get_parent(mission->condition()));
  if (state) readers.push_back(dds_get_parent(state->condition()));
  std::vector<std::unique_ptr<dds::AgentInbox>> inboxes;
  std::vector<std::pair<RobotId, std::unique_ptr<dds::CommandWriter>>> claims;
  for (RobotId k = 0; k < robots; ++k) {
    if (auto in = tolerant([&] { return std::make_unique<dds::AgentInbox>(participant, k, waiter); })) {
      // A reader's read condition's parent is the reader: samples are counted there, by loan, type-free.
      readers.push_back(dds_get_parent(in->packet_condition()));
      inboxes.push_back(std::move(in));
    }
    if (auto w = tolerant([&] { return std::make_unique<dds::CommandWriter>(participant, false, k); })) {
      claims.emplace_back(k, std::move(w));
    }
  }
  for (dds_entity_t r : readers) check(r, "dds_get_parent");
  const dds_entity_t participants =
      check(dds_create_reader(participant.get(), DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, nullptr),
            "dds_create_reader(DCPSParticipant)");
  dds_guid_t own{};
  check(dds_get_guid(participant.get(), &own), "dds_get_guid");

  std::uint64_t samples = 0;
  std::uint32_t most_readers = 0, most_writers = 0;
  std::size_t most_seen = 0;
  const dds_time_t end = dds_time() + static_cast<dds_duration_t>(seconds * 1e9);
  dds_time_t next_claim = 0;
  while (dds_time() < end && !signals.stop_requested()) {
    const dds_time_t now = dds_time();
    if (now >= next_claim) {
      for (const auto& [k, w] : claims) w->claim(k, 0x5eed + k, 1);
      next_claim = now + DDS_MSECS(200);
    }
    for (dds_entity_t r : readers) {
      samples += drain(r);
      most_readers = std::max(most_readers, readers_matched(r));
    }
    for (const auto& [k, w] : claims) most_writers = std::max(most_writers, writers_matched(w->get()));
    // Every participant discovery knows now (read, not taken: the builtin reader keeps the live ones).
    void* ptrs[64] = {};
    dds_sample_info_t infos[64];
    const dds_return_t n = dds_read(participants, ptrs, infos, 64, 64);
    std::set<std::string> others;
    for (int i = 0; i < std::max(n, 0); ++i) {
      if (!infos[i].valid_data || infos[i].instance_state != DDS_IST_ALIVE) continue;
      const auto* p = static_cast<const dds_builtintopic_participant_t*>(ptrs[i]);
      if (std::equal(std::begin(p->key.v), std::end(p->key.v), std::begin(own.v))) continue;
      others.insert(std::string(reinterpret_cast<const char*>(p->key.v), sizeof p->key.v));
    }
    if (n > 0) dds_return_loan(participants, ptrs, n);
    most_seen = std::max(most_seen, others.size());
    waiter.wait_until(std::min(end, now + DDS_MSECS(50)));
  }
  std::cout << "outsider samples=" << samples << " readers_matched=" << most_readers
            << " writers_matched=" << most_writers << " participants_seen=" << most_seen
            << " readers=" << readers.size() << " writers=" << claims.size() << " skipped=" << skipped
            << std::endl;
  signals.notify(nullptr);
  return 0;
}

int impostor(dds::Participant& participant, RobotId self, std::uint32_t robots, double seconds,
             dds::SignalWatch& signals) {
  dds::Waiter waiter(participant);
  signals.notify(&waiter);
  // The run's nonce from its mission (robot J may read it), so the claims pass the world's wire checks and
  // meet the identity check; one claim every 0.3 s, under the world's budget of claims a second a writer.
  dds::MissionReader mission(participant);
  waiter.attach(mission.condition());
  dds::RefusalLog refusals("outsider", std::cerr);
  dds::CommandWriter claims(participant, false, self);
  std::uint64_t sent = 0;
  std::uint32_t most_writers = 0;
  bool stamped = false;
  RobotId next = 0;
  // Until the mission comes, only a signal ends the wait: the S seconds of claims start with the nonce.
  const dds_duration_t claiming = static_cast<dds_duration_t>(seconds * 1e9);
  dds_time_t end = DDS_NEVER;
  while (dds_time() < end && !signals.stop_requested()) {
    if (auto m = mission.take(std::nullopt, refusals)) {
      claims.set_stamp(m->run_nonce);
      if (!stamped) end = dds_time() + claiming;
      stamped = true;
    }
    if (stamped) {
      if (next == self) next = (next + 1) % robots;
      claims.claim(next, 0xbad0 + next, 1);
      ++sent;
      next = (next + 1) % robots;
    }
    most_writers = std::max(most_writers, writers_matched(claims.get()));
    waiter.wait_until(std::min(end, dds_time() + DDS_MSECS(300)));
  }
  std::cout << "impostor sent=" << sent << " writers_matched=" << most_writers << std::endl;
  signals.notify(nullptr);
  return 0;
}

int peek(dds::Participant& participant, RobotId of) {
  dds::Waiter waiter(participant);
  try {
    dds::AgentInbox inbox(participant, of, waiter);
  } catch (const DdsError& e) {
    std::cout << "refused: " << e.what() << std::endl;
    return 4;
  }
  std::cout << "subscribed " << dds::robot_partition(of) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"outsider: a participant that is not part of a secure swarmform run (tests of --secure)"};
  app.require_subcommand(1);
  std::uint32_t domain = 0;
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0u, 232u))->required();
  std::string security_dir, identity;
  app.add_option("--security-dir", security_dir, "use this directory's identity NAME (--identity)");
  app.add_option("--identity", identity, "the identity of --security-dir to use: world, robot-K, observer");
  auto* li = app.add_subcommand("listen", "read everything, claim every id, count what comes");
  std::uint32_t robots = 9;
  double seconds = 10;
  li->add_option("--robots", robots, "robots 0..N-1 whose packets it tries to read")
      ->check(CLI::Range(1u, 256u));
  li->add_option("--seconds", seconds, "how long to listen")->check(CLI::Range(0.1, 600.0));
  auto* im = app.add_subcommand("impostor", "as robot J of this run, claim every other id");
  im->add_option("--robots", robots, "ids 0..N-1 to claim (all but its own)")->check(CLI::Range(1u, 256u));
  im->add_option("--seconds", seconds, "how long to claim")->check(CLI::Range(0.1, 600.0));
  auto* pk = app.add_subcommand("peek", "subscribe to robot K's packets with --identity's certificate");
  std::uint32_t of = 0;
  pk->add_option("--partition-of", of, "the robot whose partition to subscribe to")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  if (security_dir.empty() != identity.empty()) {
    std::cerr << "outsider: --security-dir and --identity go together\n";
    return 2;
  }
  try {
    dds::SignalWatch signals;
    dds::DdsSettings settings;
    settings.domain = domain;
    settings.role = dds::Role::Agent;
    if (!security_dir.empty()) settings.security = dds::security_files(security_dir, identity);
    dds::Participant participant(settings);
    if (pk->parsed()) return peek(participant, of);
    if (im->parsed()) {
      const std::string prefix = "robot-";
      if (identity.rfind(prefix, 0) != 0) {
        std::cerr << "outsider impostor: --identity must be robot-J\n";
        return 2;
      }
      return impostor(participant, static_cast<RobotId>(std::stoul(identity.substr(prefix.size()))), robots,
                      seconds, signals);
    }
    return listen(participant, robots, seconds, signals);
  } catch (const std::invalid_argument& e) {
    std::cerr << "outsider: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "outsider: " << e.what() << "\n";
    return 1;
  }
}
