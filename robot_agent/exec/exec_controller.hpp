// A behaviour that runs as its own program (robot_agent --exec "CMD"), behind the pure Controller interface:
// the adapter owns the child process and translates each tick's Perception and Command through the line
// protocol (line_protocol.hpp), so the rest of the agent does not know the behaviour is not C++.
// A child that exits, stays silent past its deadline, or writes anything but a valid answer ends the robot:
// step() and init() throw BehaviourFailure naming the robot, the command and what the child did, and the
// child is killed and reaped (here or in the destructor, whichever comes first).
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "behaviour/controller.hpp"
#include "robot_agent/exec/child_process.hpp"

namespace swarmform::agent {

struct BehaviourFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ExecOptions {
  std::string command;                             // as given to --exec: run by /bin/sh -c "exec CMD"
  std::chrono::milliseconds reply_timeout{5000};   // for each command
  std::chrono::milliseconds hello_timeout{10000};  // for the hello (an interpreter's start-up included)
  // Called at least every 100 ms while the child is being waited for: the agent renews its liveliness, so a
  // behaviour that is slow (but within its deadline) is not taken for a dead robot. May be empty.
  std::function<void()> keep_alive;
};

class ExecController final : public controller::Controller {
 public:
  explicit ExecController(ExecOptions options);
  ~ExecController() override;

  void init(const Mission& mission, RobotId self) override;  // starts the child and shakes hands
  Command step(const Perception& perception) override;
  void reset() override;  // a fresh child, handshake again

  // The child's pid (-1 before init or after a failure), for tests.
  pid_t child_pid() const { return child_ ? child_->pid() : -1; }

 private:
  [[noreturn]] void fail(const std::string& what);
  // The child's next line, within `timeout` of `since` (when the exchange began).
  std::string read_reply(std::chrono::milliseconds timeout, std::chrono::steady_clock::time_point since,
                         const std::string& due);
  void send(const std::string& line, std::chrono::milliseconds timeout, const std::string& what);

  ExecOptions options_;
  Mission mission_;
  RobotId self_ = 0;
  std::unique_ptr<ChildProcess> child_;
};

}  // namespace swarmform::agent
