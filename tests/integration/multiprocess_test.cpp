// Multi-process integration tests: the real world_server and robot_agent executables over DDS on
// loopback. Each test has its own DDS domain (test_domain(k), tests/support/test_domain.hpp), kills every
// process it started by pid (Process's destructor) and bounds every wait. The scenario: 8 random walkers,
// lockstep, 300 ticks (random_walk_8.yaml).
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/resource.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <thread>
#include <utility>

#include "common/exit_codes.hpp"
#include "tests/support/process_fixture.hpp"
#include "tests/support/test_domain.hpp"

namespace {

using swarmform::testing::eventually;
using swarmform::testing::kOpenEndedTicks;
using swarmform::testing::Process;
using swarmform::testing::read_file;
using Json = nlohmann::json;

constexpr int kRobots = 8;
constexpr double kRunDeadline = 60.0;  // s, for one whole run (it takes ~2 s)

const std::string kWorld = WORLD_SERVER_EXE;
const std::string kAgent = ROBOT_AGENT_EXE;
const std::string kRogue = ROGUE_AGENT_EXE;
const std::string kBare = BARE_ROUND_EXE;
const std::string kScenario = INTEGRATION_SCENARIO;

class MultiProcess : public swarmform::testing::ProcessFixture {
 protected:
  MultiProcess() : ProcessFixture("swarmform-it") {}
  Process& world(int domain, const std::string& run, std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {
        kWorld,     "--scenario",           kScenario,           "--out", path(run),
        "--domain", std::to_string(domain), "--connect-timeout", "30"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return start(argv, run + "-world");
  }
  Process& agent(int domain, int id, const std::string& tag) {
    return start({kAgent, "--id", std::to_string(id), "--domain", std::to_string(domain), "--timeout", "30"},
                 tag + "-agent" + std::to_string(id));
  }

  // A world for 2 robots on `domain` and agent 0, started (for the tests of what happens before the run).
  struct WorldAndAgent0 {
    Process& world;
    Process& agent0;
  };
  WorldAndAgent0 world_and_agent0(int domain, const std::string& run, std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {kWorld,
                                     "--scenario",
                                     kScenario,
                                     "--out",
                                     path(run),
                                     "--domain",
                                     std::to_string(domain),
                                     "--connect-timeout",
                                     "20",
                                     "--robots",
                                     "2",
                                     "--max-ticks",
                                     "30"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    Process& w = start(argv, run + "-world");
    return {w, agent(domain, 0, run)};
  }
  static bool agent0_claimed(const Process& w) {
    return eventually(20.0, [&] { return w.err().find("id 0 claimed by pid") != std::string::npos; });
  }

  // A world for 2 robots on `domain` whose agent 0 claimed its id and was SIGKILLed before the run, its
  // writer's lease lapsed since (a lapse before the first packet is not a loss: the id stays counted).
  // (integration_tests run serially: its tests reuse the stalled tests' domain.)
  Process& world_whose_agent0_died_before_the_run(int domain, const std::string& run,
                                                  std::vector<std::string> extra = {}) {
    auto [w, first] = world_and_agent0(domain, run, std::move(extra));
    EXPECT_TRUE(agent0_claimed(w)) << w.err();
    EXPECT_EQ(::kill(first.pid(), SIGKILL), 0);
    EXPECT_EQ(first.wait_for(5.0), 128 + SIGKILL);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // three writer leases: the lapse is seen
    return w;
  }

  Json summary(const std::string& run) const { return Json::parse(read_file(path(run) + "/summary.json")); }
  std::vector<Json> events(const std::string& run) const {
    std::vector<Json> out;
    std::istringstream in(read_file(path(run) + "/events.jsonl"));
    for (std::string line; std::getline(in, line);) {
      if (!line.empty()) out.push_back(Json::parse(line));
    }
    return out;
  }
  std::vector<Json> events_of(const std::string& run, const std::string& kind) const {
    std::vector<Json> out;
    for (Json& e : events(run)) {
      if (e.value("kind", "") == kind) out.push_back(std::move(e));
    }
    return out;
  }
  bool has_event(const std::string& run, const std::string& kind, int id) const {
    for (const Json& e : events_of(run, kind)) {
      if (e.value("id", -1) == id) return true;
    }
    return false;
  }

  // An agent stalled after its claim, before the run, for longer than its command writer's liveliness lease
  // (500 ms): SIGSTOP here, CPU starvation while 1024 agents start in bench/scale. Before the run a lapse is
  // not a loss (world_server/server.cpp pump): the agent keeps its id, the world counts the lapse, and the
  // run starts with it. Run `run` on `domain`, stalling agent 0 for `stall` (shorter than its participant's
  // 30 s lease: past that, DDS forgets the participant, and the agent comes back as a rebound claim).
  void stalled_before_the_run(int domain, const std::string& run, std::chrono::milliseconds stall) {
    auto [w, first] = world_and_agent0(domain, run);
    ASSERT_TRUE(agent0_claimed(w)) << w.err();
    ASSERT_EQ(::kill(first.pid(), SIGSTOP), 0);
    std::this_thread::sleep_for(stall);
    ASSERT_EQ(::kill(first.pid(), SIGCONT), 0);
    Process& second = agent(domain, 1, run);
    ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
    EXPECT_NE(w.out().find("done ticks=30"), std::string::npos) << w.out();
    EXPECT_EQ(first.wait_for(10.0), 0) << first.err();
    EXPECT_EQ(second.wait_for(10.0), 0) << second.err();
    EXPECT_NE(w.err().find("liveliness lapsed"), std::string::npos) << w.err();  // the stall did lapse
    EXPECT_FALSE(has_event(run, "agent_lost", 0));                               // but lost nothing
    EXPECT_EQ(events_of(run, "agent_connected").size(), 2u);  // each connected once, never re-counted
  }

  // A whole clean run: world + 8 agents; returns the trajectory hash. Checks every agent saw only its own
  // packets, every process exited 0, the run completed.
  std::string clean_run(int domain, const std::string& run, Process* also = nullptr) {
    Process& w = world(domain, run);
    if (also != nullptr) {
      EXPECT_TRUE(eventually(20.0, [&] { return also->out().find(" ready") != std::string::npos; }))
          << also->err();
    }
    std::vector<Process*> agents;
    for (int i = 0; i < kRobots; ++i) agents.push_back(&agent(domain, i, run));
    EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
    EXPECT_NE(w.out().find("done ticks=300 run_dir=" + path(run)), std::string::npos) << w.out();
    for (int i = 0; i < kRobots; ++i) {
      EXPECT_EQ(agents[i]->wait_for(10.0), 0) << "agent " << i << ": " << agents[i]->err();
      // The last tick's packet is followed by the END packet: 301 packets, none of another robot.
      EXPECT_NE(agents[i]->out().find("agent id=" + std::to_string(i) + " packets=301 foreign_packets=0"),
                std::string::npos)
          << agents[i]->out();
    }
    if (also != nullptr) {
      EXPECT_TRUE(also->wait_for(10.0).has_value());
    }
    const Json s = summary(run);
    EXPECT_EQ(s["ticks"], 300);
    EXPECT_EQ(s["robots"], kRobots);
    EXPECT_EQ(s["alive_at_end"], kRobots);
    // The steady rate leaves out the default 100 warm-up ticks: its 200 ticks took part of the run's wall
    // time.
    EXPECT_EQ(s["steady_from_tick"], 100);
    EXPECT_TRUE(s["steady_ticks_per_second"].is_number()) << s.dump();
    if (s["steady_ticks_per_second"].is_number()) {
      const double steady_seconds = 200.0 / s["steady_ticks_per_second"].get<double>();
      EXPECT_GT(steady_seconds, 0.0);
      EXPECT_LT(steady_seconds, s["wall_seconds"].get<double>());
    }
    EXPECT_EQ(events_of(run, "agent_connected").size(), static_cast<std::size_t>(kRobots));
    return s.value("trajectory_sha256", "");
  }
};

// The world's resident memory (kB) now, 0 when it cannot be read (the process is gone).
long rss_kb(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(f, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return 0;
}

// Waits for `p` to exit within `seconds`, sampling its resident memory every 50 ms; returns the exit code
// (nullopt on the deadline) and puts the peak in `peak_kb`.
std::optional<int> wait_sampling_rss(Process& p, double seconds, long& peak_kb) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  peak_kb = 0;
  while (std::chrono::steady_clock::now() < end) {
    peak_kb = std::max(peak_kb, rss_kb(p.pid()));
    if (const auto code = p.wait_for(0.05)) return code;
  }
  return std::nullopt;
}

std::size_t dir_bytes(const std::string& dir) {
  std::size_t total = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) total += e.file_size();
  }
  return total;
}

std::size_t count_lines(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) n += line.find(needle) != std::string::npos ? 1 : 0;
  return n;
}

