#include "robot_agent/exec/exec_controller.hpp"

#include <algorithm>

#include "robot_agent/exec/line_protocol.hpp"

namespace swarmform::agent {

namespace {

constexpr std::chrono::milliseconds kExitGrace{500};  // for the child to be reaped once its stdout closed
constexpr std::chrono::milliseconds kKeepAlivePeriod{100};  // well within the agents' 500 ms liveliness lease

std::string ms_text(std::chrono::milliseconds ms) {
  const auto whole = ms.count() / 1000;
  const auto frac = ms.count() % 1000;
  return frac == 0 ? std::to_string(whole) + " s" : std::to_string(ms.count()) + " ms";
}

}  // namespace

ExecController::ExecController(ExecOptions options) : options_(std::move(options)) {}

ExecController::~ExecController() = default;  // ~ChildProcess kills and reaps

void ExecController::fail(const std::string& what) {
  const std::string pid = child_ ? " (pid " + std::to_string(child_->pid()) + ")" : std::string();
  child_.reset();  // killed and reaped now: a failed robot leaves no process behind
  throw BehaviourFailure("robot " + std::to_string(self_) + ": the behaviour '" + options_.command + "'" +
                         pid + " " + what);
}

std::string ExecController::read_reply(std::chrono::milliseconds timeout,
                                       std::chrono::steady_clock::time_point since, const std::string& due) {
  std::string line;
  const auto deadline = since + timeout;
  ChildProcess::Read got = ChildProcess::Read::Timeout;
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    got = child_->read_line(std::min(left, kKeepAlivePeriod), line, kMaxLineBytes);
    if (got != ChildProcess::Read::Timeout) break;
    if (options_.keep_alive) options_.keep_alive();
  }
  switch (got) {
    case ChildProcess::Read::Line:
      return line;
    case ChildProcess::Read::Timeout:
      fail("did not answer " + due + " within " + ms_text(timeout) + " (hung, or it writes no newline)");
    case ChildProcess::Read::TooLong:
      fail("wrote a line over " + std::to_string(kMaxLineBytes) + " bytes where " + due + " was due");
    case ChildProcess::Read::Exited:
      break;
  }
  fail(child_->exit_description(kExitGrace) + " instead of answering " + due);
}

void ExecController::send(const std::string& line, std::chrono::milliseconds timeout,
                          const std::string& what) {
  child_->queue_line(line);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    switch (child_->flush(std::max(std::chrono::milliseconds(0), std::min(left, kKeepAlivePeriod)))) {
      case ChildProcess::Write::Done:
        return;
      case ChildProcess::Write::Closed:
        fail(child_->exit_description(kExitGrace) + " before reading " + what);
      case ChildProcess::Write::Timeout:
        break;
    }
    if (left.count() <= 0) fail("did not read " + what + " within " + ms_text(timeout) + " (hung)");
    if (options_.keep_alive) options_.keep_alive();
  }
}

void ExecController::init(const Mission& mission, RobotId self) {
  mission_ = mission;
  self_ = self;
  child_.reset();
  try {
    child_ = std::make_unique<ChildProcess>(options_.command, "SWARMFORM_ROBOT_ID", std::to_string(self));
  } catch (const std::exception& e) {
    fail(std::string("could not be started: ") + e.what());
  }
  const auto start = std::chrono::steady_clock::now();
  send(encode_hello(mission, self), options_.hello_timeout, "the hello");
  const std::string reply = read_reply(options_.hello_timeout, start, "the hello");
  try {
    (void)parse_hello_reply(reply);
  } catch (const ProtocolError& e) {
    fail(e.what());
  }
}

Command ExecController::step(const Perception& perception) {
  if (!child_) fail("is not running (it failed before)");
  const std::string due = "the perception of tick " + std::to_string(perception.tick);
  // One deadline for the whole exchange: the child reads the perception and answers within reply_timeout.
  const auto start = std::chrono::steady_clock::now();
  send(encode_perception(perception), options_.reply_timeout, due);
  const std::string reply = read_reply(options_.reply_timeout, start, due);
  try {
    return parse_command(reply, perception.tick, mission_.max_message_bytes);
  } catch (const ProtocolError& e) {
    fail(e.what());
  }
}

void ExecController::reset() {
  init(mission_, self_);
}

}  // namespace swarmform::agent
