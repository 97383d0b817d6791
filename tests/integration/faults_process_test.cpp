// Scheduled faults with real processes (world/faults.hpp, world_server/process_faults.hpp), over DDS on
// loopback: the world SIGSTOPs a stalled agent at the stall's tick and SIGCONTs it at its end (the process is
// seen stopped meanwhile and exits 0 at the end); a stall of a robot without --agent-pid withholds its
// packets instead; world faults give the DDS world the in-process harness's trajectory bit for bit. Test
// domains 44..46 (test_domain.hpp); every process is SIGKILLed and reaped by the fixture, every wait has a
// deadline.
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/process.hpp"
#include "tests/support/process_fixture.hpp"
#include "tests/support/test_domain.hpp"

namespace {

using swarmform::testing::eventually;
using swarmform::testing::Process;
using swarmform::testing::read_file;
using Json = nlohmann::json;

constexpr int kRobots = 8;
constexpr double kRunDeadline = 60.0;  // s, for one whole run (a few seconds)

const std::string kWorld = WORLD_SERVER_EXE;
const std::string kAgent = ROBOT_AGENT_EXE;
const std::string kInProcess = SWARM_INPROCESS_EXE;
const std::string kScenario = INTEGRATION_SCENARIO;

// The state letter of /proc/PID/stat ('T': stopped), or ' ' when it cannot be read.
char process_state(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');
  return close == std::string::npos || close + 2 >= text.size() ? ' ' : text[close + 2];
}

class ProcessFaults : public swarmform::testing::ProcessFixture {
 protected:
  ProcessFaults() : ProcessFixture("swarmform-faults") {}

  std::vector<Process*> agents(int domain, const std::string& tag) {
    std::vector<Process*> out;
    for (int i = 0; i < kRobots; ++i) {
      out.push_back(
          &start({kAgent, "--id", std::to_string(i), "--domain", std::to_string(domain), "--timeout", "30"},
                 tag + "-agent" + std::to_string(i)));
    }
    return out;
  }
  Process& world(int domain, const std::string& run, std::vector<std::string> extra) {
    std::vector<std::string> argv = {
        kWorld,     "--scenario",           kScenario,           "--out", path(run),
        "--domain", std::to_string(domain), "--connect-timeout", "30"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return start(argv, run + "-world");
  }
  std::vector<Json> events(const std::string& run) const {
    std::vector<Json> out;
    std::istringstream in(read_file(path(run) + "/events.jsonl"));
    for (std::string line; std::getline(in, line);) {
      if (!line.empty()) out.push_back(Json::parse(line));
    }
    return out;
  }
  // The events of `kind` whose detail starts with the fault's text.
  std::vector<Json> fault_events(const std::string& run, const std::string& kind,
                                 const std::string& text) const {
    std::vector<Json> out;
    for (Json& e : events(run)) {
      if (e.value("kind", "") == kind && e.value("detail", "").rfind(text + ":", 0) == 0) out.push_back(e);
    }
    return out;
  }
  Json summary(const std::string& run) const { return Json::parse(read_file(path(run) + "/summary.json")); }
};

TEST_F(ProcessFaults, AStallSigstopsTheAgentAtItsTickAndSigcontsItAtItsEnd) {
  const int domain = swarmform::testing::test_domain(44);
  auto a = agents(domain, "stall");
  const pid_t pid = a[3]->pid();
  Process& w =
      world(domain, "stall",
            {"--max-ticks", "120", "--fault", "stall:3@20+30", "--agent-pid", "3=" + std::to_string(pid)});
  // The world waits up to the lockstep deadline (2 s) for the stopped agent: the stop is seen.
  EXPECT_TRUE(eventually(kRunDeadline, [&] { return process_state(pid) == 'T' || !w.running(); }));
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_NE(process_state(pid), 'T');
  for (int i = 0; i < kRobots; ++i)
    EXPECT_EQ(a[i]->wait_for(10.0), 0) << "agent " << i << ": " << a[i]->err();

  const auto started = fault_events("stall", "fault", "stall:3@20+30");
  ASSERT_EQ(started.size(), 1u);
  EXPECT_EQ(started[0]["tick"], 20);
  EXPECT_EQ(started[0]["id"], 3);
  EXPECT_EQ(started[0]["detail"], "stall:3@20+30: SIGSTOP pid " + std::to_string(pid));
  const auto ended = fault_events("stall", "fault_end", "stall:3@20+30");
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0]["tick"], 50);
  EXPECT_EQ(ended[0]["detail"], "stall:3@20+30: SIGCONT pid " + std::to_string(pid));
  EXPECT_EQ(summary("stall")["ticks"], 120);
}