TEST_F(MultiProcess, EightAgentsInLockstepGetOnlyTheirOwnPacketsAndRepeatBitForBit) {
  const int domain = swarmform::testing::test_domain(1);
  const std::string first = clean_run(domain, "first");
  const std::string second = clean_run(domain, "second");
  EXPECT_EQ(first.size(), 64u);
  EXPECT_EQ(first, second);
}

// The run is open-ended (kOpenEndedTicks): ended by SIGTERM once the restarted agent has rejoined.
TEST_F(MultiProcess, KilledAgentIsDetectedWithinOneSecondAndOneRestartedByHandRejoinsWithOpenRejoin) {
  const int domain = swarmform::testing::test_domain(2);
  std::vector<Process*> agents;
  for (int i = 0; i < kRobots; ++i) agents.push_back(&agent(domain, i, "kill"));
  // The agent is restarted by hand, as --open-rejoin allows (docs/wire.md "Claim proofs").
  Process& w = world(domain, "kill",
                     {"--max-ticks", kOpenEndedTicks, "--kill", "3@100", "--agent-pid",
                      "3=" + std::to_string(agents[3]->pid()), "--open-rejoin"});
  ASSERT_TRUE(eventually(kRunDeadline, [&] { return has_event("kill", "death", 3) || !w.running(); }));
  EXPECT_EQ(agents[3]->wait_for(1.0), 128 + 9);  // it was SIGKILLed
  Process& again = agent(domain, 3, "kill-again");
  // The world prints the rejoin on stdout at once (events.jsonl is buffered).
  EXPECT_TRUE(eventually(kRunDeadline, [&] {
    return w.out().find("rejoin id=3 ") != std::string::npos || !w.running();
  })) << w.out();
  ASSERT_TRUE(w.running()) << w.err();
  // Taken without a token: the world says so, naming the claimant's participant.
  EXPECT_NE(w.err().find("id 3 claimed by pid " + std::to_string(again.pid()) + " (participant "),
            std::string::npos)
      << w.err();
  EXPECT_NE(w.err().find("), unissued"), std::string::npos) << w.err();
  ASSERT_EQ(::kill(w.pid(), SIGTERM), 0);
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(again.wait_for(10.0), 0) << again.err() << w.err();
  for (int i = 0; i < kRobots; ++i) {
    if (i == 3) continue;
    EXPECT_EQ(agents[i]->wait_for(10.0), 0) << i << ": " << agents[i]->err();
  }

  const Json s = summary("kill");
  EXPECT_EQ(s["end_reason"], "interrupted");
  ASSERT_EQ(s["deaths"].size(), 1u);
  EXPECT_EQ(s["deaths"][0]["id"], 3);
  // Lockstep waits for the dead agent until DDS liveliness says it is gone, so its death is recorded at the
  // tick of the kill, or at most one second's worth of ticks (tick_rate 10) later.
  EXPECT_GE(s["deaths"][0]["tick"].get<int>(), 100);
  EXPECT_LE(s["deaths"][0]["tick"].get<int>(), 110);
  const auto detected = events_of("kill", "death_detected");
  ASSERT_EQ(detected.size(), 1u);
  std::smatch m;
  const std::string detail = detected[0]["detail"];
  ASSERT_TRUE(std::regex_search(detail, m, std::regex("detected ([0-9]+) ms after SIGKILL"))) << detail;
  EXPECT_LE(std::stoi(m[1]), 1000) << detail;
  // The restarted agent with the same id came back as a fresh robot.
  ASSERT_EQ(s["rejoins"].size(), 1u);
  EXPECT_EQ(s["rejoins"][0]["id"], 3);
  EXPECT_EQ(s["alive_at_end"], kRobots);
}

