// Faces (docs/wire.md "Faces"): a world of 66 robots speaks through two participants, face 0 for
// robots 0..63 and face 1 for 64 and 65, and agent K peers with face K/64 only. One lockstep run with every
// robot its own process (a forked robot_agent --count block) must give the in-process harness's trajectory
// bit for bit, every agent must get its own packets only (none of another robot), and the world must have had
// two faces. Test domain 59 (test_domain.hpp); every process is SIGKILLed and reaped by the fixture, every
// wait has a deadline.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/dds/cyclone_config.hpp"
#include "tests/support/process.hpp"
#include "tests/support/process_fixture.hpp"
#include "tests/support/test_domain.hpp"

namespace {

using swarmform::testing::Process;
using swarmform::testing::read_file;
using Json = nlohmann::json;

constexpr int kRobots = 66;
constexpr int kTicks = 40;
constexpr double kRunDeadline = 90.0;  // s, for one whole run (a few seconds on a quiet machine)

const std::string kWorld = WORLD_SERVER_EXE;
const std::string kAgent = ROBOT_AGENT_EXE;
const std::string kInProcess = SWARM_INPROCESS_EXE;
const std::string kScenario = FACES_SCENARIO;

// The lines of events.jsonl that would make a multi-process run differ from the in-process one.
std::string late_or_dead_events(const std::string& events) {
  std::string out;
  std::size_t from = 0;
  while (from < events.size()) {
    const std::size_t end = std::min(events.find('\n', from), events.size());
    const std::string line = events.substr(from, end - from);
    for (const char* kind : {"\"command_waited_out\"", "\"death\"", "\"agent_stalled\"", "\"rejoin\""}) {
      if (line.find(kind) != std::string::npos) {
        out += line + "\n";
        break;
      }
    }
    from = end + 1;
  }
  return out;
}

class Faces : public swarmform::testing::ProcessFixture {
 protected:
  Faces() : ProcessFixture("swarmform-faces") {}
  Json summary(const std::string& run) const { return Json::parse(read_file(path(run) + "/summary.json")); }
};

TEST_F(Faces, TwoFacesGiveTheInProcessTrajectoryBitForBitAndEachAgentOnlyItsOwnPackets) {
  ASSERT_EQ(swarmform::dds::face_count(kRobots), 2u);
  const int domain = swarmform::testing::test_domain(59);
  Process& block = start({kAgent, "--id", "0", "--count", std::to_string(kRobots), "--domain",
                          std::to_string(domain), "--timeout", "60"},
                         "block");
  // Every id's process, as `swarm run` tells the world: a block slow to answer its first packets (66 robots
  // in one process, under the sanitizers on a loaded host) is then waited for, not taken for dead at tick 0.
  const std::string pids = path("block.pids.json");
  {
    std::ofstream f(pids);
    for (int id = 0; id < kRobots; ++id) f << (id == 0 ? "{" : ", ") << '"' << id << "\": " << block.pid();
    f << "}";
  }
  Process& w = start({kWorld, "--scenario", kScenario, "--out", path("dds"), "--domain",
                      std::to_string(domain), "--connect-timeout", "60", "--agent-pids", pids},
                     "world");
  ASSERT_EQ(w.wait_for(kRunDeadline), 0) << w.err();
  EXPECT_EQ(block.wait_for(20.0), 0) << block.err();
  EXPECT_NE(w.out().find("done ticks=" + std::to_string(kTicks)), std::string::npos) << w.out();
  // Robots on both faces: each got every tick's packet and the END, and none of another robot.
  for (const int id : {0, 63, 64, 65}) {
    EXPECT_NE(block.out().find("agent id=" + std::to_string(id) + " packets=" + std::to_string(kTicks + 1) +
                               " foreign_packets=0"),
              std::string::npos)
        << "agent " << id << ": " << block.out();
  }
  EXPECT_EQ(w.err().find("refused a claim"), std::string::npos) << w.err();
  const Json dds = summary("dds");
  EXPECT_EQ(dds["alive_at_end"], kRobots);

  Process& in =
      start({kInProcess, "--scenario", kScenario, "--quiet", "--out", path("inprocess")}, "inprocess");
  ASSERT_EQ(in.wait_for(kRunDeadline), 0) << in.err();
  const std::string sha = dds["trajectory_sha256"];
  EXPECT_EQ(sha.size(), 64u);
  EXPECT_EQ(sha, summary("inprocess")["trajectory_sha256"].get<std::string>())
      << "the DDS run's events of late commands and deaths, if any:\n"
      << late_or_dead_events(read_file(path("dds") + "/events.jsonl"));
}

}  // namespace