TEST_F(ProcessFaults, AStallWithoutTheAgentsPidWithholdsItsPacketsAndAStallPastTheEndIsContinued) {
  const int domain = swarmform::testing::test_domain(45);
  auto a = agents(domain, "withheld");
  const pid_t pid5 = a[5]->pid();
  // Robot 2: no --agent-pid, its packets are withheld for ticks 10..29. Robot 5: stopped at tick 40 for
  // longer than the run; the world continues it before the end, so it hears the END and exits 0.
  Process& w = world(domain, "withheld",
                     {"--max-ticks", "60", "--fault", "stall:2@10+20", "--fault", "stall:5@40+1000",
                      "--agent-pid", "5=" + std::to_string(pid5)});
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  for (int i = 0; i < kRobots; ++i) {
    if (i == 5) continue;
    EXPECT_EQ(a[i]->wait_for(10.0), 0) << "agent " << i << ": " << a[i]->err();
  }
  // Agent 5 was continued, so it ends by itself. (Stopped past its 500 ms lease, it was taken for dead and
  // may not get the END: whether it does is the liveliness rule's (docs/wire.md), not the fault's.)
  const auto code5 = a[5]->wait_for(20.0);
  EXPECT_TRUE(code5.has_value()) << "agent 5 still stopped or running: state " << process_state(pid5);
  if (code5) {
    EXPECT_LT(*code5, 128) << "agent 5 died of a signal";
  }
  // 61 packets (ticks 0..59 and the END) less the 20 withheld.
  EXPECT_NE(a[2]->out().find("agent id=2 packets=41 "), std::string::npos) << a[2]->out();
  const auto withheld = fault_events("withheld", "fault", "stall:2@10+20");
  ASSERT_EQ(withheld.size(), 1u);
  EXPECT_EQ(withheld[0]["tick"], 10);
  EXPECT_NE(withheld[0]["detail"].get<std::string>().find("its packets are withheld for 20 ticks"),
            std::string::npos);
  EXPECT_EQ(fault_events("withheld", "fault_end", "stall:2@10+20").at(0)["tick"], 30);
  const auto continued = fault_events("withheld", "fault_end", "stall:5@40+1000");
  ASSERT_EQ(continued.size(), 1u);
  EXPECT_NE(
      continued[0]["detail"].get<std::string>().find("SIGCONT pid " + std::to_string(pid5) + " at the end"),
      std::string::npos);
}

TEST_F(ProcessFaults, WorldFaultsGiveTheDdsWorldTheInProcessTrajectoryBitForBit) {
  const int domain = swarmform::testing::test_domain(46);
  const std::vector<std::string> faults = {"--fault", "wheel:1/left@10+30", "--fault", "loss:all@40+10",
                                           "--fault", "range:all@60=1.0",   "--fault", "ultrasonic:2@5",
                                           "--fault", "loss:6@70+20"};
  auto a = agents(domain, "world");
  std::vector<std::string> extra = {"--max-ticks", "120"};
  extra.insert(extra.end(), faults.begin(), faults.end());
  Process& w = world(domain, "world", extra);
  EXPECT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  for (int i = 0; i < kRobots; ++i)
    EXPECT_EQ(a[i]->wait_for(10.0), 0) << "agent " << i << ": " << a[i]->err();

  std::vector<std::string> argv = {kInProcess, "--scenario", kScenario, "--max-ticks",
                                   "120",      "--quiet",    "--out",   path("inprocess")};
  argv.insert(argv.end(), faults.begin(), faults.end());
  Process& in = start(argv, "inprocess");
  EXPECT_EQ(in.wait_for(kRunDeadline), 0) << in.err();

  const std::string dds_sha = summary("world")["trajectory_sha256"];
  EXPECT_EQ(dds_sha.size(), 64u);
  EXPECT_EQ(dds_sha, summary("inprocess")["trajectory_sha256"].get<std::string>());
  // And the same fault events, at the same ticks.
  for (const std::string kind : {"fault", "fault_end"}) {
    std::vector<Json> dds;
    std::vector<Json> inp;
    for (const Json& e : events("world")) {
      if (e["kind"] == kind) dds.push_back(e);
    }
    for (const Json& e : events("inprocess")) {
      if (e["kind"] == kind) inp.push_back(e);
    }
    EXPECT_EQ(dds.size(), kind == "fault" ? 5u : 3u);
    EXPECT_EQ(Json(dds).dump(), Json(inp).dump());
  }
}

}  // namespace