TEST_F(MultiProcess, SecondAgentWithATakenIdIsRefused) {
  const int domain = swarmform::testing::test_domain(3);
  Process& w = world(domain, "dup");
  Process& first = agent(domain, 2, "dup");
  ASSERT_TRUE(eventually(30.0, [&] { return w.err().find("id 2 claimed by pid") != std::string::npos; }));
  Process& second = agent(domain, 2, "dup-second");
  const auto code = second.wait_for(20.0);
  EXPECT_EQ(code, swarmform::exit_codes::kExitIdRefused) << second.err();
  EXPECT_NE(second.err().find("refused: id 2 is already owned by a live agent"), std::string::npos)
      << second.err();
  for (int i = 0; i < kRobots; ++i) {
    if (i != 2) agent(domain, i, "dup");
  }
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(first.wait_for(10.0), 0) << first.err();
  EXPECT_EQ(summary("dup")["alive_at_end"], kRobots);
  EXPECT_TRUE(has_event("dup", "claim_refused", 2));
}

TEST_F(MultiProcess, CommandsFromAWriterThatDoesNotOwnTheIdAreDroppedAndLogged) {
  const int domain = swarmform::testing::test_domain(4);
  const std::string baseline = clean_run(domain, "baseline");
  Process& spoofer = start(
      {kRogue, "--domain", std::to_string(domain), "--timeout", "60", "spoof", "--target", "5"}, "spoofer");
  const std::string spoofed = clean_run(domain, "spoofed", &spoofer);
  EXPECT_FALSE(events_of("spoofed", "spoofed_command").empty());
  for (const Json& e : events_of("spoofed", "spoofed_command")) EXPECT_EQ(e["id"], 5);
  // Ignored means ignored: the robot moved exactly as without the spoofer.
  EXPECT_EQ(spoofed, baseline);
}

TEST_F(MultiProcess, NonFiniteAndOversizeCommandsAreRejectedLoggedAndTheRunGoesOn) {
  const int domain = swarmform::testing::test_domain(5);
  Process& w = world(domain, "nan");
  for (int i = 0; i < kRobots - 1; ++i) agent(domain, i, "nan");
  Process& rogue =
      start({kRogue, "--domain", std::to_string(domain), "--timeout", "60", "nan", "--id", "7"}, "rogue");
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(rogue.wait_for(10.0), 0) << rogue.err();
  std::set<std::string> verdicts;
  for (const Json& e : events_of("nan", "command")) {
    EXPECT_EQ(e["id"], 7);
    verdicts.insert(e.value("verdict", ""));
  }
  EXPECT_TRUE(verdicts.count("rejected_non_finite")) << verdicts.size();
  EXPECT_TRUE(verdicts.count("message_dropped") || verdicts.count("clamped"));
  const Json s = summary("nan");
  EXPECT_EQ(s["ticks"], 300);
  EXPECT_EQ(s["alive_at_end"], kRobots);
  // Every bad command counted, but logged once a second per robot and verdict (with the
  // count it stands for), not once a tick.
  EXPECT_GE(s["command_verdicts"].get<int>(), 290) << s.dump();
  const std::size_t seconds = static_cast<std::size_t>(s["wall_seconds"].get<double>()) + 2;
  EXPECT_LE(events_of("nan", "command").size(), 2 * seconds);
}

TEST_F(MultiProcess, WorldNamesTheAgentsMissingAtTheConnectTimeout) {
  // 10 s: time enough for agent 0 to find the world and claim on a loaded 2-core machine (with 1 s it was
  // sometimes still discovering, and all 8 were named).
  const int domain = swarmform::testing::test_domain(6);
  Process& w = start({kWorld, "--scenario", kScenario, "--out", path("missing"), "--domain",
                      std::to_string(domain), "--connect-timeout", "10"},
                     "missing-world");
  agent(domain, 0, "missing");
  EXPECT_EQ(w.wait_for(60.0), swarmform::exit_codes::kExitAgentsMissing);
  EXPECT_NE(w.err().find("7 of 8 agents missing, and none claimed its id in the last 10 s"),
            std::string::npos)
      << w.err();
  EXPECT_NE(w.err().find(" since the world was ready): 1-7"), std::string::npos) << w.err();
}

