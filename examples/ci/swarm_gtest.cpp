// A swarm as a GoogleTest: launch six robots of our own behaviour (a Python program over --exec), kill two of
// them, and assert on the run's summary.json, with a deadline and cleanup. Build it in your project with
//   find_package(GTest REQUIRED)
//   add_executable(swarm_gtest swarm_gtest.cpp)
//   target_link_libraries(swarm_gtest PRIVATE GTest::gtest_main)
// and run it from the swarmform checkout (or set SWARM to the path of scripts/swarm).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

class SwarmTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/swarm-gtest-XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }  // cleanup, pass or fail

  // Runs `swarm run ARGS --out DIR/run` under a deadline (SIGTERM after 600 s: swarm stops the world and
  // every agent; SIGKILL 30 s later). Returns swarm's exit code (124/137: the deadline passed).
  int swarm_run(const std::string& args) {
    const char* swarm = std::getenv("SWARM");
    const std::string cmd = "timeout -k 30 600 " + std::string(swarm ? swarm : "scripts/swarm") + " run " +
                            args + " --no-pictures --out '" + (dir_ / "run").string() + "'";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

  std::string summary() const {
    std::ifstream in(dir_ / "run" / "summary.json");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  fs::path dir_;
};

TEST_F(SwarmTest, SixAggregatingRobotsSurviveTwoKills) {
  const int code = swarm_run(
      "--scenario examples/agents/aggregation.yaml --exec 'python3 examples/agents/aggregation.py' "
      "--max-ticks 400 --kill 1@100 --kill 4@200 "
      "--expect 'deaths == 2' --expect 'alive_at_end == 4' --expect 'command_verdicts == 0'");
  // 0: the run ended and every --expect held; 4: an expectation failed (swarm printed which); else the run
  // failed.
  ASSERT_EQ(code, 0) << "swarm run failed; its output above says why";
  // The summary is plain JSON for anything --expect does not say (a JSON library reads it properly).
  EXPECT_NE(summary().find("\"robots\": 6"), std::string::npos) << summary();
}
