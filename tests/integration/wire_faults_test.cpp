// Stalls, identity and the wire on real processes (docs/wire.md, docs/faults.md): stalls that are not deaths,
// a stalled agent that rejoins afresh, an agent that lost its id, forged packets from another participant,
// and samples of another wire version or run. Domains: test_domain(36) and (37)
// (tests/support/test_domain.hpp); every wait has a deadline and every process is SIGKILLed by pid at the
// end (ProcessFixture).
#include <gtest/gtest.h>
#include <signal.h>

#include <dirent.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <thread>
#include <utility>

#include "common/dds/wire_version.hpp"
#include "common/exit_codes.hpp"
#include "tests/integration/issued_run.hpp"
#include "tests/support/process_fixture.hpp"
#include "tests/support/test_domain.hpp"

namespace {

using swarmform::testing::eventually;
using swarmform::testing::IssuedRun;
using swarmform::testing::kOpenEndedTicks;
using swarmform::testing::Process;
using swarmform::testing::read_file;
using Json = nlohmann::json;

constexpr int kRobots = 8;
constexpr double kRunDeadline = 120.0;  // s, for one whole run (the longest here take ~10 s)
// Long enough for the world to print its first progress line (after 1 s) well before the end: lockstep runs
// the random walk at 1,800-4,000 ticks/s. A fault the world runs on through needs kOpenEndedTicks instead.
constexpr int kLongRun = 15000;

// The UDP ports process `pid` holds (its sockets' inodes in /proc/net/udp): what a forger on the host finds.
std::set<int> udp_ports_of(pid_t pid) {
  std::set<std::string> inodes;
  const std::string fd_dir = "/proc/" + std::to_string(pid) + "/fd";
  if (DIR* d = opendir(fd_dir.c_str())) {
    while (dirent* e = readdir(d)) {
      char target[256] = {};
      const std::string link = fd_dir + "/" + e->d_name;
      const ssize_t n = readlink(link.c_str(), target, sizeof target - 1);
      const std::string t(target, n > 0 ? static_cast<std::size_t>(n) : 0);
      if (t.rfind("socket:[", 0) == 0) inodes.insert(t.substr(8, t.size() - 9));
    }
    closedir(d);
  }
  std::set<int> ports;
  std::ifstream udp("/proc/net/udp");
  std::string line;
  std::getline(udp, line);  // header
  while (std::getline(udp, line)) {
    std::istringstream in(line);
    std::string slot, local, remote, st, queues, tr, retr, uid, timeout, inode;
    in >> slot >> local >> remote >> st >> queues >> tr >> retr >> uid >> timeout >> inode;
    if (inodes.count(inode) && local.find(':') != std::string::npos) {
      ports.insert(std::stoi(local.substr(local.find(':') + 1), nullptr, 16));
    }
  }
  return ports;
}

const std::string kWorld = WORLD_SERVER_EXE;
const std::string kAgent = ROBOT_AGENT_EXE;
const std::string kRogue = ROGUE_AGENT_EXE;
const std::string kScenario = INTEGRATION_SCENARIO;

class WireFaults : public swarmform::testing::ProcessFixture {
 protected:
  WireFaults() : ProcessFixture("swarmform-wire") {}
  Process& world(int domain, const std::string& run, std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {
        kWorld,     "--scenario",           kScenario,           "--out", path(run),
        "--domain", std::to_string(domain), "--connect-timeout", "30"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return start(argv, run + "-world");
  }
  Process& agent(int domain, int id, const std::string& tag, std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {
        kAgent, "--id", std::to_string(id), "--domain", std::to_string(domain), "--timeout", "30"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return start(argv, tag + "-agent" + std::to_string(id) + "-" + std::to_string(processes_.size()));
  }
  // An agent as `swarm run` starts it: the run's nonce, and its id's token in its environment.
  Process& issued_agent(int domain, int id, const std::string& tag, const IssuedRun& run) {
    std::vector<std::string> argv = {
        kAgent, "--id", std::to_string(id), "--domain", std::to_string(domain), "--timeout", "30"};
    for (const std::string& f : run.nonce_flags()) argv.push_back(f);
    return start(argv, tag + "-agent" + std::to_string(id) + "-" + std::to_string(processes_.size()),
                 run.agent_env(static_cast<swarmform::RobotId>(id)));
  }
  std::vector<Process*> agents(int domain, const std::string& tag) {
    std::vector<Process*> out;
    for (int i = 0; i < kRobots; ++i) out.push_back(&agent(domain, i, tag));
    return out;
  }
  Json summary(const std::string& run) const { return Json::parse(read_file(path(run) + "/summary.json")); }
  bool has_event(const std::string& run, const std::string& kind, int id) const {
    std::istringstream in(read_file(path(run) + "/events.jsonl"));
    for (std::string line; std::getline(in, line);) {
      if (line.empty()) continue;
      const Json e = Json::parse(line, nullptr, false);
      if (e.is_object() && e.value("kind", "") == kind && e.value("id", -1) == id) return true;
    }
    return false;
  }
  // Once the world has printed a progress line, the run is ticking.
  static bool ticking(Process& w) { return w.out().find("progress tick=") != std::string::npos; }
  std::vector<Process*> resume_agent_3_after_the_end(int domain, const std::string& name,
                                                     std::vector<std::string> flags, bool cut_short);
  static void stall(pid_t pid, std::chrono::milliseconds how_long) {
    ASSERT_EQ(::kill(pid, SIGSTOP), 0);
    std::this_thread::sleep_for(how_long);
    ASSERT_EQ(::kill(pid, SIGCONT), 0);
  }
  // A lockstep run of kLongRun ticks, every agent exiting 0; `during` acts on it once it ticks (the world
  // must still be running then). Returns the trajectory hash.
  template <typename F>
  std::string lockstep_run(int domain, const std::string& run, F&& during) {
    Process& w = world(domain, run, {"--max-ticks", std::to_string(kLongRun)});
    std::vector<Process*> as = agents(domain, run);
    EXPECT_TRUE(eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) << w.out();
    EXPECT_TRUE(w.running()) << "the run ended before the fault: make it longer";
    during(w, as);
    EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
    EXPECT_NE(w.out().find("done ticks=" + std::to_string(kLongRun)), std::string::npos) << w.out();
    for (int i = 0; i < kRobots; ++i) EXPECT_EQ(as[i]->wait_for(15.0), 0) << i << ": " << as[i]->err();
    return summary(run).value("trajectory_sha256", "");
  }
};

// A world SIGSTOPped for 3 s found every agent's liveliness lease expired when it resumed and
// recorded them all dead (12 of 13 runs). It now judges them against its own awake time (stall_guard.hpp).
// Stopped 8 s (under the agents' 10 s world timeout once its 2 s lease is counted), it met each agent's
// keep-alive samples of the whole stop in one burst, past the writer's receive budget, which dropped the
// round's commands with them: the run waited for them until lockstep_deadline. The agents write no sample
// while the world is silent now, so nothing is dropped.
TEST_F(WireFaults, WorldStalledEightSecondsInLockstepKillsNobodyDropsNothingAndChangesNothing) {
  const int domain = swarmform::testing::test_domain(36);
  const std::string baseline = lockstep_run(domain, "baseline", [](Process&, std::vector<Process*>&) {});
  const std::string stalled = lockstep_run(domain, "stalled", [&](Process& w, std::vector<Process*>&) {
    stall(w.pid(), std::chrono::milliseconds(8000));
  });
  EXPECT_EQ(baseline.size(), 64u);
  EXPECT_EQ(stalled, baseline);
  const Json s = summary("stalled");
  EXPECT_EQ(s["deaths"].size(), 0u) << s["deaths"].dump();
  // The 3 s stop is one of the world's own stalls; a loaded host may add short ones of its own (seen: 4 in
  // all), so the count is at least 1 and the time at least the stop's, less the loop's 250 ms allowance.
  const std::string err = read_file(path("stalled-world.err"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      err, m, std::regex(R"(the world itself stalled (\d+) time\(s\), ([0-9.]+) s in all)")))
      << err;
  EXPECT_GE(std::stoi(m[1]), 1) << err;
  EXPECT_GE(std::stod(m[2]), 7.7) << err;
  EXPECT_EQ(s["alive_at_end"], kRobots);
  EXPECT_EQ(s["input_dropped"]["commands_over_limit"], 0) << s["input_dropped"].dump();
}

// An agent tolerates a silent world for --world-timeout seconds of its own time (default 10): with 1 s it
// gives up during a 4 s stall of the world and says so; one with the default rides the stall out, and so
// does one with 1 s that knows the world's process (--world-pid, as swarm run starts it): it is there, so
// the world is slow, not gone.
TEST_F(WireFaults, AgentGivesUpOnASilentWorldOnlyAfterItsWorldTimeout) {
  const int domain = swarmform::testing::test_domain(36);
  Process& w = world(domain, "silent-world", {"--robots", "3", "--max-ticks", std::to_string(kLongRun)});
  Process& impatient = agent(domain, 0, "silent-world", {"--world-timeout", "1"});
  Process& patient = agent(domain, 1, "silent-world");
  Process& knowing =
      agent(domain, 2, "silent-world", {"--world-timeout", "1", "--world-pid", std::to_string(w.pid())});
  ASSERT_TRUE(eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) << w.out();
  ASSERT_TRUE(w.running());
  stall(w.pid(), std::chrono::milliseconds(4000));
  EXPECT_EQ(impatient.wait_for(15.0), swarmform::exit_codes::kExitNoWorld) << impatient.err();
  EXPECT_NE(impatient.err().find("the world went away before announcing the end (silent for 1 s"),
            std::string::npos)
      << impatient.err();
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(patient.wait_for(15.0), 0) << patient.err();
  EXPECT_EQ(knowing.wait_for(15.0), 0) << knowing.err();
  const Json s = summary("silent-world");
  EXPECT_EQ(s["alive_at_end"], 2) << w.err();
  ASSERT_EQ(s["deaths"].size(), 1u) << s.dump();
  EXPECT_EQ(s["deaths"][0]["id"], 0);
}

// A world whose process is gone is gone at once for an agent that knows its pid, long before its
// --world-timeout (60 s here) would say so; it names the pid.
TEST_F(WireFaults, AnAgentThatKnowsTheWorldsPidEndsAsSoonAsTheWorldIsKilled) {
  const int domain = swarmform::testing::test_domain(36);
  Process& w = world(domain, "world-killed", {"--robots", "1", "--max-ticks", std::to_string(kLongRun)});
  Process& a =
      agent(domain, 0, "world-killed", {"--world-timeout", "60", "--world-pid", std::to_string(w.pid())});
  ASSERT_TRUE(eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) << w.out();
  ASSERT_TRUE(w.running());
  ASSERT_EQ(::kill(w.pid(), SIGKILL), 0);
  EXPECT_EQ(w.wait_for(10.0), 128 + SIGKILL);
  // Within its lease (2 s) and a look at /proc, not its 60 s world timeout.
  EXPECT_EQ(a.wait_for(10.0), swarmform::exit_codes::kExitNoWorld) << a.err();
  EXPECT_NE(a.err().find("the world went away before announcing the end (its process, pid " +
                         std::to_string(w.pid()) + ", is gone)"),
            std::string::npos)
      << a.err();
}

// A world stopped past some agents' world timeout: those give up and exit (deaths), the others ride the stall
// out. The world's end-of-run line counts what it recorded: its deaths are summary.json's, its comebacks no
// more than the robots alive at the end. It used to count an agent that exited during the stall as a comeback
// when its last samples were taken before its going was seen (a 12 s stall: "9 lost agent(s) came back" with
// 6 deaths recorded).
TEST_F(WireFaults, TheWorldsStallLineAgreesWithTheDeathsItRecorded) {
  const int domain = swarmform::testing::test_domain(36);
  constexpr int kAgents = 6;
  Process& w = world(domain, "stall-count",
                     {"--robots", std::to_string(kAgents), "--max-ticks", std::to_string(kLongRun)});
  std::vector<Process*> as;
  for (int i = 0; i < kAgents; ++i) {
    as.push_back(i < kAgents / 2 ? &agent(domain, i, "stall-count", {"--world-timeout", "1"})
                                 : &agent(domain, i, "stall-count"));
  }
  ASSERT_TRUE(eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) << w.out();
  ASSERT_TRUE(w.running());
  stall(w.pid(), std::chrono::milliseconds(4000));
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  for (int i = 0; i < kAgents; ++i) {
    EXPECT_EQ(as[i]->wait_for(15.0),
              i < kAgents / 2 ? swarmform::exit_codes::kExitNoWorld : swarmform::exit_codes::kExitOk)
        << i << ": " << as[i]->err();
  }
  const Json s = summary("stall-count");
  ASSERT_EQ(s["deaths"].size(), static_cast<std::size_t>(kAgents / 2)) << s.dump();
  std::smatch m;
  const std::string err = w.err();
  ASSERT_TRUE(
      std::regex_search(err, m,
                        std::regex("the world itself stalled 1 time\\(s\\), [0-9.]+ s in all; ([0-9]+) "
                                   "lost agent\\(s\\) came back within the grace and were not taken "
                                   "for dead; ([0-9]+) were recorded dead")))
      << err;
  EXPECT_EQ(std::stoi(m[2]), kAgents / 2) << err;
  EXPECT_LE(std::stoi(m[1]), s["alive_at_end"].get<int>()) << err;
}

// Before the run starts the world may be slow to admit the others (1024 agents on 2 cores: its writers
// missed their lease for many seconds): an agent waiting for its first packet takes the world for gone only
// after its own timeout, not after its world timeout. Here agent 0 (world timeout 1 s) is admitted, the
// world stalls 4 s, then agent 1 comes and the run is played out whole.
TEST_F(WireFaults, AnAgentWaitingForTheRunOutlivesASilentWorldUntilItsTimeout) {
  const int domain = swarmform::testing::test_domain(36);
  Process& w = world(domain, "slow-start", {"--robots", "2", "--max-ticks", "50"});
  Process& early = agent(domain, 0, "slow-start", {"--world-timeout", "1"});
  ASSERT_TRUE(eventually(30.0, [&] {
    return w.err().find("id 0 claimed by pid") != std::string::npos || !w.running() || !early.running();
  })) << w.err();
  ASSERT_TRUE(w.running()) << w.err();
  ASSERT_TRUE(early.running()) << early.err();
  stall(w.pid(), std::chrono::milliseconds(4000));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_TRUE(early.running()) << early.err();
  Process& late = agent(domain, 1, "slow-start");
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(early.wait_for(15.0), 0) << early.err();
  EXPECT_EQ(late.wait_for(15.0), 0) << late.err();
  EXPECT_EQ(summary("slow-start")["alive_at_end"], 2);
}

// An agent stalled 3 s in lockstep is taken for dead (its lease ran out while the world was awake); when it
// resumes, its robot rejoins and its controller starts afresh (init again), recorded as a rejoin. The world
// runs on without robot 2 while it is stalled, so the run is open-ended (kOpenEndedTicks): ended by SIGTERM
// once the rejoin is recorded.
TEST_F(WireFaults, AgentStalledThreeSecondsInLockstepRejoinsWithAFreshController) {
  const int domain = swarmform::testing::test_domain(36);
  Process& w = world(domain, "agent-stall", {"--max-ticks", kOpenEndedTicks});
  std::vector<Process*> as = agents(domain, "agent-stall");
  ASSERT_TRUE(eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) << w.out();
  ASSERT_TRUE(w.running()) << w.err();
  stall(as[2]->pid(), std::chrono::milliseconds(3000));
  EXPECT_TRUE(eventually(20.0, [&] { return has_event("agent-stall", "rejoin", 2) || !w.running(); }));
  ASSERT_TRUE(w.running()) << w.err();
  ASSERT_EQ(::kill(w.pid(), SIGTERM), 0);
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  for (int i = 0; i < kRobots; ++i) EXPECT_EQ(as[i]->wait_for(15.0), 0) << i << ": " << as[i]->err();
  EXPECT_NE(as[2]->out().find("restarts=1"), std::string::npos) << as[2]->out();
  EXPECT_NE(as[2]->err().find("controller started afresh"), std::string::npos) << as[2]->err();
  const Json s = summary("agent-stall");
  EXPECT_EQ(s["end_reason"], "interrupted");
  ASSERT_EQ(s["deaths"].size(), 1u) << s.dump();
  EXPECT_EQ(s["deaths"][0]["id"], 2);
  ASSERT_EQ(s["rejoins"].size(), 1u) << s.dump();
  EXPECT_EQ(s["rejoins"][0]["id"], 2);
  EXPECT_EQ(s["alive_at_end"], kRobots);
}

// The dead lock behind a world's own stall that killed a patient agent now and then: an agent whose writer
// lost its liveliness at the world (here: stalled 1.5 s, past its 500 ms lease) while it has already answered
// the round, and whose world stays alive (its writers' 2 s lease holds, so it has no reason to re-claim).
// Cyclone 0.10.2 brings a lost writer back only on a sample, never on a liveliness assertion, and the world
// sends a dead robot none: without the ALIVE keep-alive the agent waited for a packet until the run ended.
// Robot 2 is a live agent that never answers, so that the world waits in round 0 and nobody's packet could
// end the wait by chance. The world never steps without a live agent in lockstep: once the lockstep deadline
// (10 s here) has passed with robot 2 still silent, the run ends agents_stalled (exit 10), naming robot 2
// alone, and every agent hears the end.
TEST_F(WireFaults, AgentTakenForDeadWhileItsWorldWaitsRejoinsWithoutAPacket) {
  const int domain = swarmform::testing::test_domain(36);
  const std::string scenario = path("long-deadline.yaml");
  {
    // The copy names its shape by its path in the repository (found from the original's folder).
    const std::string shape = (std::filesystem::path(kScenario).parent_path() / "../../shapes/square.txt")
                                  .lexically_normal()
                                  .string();
    std::string text = std::regex_replace(read_file(kScenario), std::regex("lockstep_deadline: [0-9.]+"),
                                          "lockstep_deadline: 10.0");
    std::ofstream(scenario) << std::regex_replace(text, std::regex("shape: square.txt"), "shape: " + shape);
  }
  Process& w =
      start({kWorld, "--scenario", scenario, "--out", path("waiting"), "--domain", std::to_string(domain),
             "--connect-timeout", "30", "--robots", "3", "--max-ticks", "30"},
            "waiting-world");
  Process& a0 = agent(domain, 0, "waiting");
  Process& a1 = agent(domain, 1, "waiting");
  Process& silent =
      start({kRogue, "--domain", std::to_string(domain), "--timeout", "60", "silent", "--id", "2"},
            "waiting-silent");
  // The run starts once all three claimed; the world's stdout and stderr are written at once (events.jsonl
  // is buffered).
  ASSERT_TRUE(eventually(kRunDeadline, [&] {
    const std::string err = w.err();
    const bool all = err.find("id 0 claimed") != std::string::npos &&
                     err.find("id 1 claimed") != std::string::npos &&
                     err.find("id 2 claimed") != std::string::npos;
    return all || !w.running();
  })) << w.err();
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // agents 0 and 1 have answered round 0
  ASSERT_EQ(w.out().find("death"), std::string::npos) << "the round must still wait for robot 2: " << w.out();
  stall(a0.pid(), std::chrono::milliseconds(1500));
  ASSERT_NE(w.out().find("death id=0 tick=0"), std::string::npos)
      << "the stall must outlast the agent's lease: " << w.out();
  // Well within the round's 10 s: only the agent's own ALIVE sample can bring it back this soon.
  EXPECT_TRUE(eventually(5.0, [&] { return w.out().find("rejoin id=0 tick=0") != std::string::npos; }))
      << w.out();
  EXPECT_EQ(w.wait_for(kRunDeadline), swarmform::exit_codes::kExitAgentsStalled) << w.err();
  EXPECT_NE(w.err().find("run ended (agents_stalled) at tick 0: robot 2 gave no command for tick 0 in 10 s"),
            std::string::npos)
      << w.err();
  EXPECT_NE(w.err().find("world_server: tick 0: waiting for robot 2 ("), std::string::npos) << w.err();
  EXPECT_EQ(a0.wait_for(15.0), 0) << a0.err();
  EXPECT_EQ(a1.wait_for(15.0), 0) << a1.err();
  EXPECT_TRUE(silent.wait_for(15.0).has_value());
  const Json s = summary("waiting");
  EXPECT_EQ(s["alive_at_end"], 3);
  EXPECT_EQ(s["ticks"], 0) << "no round was stepped without robot 2";
  EXPECT_EQ(s["end_reason"], "agents_stalled");
  EXPECT_TRUE(has_event("waiting", "command_waited_out", 2));
  EXPECT_FALSE(has_event("waiting", "command_waited_out", 0));
  EXPECT_FALSE(has_event("waiting", "command_waited_out", 1));
}

// Runs `name` (world flags `flags`) with agent 3 SIGSTOPped mid-run until the world has exited, then
// continued: it finds its END waiting and exits 0 on its own within 4 s, saying the run ended without it at
// the world's last tick. With `cut_short` (a lockstep run, whose length in wall time is the host's), once the
// world has stepped on after the death the run is ended by SIGTERM (it announces its END as at max_ticks):
// the agent must stay stopped well under its participant's 30 s lease (common/dds/cyclone_config.cpp), or
// the world's writer forgets its reader and sends it nothing, and a run left to its max_ticks on a loaded
// host outlasted that. A realtime run is left to its end: its ticks are wall time, and the agent tells a late
// END only by more than a second's ticks missed. Returns the agents for the caller's checks.
std::vector<Process*> WireFaults::resume_agent_3_after_the_end(int domain, const std::string& name,
                                                               std::vector<std::string> flags,
                                                               bool cut_short) {
  Process& w = world(domain, name, std::move(flags));
  std::vector<Process*> as = agents(domain, name);
  if (!eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) {
    ADD_FAILURE() << "the run never ticked: " << w.out();
    return as;
  }
  if (!w.running()) {
    ADD_FAILURE() << "the run ended before the fault: make it longer";
    return as;
  }
  EXPECT_EQ(::kill(as[3]->pid(), SIGSTOP), 0);
  const auto dead = [&] { return w.out().find("death id=3 tick=") != std::string::npos; };
  // Some rounds after the death (the agent tells a late END by the ticks it missed): a progress line
  // printed after the death line.
  const auto stepped_on = [&] {
    const std::string out = w.out();
    const auto death = out.find("death id=3 tick=");
    return death != std::string::npos && out.find("progress tick=", death) != std::string::npos;
  };
  EXPECT_TRUE(eventually(20.0, [&] { return stepped_on() || !w.running(); })) << w.out();
  if (cut_short && w.running()) {
    EXPECT_EQ(::kill(w.pid(), SIGTERM), 0);
  }
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_TRUE(dead()) << w.out();
  EXPECT_EQ(::kill(as[3]->pid(), SIGCONT), 0);
  EXPECT_EQ(as[3]->wait_for(4.0), 0) << as[3]->err();
  std::smatch done;
  const std::string out = w.out();
  EXPECT_TRUE(std::regex_search(out, done, std::regex("done ticks=([0-9]+)"))) << out;
  EXPECT_NE(
      as[3]->err().find("robot_agent 3: the run ended at tick " + done[1].str() + " without this robot"),
      std::string::npos)
      << as[3]->err();
  return as;
}

// An agent taken for dead that resumes only after the run has ended (stopped until the world has exited; the
// world does not know its pid, so nothing tells its stop from a death) finds its END waiting and exits 0 on
// its own, its log saying why, well within the launcher's 5 s. Before, the world told only the agents it
// held alive: this one waited out its 10 s world timeout (the launcher SIGKILLed it at 5 s, its log empty).
TEST_F(WireFaults, AnAgentThatResumesAfterTheRunEndedFindsItsEndAndSaysWhy) {
  const int domain = swarmform::testing::test_domain(36);
  const std::vector<Process*> as =
      resume_agent_3_after_the_end(domain, "late", {"--max-ticks", std::to_string(kLongRun)}, true);
  EXPECT_NE(as[3]->err().find(" without this robot: its last packet was for tick "), std::string::npos)
      << as[3]->err();
  for (int i = 0; i < kRobots; ++i) {
    if (i == 3) continue;
    EXPECT_EQ(as[i]->wait_for(15.0), 0) << i << ": " << as[i]->err();
  }
  EXPECT_EQ(summary("late")["alive_at_end"], kRobots - 1);
}

// The same in realtime (deadlines stand there, whatever the world knows of its pids): the perceptions written
// to agent 3 before its death come in with its END when it resumes; it still tells the END from them.
TEST_F(WireFaults, ARealtimeAgentThatResumesAfterTheRunEndedFindsItsEndAndSaysWhy) {
  const int domain = swarmform::testing::test_domain(37);
  const std::vector<Process*> as =
      resume_agent_3_after_the_end(domain, "late-rt", {"--mode", "realtime", "--max-ticks", "60"}, false);
  for (int i = 0; i < kRobots; ++i) {
    if (i == 3) continue;
    EXPECT_EQ(as[i]->wait_for(15.0), 0) << i << ": " << as[i]->err();
    EXPECT_EQ(as[i]->err().find("without this robot"), std::string::npos) << i << ": " << as[i]->err();
  }
}

// Realtime keeps its deadlines: agents stopped together past their lease are dead. But the run says what it
// was, one event of the host: one mass_loss event and one summary entry naming all 8 robots, their processes
// all still there (the world knows their pids, as the launcher tells it). Before: 8 deaths and nothing else.
TEST_F(WireFaults, RealtimeAgentsStoppedTogetherAreOneMassLossNotEightIndependentDeaths) {
  const int domain = swarmform::testing::test_domain(37);
  const std::vector<Process*> as = agents(domain, "mass");
  std::vector<std::string> flags = {"--mode", "realtime", "--max-ticks", "60"};
  for (int i = 0; i < kRobots; ++i)
    flags.insert(flags.end(), {"--agent-pid", std::to_string(i) + "=" + std::to_string(as[i]->pid())});
  Process& w = world(domain, "mass", flags);
  ASSERT_TRUE(eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) << w.out();
  ASSERT_TRUE(w.running()) << "the run ended before the fault: make it longer";
  for (Process* a : as) ASSERT_EQ(::kill(a->pid(), SIGSTOP), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // three leases
  for (Process* a : as) ASSERT_EQ(::kill(a->pid(), SIGCONT), 0);
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  for (int i = 0; i < kRobots; ++i) EXPECT_TRUE(as[i]->wait_for(15.0).has_value()) << i;
  const Json s = summary("mass");
  EXPECT_EQ(s["deaths"].size(), static_cast<std::size_t>(kRobots)) << s["deaths"].dump();
  ASSERT_EQ(s["mass_losses"].size(), 1u) << s["mass_losses"].dump();
  const Json& g = s["mass_losses"][0];
  std::set<int> robots;
  for (const auto& id : g["robots"]) robots.insert(id.get<int>());
  EXPECT_EQ(robots.size(), static_cast<std::size_t>(kRobots)) << g.dump();
  EXPECT_EQ(g["processes_present"], kRobots) << g.dump();
  EXPECT_LE(g["within_ms"].get<double>(), 500.0) << g.dump();
  EXPECT_TRUE(has_event("mass", "mass_loss", -1));
  EXPECT_NE(w.out().find("mass_loss robots=8 "), std::string::npos) << w.out();
}

// Realtime: agent 4 stalls, is taken for dead, and an agent restarted by hand claims id 4. The old one,
// resumed, is told by the world's packets (another owner) and exits 5 with a clear message; it used to run to
// the end.
TEST_F(WireFaults, RealtimeAgentReplacedByARestartedOneIsToldAndExitsNonZero) {
  const int domain = swarmform::testing::test_domain(37);
  // Restarted by hand: only a world started with --open-rejoin lets it take the id (docs/wire.md "Claim
  // proofs").
  Process& w = world(domain, "replaced", {"--mode", "realtime", "--max-ticks", "150", "--open-rejoin"});
  std::vector<Process*> as = agents(domain, "replaced");
  ASSERT_TRUE(eventually(kRunDeadline, [&] { return ticking(w) || !w.running(); })) << w.out();
  ASSERT_EQ(::kill(as[4]->pid(), SIGSTOP), 0);
  ASSERT_TRUE(eventually(20.0, [&] { return has_event("replaced", "death", 4) || !w.running(); }));
  Process& again = agent(domain, 4, "replaced-again");
  EXPECT_TRUE(eventually(20.0, [&] { return has_event("replaced", "rejoin", 4) || !w.running(); }));
  ASSERT_EQ(::kill(as[4]->pid(), SIGCONT), 0);
  EXPECT_EQ(as[4]->wait_for(15.0), swarmform::exit_codes::kExitIdLost) << as[4]->err();
  EXPECT_NE(as[4]->err().find("lost id 4 to another agent"), std::string::npos) << as[4]->err();
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(again.wait_for(15.0), 0) << again.err();
  EXPECT_EQ(summary("replaced")["alive_at_end"], kRobots);
}

// Without --secure, a process on the host that read the run nonce from the mission claims robot 3 after its
// agent died, stating a pid of its own choosing. The world, holding the run's secret as under `swarm run`,
// refuses it and names it by its participant's GUID (what DDS discovery says, not what the claim says); a
// robot_agent started by hand is refused too; the agent restarted with robot 3's token, as the launcher
// restarts one, takes the id back. Before: the stranger was accepted (`rejoin id=3`) and drove robot 3.
TEST_F(WireFaults, AStrangersClaimOfADeadIdIsRefusedAndTheStartersRestartedAgentRejoins) {
  const int domain = swarmform::testing::test_domain(36);
  const IssuedRun run;
  std::vector<Process*> as;
  for (int i = 0; i < kRobots; ++i) as.push_back(&issued_agent(domain, i, "stranger", run));
  std::vector<std::string> argv = {kWorld,
                                   "--scenario",
                                   kScenario,
                                   "--out",
                                   path("stranger"),
                                   "--domain",
                                   std::to_string(domain),
                                   "--connect-timeout",
                                   "30",
                                   "--max-ticks",
                                   kOpenEndedTicks,
                                   "--kill",
                                   "3@50",
                                   "--agent-pid",
                                   "3=" + std::to_string(as[3]->pid())};
  for (const std::string& f : run.nonce_flags()) argv.push_back(f);
  Process& w = start(argv, "stranger-world", run.world_env());
  ASSERT_TRUE(eventually(kRunDeadline,
                         [&] { return w.out().find("death id=3 ") != std::string::npos || !w.running(); }))
      << w.out() << w.err();
  ASSERT_TRUE(w.running()) << w.err();

  Process& rogue = start({kRogue, "--domain", std::to_string(domain), "--timeout", "30", "stranger", "--id",
                          "3", "--pid", "4242"},
                         "stranger-rogue");
  EXPECT_EQ(rogue.wait_for(40.0), 4) << rogue.out() << rogue.err();
  EXPECT_NE(rogue.err().find("refused: this run's ids go only to agents its starter issued"),
            std::string::npos)
      << rogue.err();
  std::smatch m;
  const std::string rogue_out = rogue.out();
  ASSERT_TRUE(std::regex_search(rogue_out, m, std::regex("stranger participant=([0-9a-f]{32})")))
      << rogue_out;
  const std::string named = "refused a claim of id 3 from pid 4242 (participant " + m[1].str() + ")";
  EXPECT_TRUE(eventually(5.0, [&] { return w.err().find(named) != std::string::npos; })) << named << "\n"
                                                                                         << w.err();

  Process& by_hand = agent(domain, 3, "stranger-by-hand", run.nonce_flags());  // no token
  EXPECT_EQ(by_hand.wait_for(40.0), swarmform::exit_codes::kExitIdRefused) << by_hand.err();
  EXPECT_EQ(w.out().find("rejoin id=3"), std::string::npos) << w.out();

  Process& again = issued_agent(domain, 3, "stranger-again", run);
  EXPECT_TRUE(eventually(kRunDeadline, [&] {
    return w.out().find("rejoin id=3 ") != std::string::npos || !w.running();
  })) << w.out();
  ASSERT_TRUE(w.running()) << w.err();
  ASSERT_EQ(::kill(w.pid(), SIGTERM), 0);
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(again.wait_for(15.0), 0) << again.err();
  EXPECT_EQ(as[3]->wait_for(5.0), 128 + SIGKILL);
  for (int i = 0; i < kRobots; ++i) {
    if (i == 3) continue;
    EXPECT_EQ(as[i]->wait_for(15.0), 0) << i << ": " << as[i]->err();
  }
  const Json s = summary("stranger");
  EXPECT_GE(s["input_dropped"]["unproven_claims"].get<int>(), 2) << s["input_dropped"].dump();
  ASSERT_EQ(s["rejoins"].size(), 1u);
  EXPECT_EQ(s["rejoins"][0]["id"], 3);
  EXPECT_EQ(s["alive_at_end"], kRobots);
  EXPECT_TRUE(has_event("stranger", "claim_unproven", 3));
}

// Another participant writes forged perceptions and END packets into robot/3 (with the right run nonce,
// owner nonce and generation, read off the wire): agent 3 refuses them, as not from the world it bound to at
// the mission, and runs to the end. It used to exit 0 at the first forged END (a silent remote kill).
TEST_F(WireFaults, ForgedEndAndPerceptionsFromAnotherParticipantAreRefused) {
  const int domain = swarmform::testing::test_domain(37);
  Process& w = world(domain, "forged", {"--max-ticks", std::to_string(kLongRun)});
  std::vector<Process*> as = agents(domain, "forged");
  // A forger on the host finds agent 3's ports and peers with it directly (agents never discover each other
  // through the world).
  std::set<int> ports;
  ASSERT_TRUE(eventually(20.0, [&] { return (ports = udp_ports_of(as[3]->pid())).size() >= 2; }));
  std::vector<std::string> argv = {kRogue, "--domain", std::to_string(domain), "--timeout", "100"};
  for (int port : ports) {
    argv.push_back("--peer");
    argv.push_back("127.0.0.1:" + std::to_string(port));
  }
  argv.insert(argv.end(), {"forge", "--target", "3"});
  Process& forger = start(argv, "forger");
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(forger.wait_for(15.0), 0) << forger.out() << forger.err();
  std::smatch m;
  const std::string forged = forger.out();
  ASSERT_TRUE(std::regex_search(forged, m, std::regex("forge sent=([0-9]+)"))) << forged;
  EXPECT_GT(std::stoi(m[1]), 10) << forged;
  EXPECT_EQ(as[3]->wait_for(15.0), 0) << as[3]->err();
  // Every real packet (1000 ticks and the END), none forged; the refusals counted and said.
  EXPECT_NE(
      as[3]->out().find("agent id=3 packets=" + std::to_string(kLongRun + 1) + " foreign_packets=0 refused="),
      std::string::npos)
      << as[3]->out();
  EXPECT_EQ(as[3]->out().find("refused=0 "), std::string::npos) << as[3]->out();
  EXPECT_NE(as[3]->err().find("not from the world whose mission this agent took"), std::string::npos)
      << as[3]->err();
  EXPECT_EQ(summary("forged")["alive_at_end"], kRobots);
}

// Claims of another run (nonce) are answered with the reason; claims of another wire version are refused
// and said at most once a second per writer (not once per sample); an agent told to take only another run's
// mission refuses this world's and says why.
TEST_F(WireFaults, SamplesOfAnotherRunOrWireVersionAreRefusedWithTheReason) {
  const int domain = swarmform::testing::test_domain(37);
  Process& w = world(domain, "badwire", {"--robots", "2", "--run-nonce", "5eed"});
  Process& other_run = start({kRogue, "--domain", std::to_string(domain), "--timeout", "20", "badwire",
                              "--id", "0", "--nonce", "deadbeef"},
                             "other-run");
  EXPECT_EQ(other_run.wait_for(30.0), 4) << other_run.err();
  EXPECT_NE(other_run.err().find("refused: run nonce 00000000deadbeef is not this run's (0000000000005eed)"),
            std::string::npos)
      << other_run.err();
  Process& old_wire = start({kRogue, "--domain", std::to_string(domain), "--timeout", "3", "badwire", "--id",
                             "1", "--version", "1"},
                            "old-wire");
  EXPECT_EQ(old_wire.wait_for(30.0), 3) << old_wire.err();  // never answered: it speaks another version
  std::smatch m;
  const std::string sent_text = old_wire.out();
  ASSERT_TRUE(std::regex_search(sent_text, m, std::regex("badwire sent=([0-9]+)"))) << sent_text;
  const int sent = std::stoi(m[1]);
  EXPECT_GE(sent, 10);
  const std::regex said(
      "world_server: refused ([0-9]+) claim sample\\(s\\) from writer [0-9a-f]+ \\(pid 0\\): "
      "wire version 1, this world speaks " +
      std::to_string(swarmform::dds::kWireVersion));
  const std::string err = w.err();
  int lines = 0;
  for (auto it = std::sregex_iterator(err.begin(), err.end(), said); it != std::sregex_iterator(); ++it)
    ++lines;
  EXPECT_GE(lines, 1) << err;
  EXPECT_LE(lines, 6) << "one line a second, not one per sample (" << sent << " sent): " << err;
  Process& stranger = start(
      {kAgent, "--id", "0", "--domain", std::to_string(domain), "--run-nonce", "1234", "--timeout", "3"},
      "stranger");
  EXPECT_EQ(stranger.wait_for(20.0), swarmform::exit_codes::kExitNoWorld) << stranger.err();
  EXPECT_NE(stranger.err().find("another run's (run nonce 0000000000005eed, this side's run is "
                                "0000000000001234)"),
            std::string::npos)
      << stranger.err();
  // The run itself is untouched: its two agents come and it completes.
  agent(domain, 0, "badwire");
  agent(domain, 1, "badwire");
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(summary("badwire")["alive_at_end"], 2);
}

}  // namespace