// The connect wait counts from the last claim, not from the start: agents that keep coming (1024 starting on
// a busy host) are slow, not missing. Three groups of agents 6 s apart with --connect-timeout 10: the last
// claims come ~13 s after the start, past a deadline counted from it, yet never 10 s after a claim.
TEST_F(MultiProcess, TheConnectTimeoutCountsFromTheLastClaimNotFromTheStart) {
  const int domain = swarmform::testing::test_domain(6);
  Process& w = start({kWorld, "--scenario", kScenario, "--out", path("trickle"), "--domain",
                      std::to_string(domain), "--connect-timeout", "10", "--max-ticks", "20"},
                     "trickle-world");
  const auto claims = [&w] {
    std::size_t n = 0;
    for (std::size_t at = w.err().find(" claimed by "); at != std::string::npos;
         at = w.err().find(" claimed by ", at + 1))
      ++n;
    return n;
  };
  const auto began = std::chrono::steady_clock::now();
  for (const auto& group : {std::pair{0, 2}, std::pair{3, 5}, std::pair{6, 7}}) {
    const int first = group.first;  // not a structured binding: clang 14 cannot capture one in a lambda
    const int last = group.second;
    if (first > 0) {
      // The previous group has all claimed; the next comes 6 s later.
      ASSERT_TRUE(eventually(30.0, [&] { return claims() == static_cast<std::size_t>(first); })) << w.err();
      std::this_thread::sleep_for(std::chrono::seconds(6));
    }
    for (int id = first; id <= last; ++id) agent(domain, id, "trickle");
  }
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_GT(std::chrono::steady_clock::now() - began, std::chrono::seconds(12));
  EXPECT_EQ(summary("trickle")["ticks"], 20);
}

TEST_F(MultiProcess, AgentGivesUpWhenNoWorldShowsUp) {
  Process& a = start(
      {kAgent, "--id", "0", "--domain", std::to_string(swarmform::testing::test_domain(7)), "--timeout", "1"},
      "lonely");
  EXPECT_EQ(a.wait_for(15.0), swarmform::exit_codes::kExitNoWorld);
  EXPECT_NE(a.err().find("no world on DDS domain"), std::string::npos) << a.err();
}

TEST_F(MultiProcess, AgentStalledPastItsWriterLeaseBeforeTheRunIsCountedAgain) {
  stalled_before_the_run(swarmform::testing::test_domain(8), "stalled", std::chrono::milliseconds(750));
}

// 3 s: past what was the agent's participant lease (1 s), after which the world forgot the participant and
// never heard the agent again; within the 30 s it is now (common/dds/cyclone_config.cpp).
TEST_F(MultiProcess, AgentStalledForThreeSecondsBeforeTheRunIsCountedAgain) {
  stalled_before_the_run(swarmform::testing::test_domain(10), "stalled-long",
                         std::chrono::milliseconds(3000));
}

// An agent killed before the run and restarted (by hand: --open-rejoin) need not wait for the dead one's
// participant lease (30 s): the lapsed id is taken over, and the run starts with the new agent.
TEST_F(MultiProcess, AgentKilledBeforeTheRunIsReplacedByARestartedOne) {
  const int domain = swarmform::testing::test_domain(8);
  Process& w = world_whose_agent0_died_before_the_run(domain, "restarted", {"--open-rejoin"});
  Process& again = start({kAgent, "--id", "0", "--domain", std::to_string(domain), "--timeout", "30"},
                         "restarted-agent0-again");
  Process& second = agent(domain, 1, "restarted");
  ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_NE(w.out().find("done ticks=30"), std::string::npos) << w.out();
  EXPECT_EQ(again.wait_for(10.0), 0) << again.err() << w.err();
  EXPECT_EQ(second.wait_for(10.0), 0) << second.err();
  EXPECT_EQ(events_of("restarted", "agent_connected").size(), 3u) << w.err();  // 0 twice: taken over
  EXPECT_EQ(w.err().find("refused a claim"), std::string::npos) << w.err();
}

// The same in a world started by hand without --open-rejoin: it cannot tell an agent restarted by hand from a
// stranger that read the run nonce, so the id that had an owner is not taken (docs/wire.md "Claim proofs");
// the refusal names the claimant's participant. The run starts with agent 0 counted, and it is dead at its
// first packet.
TEST_F(MultiProcess, AnAgentStartedByHandCannotTakeAnOwnedIdWithoutOpenRejoin) {
  const int domain = swarmform::testing::test_domain(8);
  Process& w = world_whose_agent0_died_before_the_run(domain, "closed");
  Process& again = start({kAgent, "--id", "0", "--domain", std::to_string(domain), "--timeout", "30"},
                         "closed-agent0-again");
  EXPECT_EQ(again.wait_for(30.0), swarmform::exit_codes::kExitIdRefused) << again.err();
  EXPECT_NE(again.err().find("refused: id 0 had an owner"), std::string::npos) << again.err();
  EXPECT_NE(again.err().find("--open-rejoin"), std::string::npos) << again.err();
  EXPECT_NE(
      w.err().find("refused a claim of id 0 from pid " + std::to_string(again.pid()) + " (participant "),
      std::string::npos)
      << w.err();
  Process& second = agent(domain, 1, "closed");
  ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(second.wait_for(10.0), 0) << second.err();
  const Json s = summary("closed");
  EXPECT_EQ(s["alive_at_end"], 1) << w.err();
  EXPECT_GE(s["input_dropped"]["unproven_claims"].get<int>(), 1) << s["input_dropped"].dump();
  EXPECT_EQ(events_of("closed", "agent_connected").size(), 2u);  // 0 once (the dead one) and 1
}

// Not replaced: the run starts with it counted; it does not answer its first packet, and the world takes it
// for dead 2 s (awake) later, not when its participant's lease (30 s) runs out.
TEST_F(MultiProcess, AgentKilledBeforeTheRunIsDeadOnceItMissesItsFirstPacket) {
  const int domain = swarmform::testing::test_domain(8);
  Process& w = world_whose_agent0_died_before_the_run(domain, "killed");
  Process& second = agent(domain, 1, "killed");
  ASSERT_EQ(w.wait_for(25.0), 0) << w.err();  // well before the dead participant's 30 s lease
  EXPECT_NE(w.out().find("done ticks=30"), std::string::npos) << w.out();
  EXPECT_EQ(second.wait_for(10.0), 0) << second.err();
  EXPECT_TRUE(has_event("killed", "death_detected", 0)) << w.err();
  EXPECT_FALSE(has_event("killed", "death_detected", 1));
  EXPECT_EQ(summary("killed")["alive_at_end"], 1) << w.err();
}

