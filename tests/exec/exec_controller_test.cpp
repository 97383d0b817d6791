// The --exec adapter against real children: one that behaves, and ones that exit, hang, write garbage or NaN,
// or speak another protocol version. Each failure must name the robot and what the child did, and leave no
// process behind (the child is reaped: signal 0 to its pid finds nothing).
#include "robot_agent/exec/exec_controller.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

namespace swarmform::agent {
namespace {

using std::chrono::milliseconds;

// A behaviour in Python with a fault chosen by argv[1], due at tick 2: ok, exit, slow (0.35 s late), garbage,
// nan, wrong_tick, ignore_eof (never exits by itself); hang (at tick 0) and deaf (reads nothing after the
// hello). Modes *_hello misbehave instead of answering the hello. The deadlines are long (30 s) except where
// the test is that one passes: a loaded machine must not fail a child that does answer.
constexpr const char* kChild = R"PY(
import json, sys, time
mode = sys.argv[1]
hello = json.loads(sys.stdin.readline())
if mode == "exit_hello": sys.exit(3)
if mode == "hang_hello": time.sleep(1000)
if mode == "version_hello":
    print(json.dumps({"type": "hello", "protocol": 99}), flush=True)
print(json.dumps({"type": "hello", "protocol": 1, "name": "test"}), flush=True)
if mode == "deaf": time.sleep(1000)
for line in sys.stdin:
    p = json.loads(line)
    t = p["tick"]
    left = p["pose"]["x"]
    if mode == "hang": time.sleep(1000)
    if t == 2:
        if mode == "exit": sys.exit(7)
        if mode == "slow": time.sleep(0.35)
        if mode == "garbage": print("left=1 right=2", flush=True); continue
        if mode == "nan": left = float("nan")
        if mode == "wrong_tick": t += 1
    data = "".join(m["data"] for m in p["messages"])
    print(json.dumps({"type": "command", "tick": t, "left": left, "right": hello["robot"], "message": data,
                      "state": 0, "events": ["tick %d" % p["tick"]]}), flush=True)
if mode == "ignore_eof": time.sleep(1000)
)PY";

class ExecControllerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("exec-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "child.py") << kChild;
    mission_.behaviour = "random_walk";
    mission_.max_message_bytes = 64;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  ExecOptions options(const std::string& mode) const {
    ExecOptions o;
    o.command = "python3 '" + (dir_ / "child.py").string() + "' " + mode;
    o.reply_timeout = milliseconds(30000);
    o.hello_timeout = milliseconds(30000);
    return o;
  }

  static Perception perception(Tick tick) {
    Perception p;
    p.tick = tick;
    p.pose.x = 0.25 * static_cast<double>(tick);
    p.messages.push_back(RabReading{1, 0.5, 0.0, {0xbe, 0xef}});
    return p;
  }

  static bool gone(pid_t pid) { return ::kill(pid, 0) != 0 && errno == ESRCH; }

  // Runs ticks 0.. until step throws; returns its message (empty if it never did within 5 ticks).
  std::string fail_message(ExecController& c) {
    for (Tick t = 0; t < 5; ++t) {
      try {
        (void)c.step(perception(t));
      } catch (const BehaviourFailure& e) {
        return e.what();
      }
    }
    return "";
  }

  std::filesystem::path dir_;
  Mission mission_;
};

TEST_F(ExecControllerTest, AWellBehavedChildAnswersEveryTick) {
  ExecController c(options("ok"));
  c.init(mission_, 4);
  for (Tick t = 0; t < 20; ++t) {
    const Command cmd = c.step(perception(t));
    EXPECT_EQ(cmd.left_speed, 0.25 * static_cast<double>(t));
    EXPECT_EQ(cmd.right_speed, 4.0);  // the robot id, from the hello
    EXPECT_EQ(cmd.message, (std::vector<std::uint8_t>{0xbe, 0xef}));
    EXPECT_EQ(cmd.telemetry.events, std::vector<std::string>{"tick " + std::to_string(t)});
  }
  const pid_t pid = c.child_pid();
  c.reset();  // a fresh child
  EXPECT_NE(c.child_pid(), pid);
  EXPECT_TRUE(gone(pid));
  EXPECT_EQ(c.step(perception(0)).right_speed, 4.0);
}

TEST_F(ExecControllerTest, AChildThatExitsIsADeadRobotSayingItsExitCode) {
  ExecController c(options("exit"));
  c.init(mission_, 3);
  const pid_t pid = c.child_pid();
  const std::string msg = fail_message(c);
  EXPECT_NE(msg.find("robot 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("exited with code 7"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tick 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("child.py"), std::string::npos) << msg;
  EXPECT_TRUE(gone(pid));
  EXPECT_EQ(c.child_pid(), -1);
  EXPECT_THROW((void)c.step(perception(3)), BehaviourFailure);  // stays dead
}

TEST_F(ExecControllerTest, AHungChildIsKilledAtItsDeadline) {
  ExecOptions o = options("hang");
  o.reply_timeout = milliseconds(300);
  ExecController c(o);
  c.init(mission_, 1);
  const pid_t pid = c.child_pid();
  const std::string msg = fail_message(c);
  EXPECT_NE(msg.find("robot 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did not answer the perception of tick 0 within 300 ms"), std::string::npos) << msg;
  EXPECT_TRUE(gone(pid));
}

TEST_F(ExecControllerTest, ASlowChildWithinItsDeadlineKeepsTheAgentAlive) {
  ExecOptions o = options("slow");
  int calls = 0;
  o.keep_alive = [&calls] { ++calls; };
  ExecController c(o);
  c.init(mission_, 0);
  (void)c.step(perception(0));
  (void)c.step(perception(1));
  const int before_slow = calls;
  (void)c.step(perception(2));  // 0.35 s: the agent's liveliness is renewed meanwhile (every 100 ms)
  EXPECT_GE(calls - before_slow, 1);
  EXPECT_EQ(c.step(perception(3)).left_speed, 0.75);
}

TEST_F(ExecControllerTest, AChildThatStopsReadingCannotBlockTheAgent) {
  ExecOptions o = options("deaf");
  o.reply_timeout = milliseconds(300);
  ExecController c(o);
  c.init(mission_, 1);
  const pid_t pid = c.child_pid();
  // It reads nothing after the hello; a perception larger than the pipe's buffer (64 KiB) must not block us.
  Perception big = perception(0);
  for (RobotId i = 0; i < 100; ++i)
    big.messages.push_back(RabReading{i, 1.0, 0.0, std::vector<std::uint8_t>(1024)});
  try {
    (void)c.step(big);
    ADD_FAILURE() << "a deaf child answered";
  } catch (const BehaviourFailure& e) {
    EXPECT_NE(std::string(e.what()).find("did not read the perception of tick 0 within 300 ms"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(gone(pid));
}

TEST_F(ExecControllerTest, GarbageNanAndAWrongTickAreDeadRobots) {
  const std::pair<const char*, const char*> cases[] = {
      {"garbage", "not JSON"}, {"nan", "non-finite"}, {"wrong_tick", "\"tick\" is 3"}};
  for (const auto& [mode, says] : cases) {
    ExecController c(options(mode));
    c.init(mission_, 2);
    const pid_t pid = c.child_pid();
    const std::string msg = fail_message(c);
    EXPECT_NE(msg.find("robot 2"), std::string::npos) << mode << ": " << msg;
    EXPECT_NE(msg.find(says), std::string::npos) << mode << ": " << msg;
    EXPECT_TRUE(gone(pid)) << mode;
  }
}

TEST_F(ExecControllerTest, AFailedHandshakeSaysWhy) {
  const std::pair<const char*, const char*> cases[] = {
      {"exit_hello", "exited with code 3 instead of answering the hello"},
      {"hang_hello", "did not answer the hello within 1 s"},
      {"version_hello", "speaks protocol 99, this agent speaks 1"}};
  for (const auto& [mode, says] : cases) {
    ExecOptions o = options(mode);
    if (std::string(mode) == "hang_hello") o.hello_timeout = milliseconds(1000);
    ExecController c(o);
    try {
      c.init(mission_, 5);
      ADD_FAILURE() << mode << ": the handshake passed";
    } catch (const BehaviourFailure& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << mode << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("robot 5"), std::string::npos) << e.what();
    }
    EXPECT_EQ(c.child_pid(), -1);
  }
}

TEST_F(ExecControllerTest, ACommandThatCannotRunIsADeadRobot) {
  ExecOptions o;
  o.command = "/nonexistent/behaviour --flag";
  ExecController c(o);
  try {
    c.init(mission_, 0);
    ADD_FAILURE() << "a missing program passed the handshake";
  } catch (const BehaviourFailure& e) {
    EXPECT_NE(std::string(e.what()).find("exited with code 127"), std::string::npos) << e.what();
  }
}

TEST_F(ExecControllerTest, TheAdapterKillsAndReapsAChildThatWillNotExit) {
  pid_t pid = -1;
  {
    ExecController c(options("ignore_eof"));
    c.init(mission_, 0);
    (void)c.step(perception(0));
    pid = c.child_pid();
    ASSERT_GT(pid, 0);
  }
  EXPECT_TRUE(gone(pid));
}

// A process is gone, or a zombie nobody reaped yet (an orphan's reaper may be slow, or absent in a
// container).
bool dead_or_zombie(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  if (text.empty()) return true;
  const auto close = text.rfind(')');
  return close != std::string::npos && close + 2 < text.size() && text[close + 2] == 'Z';
}

TEST_F(ExecControllerTest, AChildDiesWithItsAgentEvenIfItIgnoresTheEndOfItsInput) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t agent = ::fork();
  ASSERT_GE(agent, 0);
  if (agent == 0) {  // a stand-in agent: starts its behaviour, says its pid, waits to be killed
    ::close(fds[0]);
    ExecController c(options("ignore_eof"));
    c.init(mission_, 0);
    const pid_t child = c.child_pid();
    if (::write(fds[1], &child, sizeof child) != static_cast<ssize_t>(sizeof child)) ::_exit(1);
    ::pause();
    ::_exit(0);
  }
  ::close(fds[1]);
  pid_t child = -1;
  const bool got = ::read(fds[0], &child, sizeof child) == static_cast<ssize_t>(sizeof child);
  ::close(fds[0]);
  ::kill(agent, SIGKILL);  // as `swarm kill`: no destructor runs
  int status = 0;
  ::waitpid(agent, &status, 0);
  ASSERT_TRUE(got) << "the stand-in agent did not start its behaviour";
  bool died = false;
  for (int i = 0; i < 500 && !died; ++i) {  // SIGKILL is immediate; the deadline is for a loaded machine
    died = dead_or_zombie(child);
    if (!died) std::this_thread::sleep_for(milliseconds(10));
  }
  EXPECT_TRUE(died) << "the behaviour (pid " << child << ") outlived its agent";
  if (!died) ::kill(child, SIGKILL);
}

TEST_F(ExecControllerTest, TheChildKnowsItsRobotIdFromTheEnvironment) {
  ExecOptions o;
  o.command = R"(sh -c 'read hello; echo "{\"type\":\"hello\",\"protocol\":1}"; read p; )"
              R"(echo "{\"type\":\"command\",\"tick\":0,\"left\":$SWARMFORM_ROBOT_ID,\"right\":0}"')";
  ExecController c(o);
  c.init(mission_, 6);
  EXPECT_EQ(c.step(perception(0)).left_speed, 6.0);
}

}  // namespace
}  // namespace swarmform::agent
