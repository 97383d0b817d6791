// One child process reached through its stdin and stdout, for a behaviour that runs as its own program
// (robot_agent --exec). It is POSIX plumbing only: no DDS, no JSON. Every read has a deadline, a child that
// dies is told apart from one that is silent, and the destructor always kills and reaps it, so an agent can
// neither hang on nor leak its child.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <string>

namespace swarmform::agent {

class ChildProcess {
 public:
  // Starts `/bin/sh -c "exec <command>"` (so a command line quotes as in a shell) with its stdin and stdout
  // on pipes to this process and its stderr inherited (the agent's log). The child gets SIGKILL when the
  // thread that started it ends (prctl PR_SET_PDEATHSIG), default signal handling and an empty signal mask,
  // no other descriptor of ours, and `env_name=env_value` in its environment. Throws std::runtime_error when
  // it cannot be started (no pipe, no fork).
  ChildProcess(const std::string& command, const std::string& env_name, const std::string& env_value);
  ~ChildProcess();  // kill_and_reap()
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  enum class Read { Line, Exited, Timeout, TooLong };
  // One line (without its '\n') into `line`, waiting at most `timeout`. Exited: the child closed its stdout
  // (it exited or is exiting); Timeout: nothing complete within the deadline; TooLong: more than max_line
  // bytes without a newline.
  Read read_line(std::chrono::milliseconds timeout, std::string& line, std::size_t max_line);
  enum class Write { Done, Closed, Timeout };
  // Queues `line` and a '\n' for the child's stdin.
  void queue_line(const std::string& line);
  // Writes what is queued, waiting at most `timeout` for the child to read it (a line longer than the pipe's
  // buffer needs the child to read; one that never reads must not hang us). Closed: its stdin is closed (it
  // exited); Timeout: some is still queued (call again to go on).
  Write flush(std::chrono::milliseconds timeout);
  // How the child ended, as a phrase ("exited with code 3", "was killed by signal 9 (Killed)"), waiting at
  // most `grace` for it to end after its stdout closed; "is still running" otherwise.
  std::string exit_description(std::chrono::milliseconds grace);
  // Closes its stdin, gives it `grace` to exit on its own, then SIGKILLs and reaps it. Idempotent.
  void kill_and_reap(std::chrono::milliseconds grace = std::chrono::milliseconds(200));

  pid_t pid() const { return pid_; }

 private:
  bool reap(std::chrono::milliseconds wait);  // true once waitpid has collected it (status_ set)

  pid_t pid_ = -1;
  int to_child_ = -1;    // its stdin
  int from_child_ = -1;  // its stdout
  std::string buffer_;   // bytes read past the last line returned
  std::string pending_;  // bytes queued for its stdin, not yet written
  bool reaped_ = false;
  int status_ = 0;  // waitpid status once reaped_
};

}  // namespace swarmform::agent