// The same lapse, but the agent is only stopped (starved, as 1024 agents starting on 2 cores are) and the
// world knows its process (--agent-pids, as the launcher writes it): in lockstep it is a straggler, waited
// for past the 2 s its first packet allows, not a death at tick 0; continued, it answers and the run ends
// with both robots alive.
TEST_F(MultiProcess, AgentStoppedBeforeItsFirstPacketIsWaitedForNotBuriedWhenTheWorldSeesItsProcess) {
  const int domain = swarmform::testing::test_domain(8);
  const std::string pids = path("stopped-first.pids.json");
  auto [w, first] = world_and_agent0(domain, "stopped-first", {"--agent-pids", pids});
  ASSERT_TRUE(agent0_claimed(w)) << w.err();
  ASSERT_EQ(::kill(first.pid(), SIGSTOP), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // three writer leases: the lapse is seen
  Process& second = agent(domain, 1, "stopped-first");
  std::ofstream(pids) << "{\"0\": " << first.pid() << ", \"1\": " << second.pid() << "}";
  // The run starts; agent 0's first packet waits in its socket past the 2 s it is given.
  const bool stalled = eventually(20.0, [&] { return has_event("stopped-first", "agent_stalled", 0); });
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  ASSERT_EQ(::kill(first.pid(), SIGCONT), 0);
  ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_TRUE(stalled) << w.err();
  EXPECT_EQ(first.wait_for(10.0), 0) << first.err();
  EXPECT_EQ(second.wait_for(10.0), 0) << second.err();
  EXPECT_FALSE(has_event("stopped-first", "death_detected", 0)) << w.err();
  const Json s = summary("stopped-first");
  EXPECT_EQ(s["alive_at_end"], 2) << w.err();
  EXPECT_EQ(s["ticks"], 30);
}

// An agent waiting for the run is quiet from 2 s after its claim (no liveliness assertions, a re-claim every
// 5 s: robot_agent/dds_link.hpp), so its writer's lease lapses; the world does not judge it before its first
// packet, so it keeps its id however long the others take to come.
TEST_F(MultiProcess, AgentWaitingForTheRunIsQuietAndKeepsItsId) {
  const int domain = swarmform::testing::test_domain(9);
  auto [w, first] = world_and_agent0(domain, "waiting");
  ASSERT_TRUE(agent0_claimed(w)) << w.err();
  std::this_thread::sleep_for(std::chrono::seconds(4));  // quiet after 2 s: four writer leases
  Process& second = agent(domain, 1, "waiting");
  ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(first.wait_for(10.0), 0) << first.err();
  EXPECT_EQ(second.wait_for(10.0), 0) << second.err();
  EXPECT_NE(w.err().find("liveliness lapsed"), std::string::npos) << w.err();  // it was quiet
  EXPECT_FALSE(has_event("waiting", "agent_lost", 0));                         // and lost nothing
  EXPECT_EQ(events_of("waiting", "agent_connected").size(), 2u);  // each connected once, never re-counted
}

// robot_agent --count: the robots of a block each run as their own process (forked from the one started),
// each killable by its pid as any agent, and the block's pid stops them all.
std::map<int, pid_t> block_pids(const Process& block) {
  std::map<int, pid_t> out;
  std::istringstream in(block.out());
  const std::regex line("robot_agent: id ([0-9]+) pid ([0-9]+)");
  std::smatch m;
  for (std::string l; std::getline(in, l);) {
    if (std::regex_search(l, m, line)) out[std::stoi(m[1])] = static_cast<pid_t>(std::stol(m[2]));
  }
  return out;
}

// Gone, or a zombie nobody has reaped yet (the container's init may not reap): either way not running.
bool not_running(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(f, stat)) return true;
  const auto close = stat.rfind(')');
  return close != std::string::npos && close + 2 < stat.size() && stat[close + 2] == 'Z';
}

TEST_F(MultiProcess, AgentBlockRunsEachRobotAsItsOwnProcessAndAKilledOneIsDetected) {
  const int domain = swarmform::testing::test_domain(12);
  Process& block = start({kAgent, "--id", "0", "--count", std::to_string(kRobots), "--domain",
                          std::to_string(domain), "--timeout", "30"},
                         "block");
  ASSERT_TRUE(eventually(20.0, [&] { return block_pids(block).size() == kRobots; })) << block.out();
  const std::map<int, pid_t> pids = block_pids(block);
  std::set<pid_t> distinct;
  for (const auto& [id, pid] : pids) distinct.insert(pid);
  EXPECT_EQ(distinct.size(), static_cast<std::size_t>(kRobots));
  EXPECT_EQ(distinct.count(block.pid()), 0u);
  Process& w = world(domain, "block", {"--kill", "3@50", "--agent-pid", "3=" + std::to_string(pids.at(3))});
  ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(block.wait_for(10.0), 128 + SIGKILL) << block.err();  // the highest child exit: robot 3's
  for (int i = 0; i < kRobots; ++i) {
    if (i == 3) continue;
    EXPECT_NE(block.out().find("agent id=" + std::to_string(i) + " packets=301 foreign_packets=0"),
              std::string::npos)
        << block.out();
  }
  const Json s = summary("block");
  ASSERT_EQ(s["deaths"].size(), 1u);
  EXPECT_EQ(s["deaths"][0]["id"], 3);
  EXPECT_EQ(s["alive_at_end"], kRobots - 1);
  EXPECT_EQ(events_of("block", "agent_connected").size(), static_cast<std::size_t>(kRobots));
}

TEST_F(MultiProcess, StoppingOrKillingAnAgentBlockStopsEveryRobotInIt) {
  const int domain = swarmform::testing::test_domain(13);  // no world: the robots wait for one
  for (const int sig : {SIGTERM, SIGKILL}) {
    const std::string tag = sig == SIGTERM ? "term" : "kill";
    Process& block =
        start({kAgent, "--id", "5", "--count", "4", "--domain", std::to_string(domain), "--timeout", "30"},
              "block-" + tag);
    ASSERT_TRUE(eventually(20.0, [&] { return block_pids(block).size() == 4u; })) << block.out();
    const std::map<int, pid_t> pids = block_pids(block);
    EXPECT_EQ(pids.begin()->first, 5);
    EXPECT_EQ(pids.rbegin()->first, 8);
    ASSERT_EQ(::kill(block.pid(), sig), 0);
    // SIGTERM: forwarded to each robot, which stops as a lone agent would (128 + 15), and so does the block.
    // SIGKILL: the block cannot forward it; each robot gets SIGTERM when its parent dies.
    EXPECT_EQ(block.wait_for(10.0), 128 + sig) << block.err();
    for (const auto& [id, pid] : pids) {
      EXPECT_TRUE(eventually(10.0, [pid = pid] { return not_running(pid); })) << "robot " << id << " " << tag;
    }
  }
}

// bench/bare_round's robots stand in for agents against the real world (how BENCHMARKS.md splits P1's gap
// between the world and the agents): they claim, answer every packet, and their --reply-bytes message reaches
// the world. 2000 bytes is over the scenario's max_message_bytes (1024), so every command is then counted as
// not taken as it came; 50 bytes (the random walk's broadcast) is within it.
TEST_F(MultiProcess, BareRoundRobotsAnswerTheRealWorldWithTheirReplyMessage) {
  const int domain = swarmform::testing::test_domain(14);
  for (const auto& [bytes, oversize] : {std::pair{"50", false}, std::pair{"2000", true}}) {
    const std::string run = std::string("bare-") + bytes;
    Process& robots = start({kBare, "--domain", std::to_string(domain), "--timeout", "30", "robot", "--id",
                             "0", "--count", "4", "--reply-bytes", bytes},
                            run + "-robots");
    Process& w = world(domain, run, {"--robots", "4", "--max-ticks", "40"});
    ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
    EXPECT_EQ(robots.wait_for(10.0), 0) << robots.err();
    const Json s = summary(run);
    EXPECT_EQ(s["ticks"], 40);
    EXPECT_EQ(s["alive_at_end"], 4);
    if (oversize) {
      EXPECT_GE(s["command_verdicts"].get<int>(), 4 * 40) << s.dump();
    } else {
      EXPECT_EQ(s["command_verdicts"], 0) << s.dump();
    }
  }
}

// Realtime at 10 ticks/s: robot 1's agent answers each packet 150 ms after taking it, so its commands miss
// their ticks and come in during a later one. The world counts the misses and, for each late command, says
// where its time went (a late_command event and a summary on stderr): here the agent's answer, longer than
// the whole 100 ms tick (the world's stamps put ~147-151 ms for the agent's 150 ms wait: a bound at the wait
// itself failed a fresh clone's run by 2 ms, so the test asserts what the event is for, that the answer took
// the tick).
TEST_F(MultiProcess, RealtimeWorldTellsWhereALateCommandsTimeWent) {
  const int domain = swarmform::testing::test_domain(15);
  Process& slow = start({kRogue, "--domain", std::to_string(domain), "--timeout", "30", "slow", "--id", "1",
                         "--delay-ms", "150", "--realtime"},
                        "slow");
  Process& fine = agent(domain, 0, "late");
  Process& w = world(domain, "late", {"--robots", "2", "--mode", "realtime", "--max-ticks", "30"});
  ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_TRUE(slow.wait_for(10.0).has_value());
  EXPECT_TRUE(fine.wait_for(10.0).has_value());
  EXPECT_NE(w.err().find(" late commands ("), std::string::npos) << w.err();
  // bench/scale/scale_run.py reads the count from a line that ends so.
  EXPECT_TRUE(std::regex_search(w.err(), std::regex("world_server: [0-9]+ missed ticks \\(see events\\)\n")))
      << w.err();
  const std::regex answered("answered ([0-9.]+) ms after it");
  int slow_answers = 0;
  for (const Json& e : events_of("late", "late_command")) {
    if (e.value("id", -1) != 1) continue;
    const std::string detail = e.value("detail", "");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(detail, m, answered)) << detail;
    EXPECT_GT(std::stod(m[1].str()), 100.0) << detail;
    ++slow_answers;
  }
  EXPECT_GE(slow_answers, 5) << "late commands of robot 1 in 30 ticks";
  EXPECT_TRUE(has_event("late", "missed_tick", 1));
}

TEST_F(MultiProcess, CheckPrintsTheScenarioAndBadInputExitsTwo) {
  Process& ok = start({kWorld, "--scenario", kScenario, "--robots", "5", "--seed", "9", "--check"}, "check");
  EXPECT_EQ(ok.wait_for(15.0), 0) << ok.err();
  const Json checked = Json::parse(ok.out());
  EXPECT_EQ(checked["robots"], 5);
  EXPECT_EQ(checked["labels"], 16);
  EXPECT_EQ(checked["mode"], "lockstep");
  EXPECT_EQ(checked["max_ticks"], 300);
  EXPECT_EQ(checked["seed"], 9);
  EXPECT_EQ(checked["behaviour_descriptor"]["name"], "random_walk") << ok.out();
  const std::string bad = path("bad.yaml");
  {
    std::ofstream f(bad);
    f << "mode: lockstep\nseed: 1\ntick_rate: -3\n";
  }
  Process& b = start({kWorld, "--scenario", bad, "--check"}, "bad");
  EXPECT_EQ(b.wait_for(15.0), swarmform::exit_codes::kExitBadInput);
  EXPECT_NE(b.err().find(bad + ":3:"), std::string::npos) << b.err();
  Process& flag = start({kWorld, "--scenario", kScenario, "--kill", "3-100"}, "badflag");
  EXPECT_EQ(flag.wait_for(15.0), swarmform::exit_codes::kExitBadInput);
  EXPECT_NE(flag.err().find("--kill 3-100"), std::string::npos) << flag.err();
  Process& noout = start({kWorld, "--scenario", kScenario}, "noout");
  EXPECT_EQ(noout.wait_for(15.0), swarmform::exit_codes::kExitBadInput);
  EXPECT_NE(noout.err().find("--out DIR is required"), std::string::npos) << noout.err();
}

// ---- untrusted input and clean ends, docs/faults.md (helper "abuse"; domains base + 37..39,
// tests/README.md)
// ----------------------

// A lockstep run of 3000 ticks, with or without the abuse of `rogues` (started first, each ready before the
// agents start). Returns the summary; `peak_kb` is the world's peak resident memory, `err` its stderr.
struct AbusedRun {
  Json summary;
  long peak_kb = 0;
  std::string err;
  std::size_t bytes = 0;
  std::size_t event_lines = 0;
};

class Abuse : public MultiProcess {
 protected:
  AbusedRun run_with(int domain, const std::string& run, const std::vector<std::vector<std::string>>& rogues,
                     const std::vector<std::string>& world_flags) {
    std::vector<Process*> started;
    for (std::size_t i = 0; i < rogues.size(); ++i) {
      std::vector<std::string> argv = {kRogue, "--domain", std::to_string(domain), "--timeout", "60"};
      argv.insert(argv.end(), rogues[i].begin(), rogues[i].end());
      started.push_back(&start(argv, run + "-rogue" + std::to_string(i)));
    }
    Process& w = world(domain, run, world_flags);
    for (Process* r : started) {
      EXPECT_TRUE(eventually(20.0, [&] { return r->out().find(" ready") != std::string::npos; })) << r->err();
    }
    std::vector<Process*> agents;
    for (int i = 0; i < kRobots; ++i) agents.push_back(&agent(domain, i, run));
    AbusedRun out;
    EXPECT_EQ(wait_sampling_rss(w, 120.0, out.peak_kb), 0) << w.err();
    for (int i = 0; i < kRobots; ++i) EXPECT_EQ(agents[i]->wait_for(10.0), 0) << agents[i]->err();
    for (Process* r : started) EXPECT_TRUE(r->wait_for(30.0).has_value()) << r->err();
    out.summary = summary(run);
    out.err = w.err();
    out.bytes = dir_bytes(path(run));
    out.event_lines = events(run).size();
    std::cout << run << ": world peak " << out.peak_kb / 1024 << " MB, run directory " << out.bytes / 1024
              << " KB, " << out.event_lines << " event lines, input_dropped "
              << out.summary["input_dropped"].dump() << "\n";
    return out;
  }
};

// One process floods, for 8 s, commands for every id (1 KB message, 4 event strings each), each followed by
// one for a new made-up id and a claim for an id outside the run. Each writer gets its budget a tick (the
// rest dropped and counted), what it sends is logged once a second, ids far outside the run never reach the
// reader's cache, refused claims keep no channel: the run is bit for bit the one without them, its
// directory and the world's memory barely grow. (8 s rather than scripts/bench-faults' 20 s: the same
// mechanism; scripts/bench-faults measures the 20 s flood and docs/faults.md has its figures.) Without the
// budgets and throttled reports every spoofed command was an event line (~25,000 here); without the reader's
// id filter the made-up ids grew the world by ~0.9 KB each (~300 MB here).
TEST_F(Abuse, FloodOfCommandsAndClaimsFromAProcessThatOwnsNoIdLeavesTheLockstepRunUnchanged) {
  const int domain = swarmform::testing::test_domain(41);
  const std::vector<std::string> ticks = {"--max-ticks", "3000"};
  const AbusedRun clean = run_with(domain, "clean", {}, ticks);
  const AbusedRun flooded = run_with(
      domain, "flooded", {{"flood", "--seconds", "8", "--ids", "8", "--made-up", "--claims"}}, ticks);
  ASSERT_EQ(clean.summary["ticks"], 3000);
  EXPECT_EQ(flooded.summary["trajectory_sha256"], clean.summary["trajectory_sha256"]);
  EXPECT_EQ(flooded.summary["alive_at_end"], kRobots);
  EXPECT_TRUE(flooded.summary["deaths"].empty());
  const Json& dropped = flooded.summary["input_dropped"];
  EXPECT_GT(dropped["commands_over_limit"].get<long>(), 0) << dropped.dump();
  EXPECT_GT(dropped["spoofed_commands"].get<long>(), 0) << dropped.dump();
  EXPECT_GT(dropped["out_of_range_ids"].get<long>(), 0) << dropped.dump();
  // The rogue's claims are refused (counted) or, on a loaded host, all dropped with its writer's budget
  // before they are decoded, where a claim cannot be told from a command (commands_over_limit, above): seen
  // once. Logged once a second a writer and kind (at most 4 kinds from the rogue's writer), over the run's
  // seconds.
  const double seconds = flooded.summary["wall_seconds"].get<double>() + 3.0;
  EXPECT_LE(flooded.event_lines, clean.event_lines + static_cast<std::size_t>(4 * seconds));
  EXPECT_LE(count_lines(flooded.err, "a claim of id"), static_cast<std::size_t>(2 * seconds)) << flooded.err;
  EXPECT_LE(flooded.summary["input_dropped"]["refused_claims"].get<double>(),
            8 * seconds);  // the claim budget
  EXPECT_LT(flooded.bytes, clean.bytes + 5u * 1024 * 1024);
#ifndef __SANITIZE_ADDRESS__
  // Not under AddressSanitizer: its quarantine keeps up to 256 MB of freed memory, so a flood's churn shows
  // as growth that is the sanitizer's own (seen: +245 MB). The Release suite and scripts/bench-faults measure
  // it.
  EXPECT_LT(flooded.peak_kb, clean.peak_kb + 40 * 1024);
#endif
}

// Realtime at 10 ticks/s, 8 s: one process floods commands for every id and made-up ones for 6 s, as fast
// as the wire takes them. Nobody dies, the excess is dropped over its writer's budget, and the event log
// stays bounded. (What the flood costs the honest robots in missed ticks is a figure, scripts/bench-faults.)
TEST_F(Abuse, FloodFromAProcessThatOwnsNoIdKillsNobodyInRealtime) {
#ifdef __SANITIZE_ADDRESS__
  // A realtime property (agents' liveliness kept through a flood, on the wall clock) is not one of the
  // sanitized build, whose processes run ~3x slower on the same 2 cores: CI saw 4 agents' leases lapse at
  // tick 13, a loaded machine 6 deaths. The lockstep flood test above runs the same input paths under ASan.
  GTEST_SKIP() << "realtime timing under AddressSanitizer; the Release suite asserts it";
#endif
  // The run's own processes (world, agents, the flooder alike) a step above the machine's other work: the
  // property is what the flood costs the honest robots, not what a busy host does to a realtime run (on a
  // loaded 2-core machine, beside another test, an agent's lease lapsed with no flood at all). Root only;
  // without the right the run keeps the default priority.
  errno = 0;
  if (setpriority(PRIO_PROCESS, 0, getpriority(PRIO_PROCESS, 0) - 5) != 0) {
    std::cout << "realtime-flooded: could not raise the run's priority (" << std::strerror(errno) << ")\n";
  }
  const int domain = swarmform::testing::test_domain(43);
  const AbusedRun flooded = run_with(domain, "realtime-flooded",
                                     {{"flood", "--seconds", "6", "--ids", "8", "--made-up", "--realtime"}},
                                     {"--mode", "realtime", "--max-ticks", "80"});
  EXPECT_EQ(flooded.summary["ticks"], 80);
  EXPECT_EQ(flooded.summary["alive_at_end"], kRobots);
  EXPECT_TRUE(flooded.summary["deaths"].empty()) << flooded.summary["deaths"].dump();
  EXPECT_EQ(flooded.summary["end_reason"], "max_ticks");
  EXPECT_GT(flooded.summary["input_dropped"]["commands_over_limit"].get<long>(), 0);
  std::size_t abuse_lines = 0;
  for (const Json& e : events("realtime-flooded")) {
    const std::string kind = e.value("kind", "");
    abuse_lines += kind == "spoofed_command" || kind == "commands_dropped" ? 1 : 0;
  }
  EXPECT_LE(abuse_lines, 2u * 12u);  // two kinds, once a second, over ~8-12 s
}

// Every end says why (docs/faults.md): the run directory's events.jsonl is /dev/full (writes fail with
// ENOSPC, as on a full disk; no root or mount needed, so the test runs anywhere). The recording's first flush
// (tick 10) fails: the world tells the agents to end (they exit 0), writes summary.json (its directory still
// has room) with end_reason disk_full and provenance, says so on one line and exits 5.
TEST_F(MultiProcess, AFullDiskEndsTheRunCleanlyWithEndReasonDiskFull) {
  const int domain = swarmform::testing::test_domain(42);
  const std::string run = path("full");
  std::filesystem::create_directories(run);
  std::filesystem::create_symlink("/dev/full", run + "/events.jsonl");
  Process& w = world(domain, "full");
  std::vector<Process*> agents;
  for (int i = 0; i < kRobots; ++i) agents.push_back(&agent(domain, i, "full"));
  EXPECT_EQ(w.wait_for(kRunDeadline), swarmform::exit_codes::kExitRecordingFailed) << w.err();
  for (int i = 0; i < kRobots; ++i) EXPECT_EQ(agents[i]->wait_for(10.0), 0) << agents[i]->err();
  EXPECT_EQ(count_lines(w.err(), "world_server: run ended (disk_full)"), 1u) << w.err();
  EXPECT_NE(w.err().find("No space left on device"), std::string::npos) << w.err();
  const Json s = summary("full");
  EXPECT_EQ(s["end_reason"], "disk_full");
  EXPECT_LT(s["ticks"].get<int>(), 300);
  EXPECT_EQ(s["provenance"]["product"], "swarmform");
  EXPECT_EQ(s["provenance"]["scenario_sha256"].get<std::string>().size(), 64u);
  EXPECT_FALSE(s["provenance"]["git_commit"].get<std::string>().empty());
}

// end_reason of the other ends a test can make quickly: max_ticks, interrupted (SIGTERM), no_agents.
TEST_F(MultiProcess, SummaryTellsWhyTheRunEnded) {
  const int domain = swarmform::testing::test_domain(42);
  clean_run(domain, "max");
  EXPECT_EQ(summary("max")["end_reason"], "max_ticks");
  Process& w = start({kWorld, "--scenario", kScenario, "--out", path("nobody"), "--domain",
                      std::to_string(domain), "--connect-timeout", "1"},
                     "nobody-world");
  EXPECT_EQ(w.wait_for(20.0), swarmform::exit_codes::kExitAgentsMissing);
  EXPECT_EQ(summary("nobody")["end_reason"], "no_agents");
  Process& t = world(domain, "term", {"--max-ticks", kOpenEndedTicks});
  for (int i = 0; i < kRobots; ++i) agent(domain, i, "term");
  ASSERT_TRUE(eventually(30.0, [&] { return t.out().find("progress tick=") != std::string::npos; }))
      << t.err();
  ASSERT_EQ(::kill(t.pid(), SIGTERM), 0);
  EXPECT_EQ(t.wait_for(20.0), 0) << t.err();
  EXPECT_EQ(summary("term")["end_reason"], "interrupted");
}

}  // namespace
