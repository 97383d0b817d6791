// A child process for the integration tests: started with fork/exec, stdout and stderr to files, waited for
// with a deadline, killed by its pid (SIGKILL) when the test is done with it, whatever happened.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace swarmform::testing {

class Process {
 public:
  // `out_prefix`: stdout goes to out_prefix + ".out", stderr to out_prefix + ".err". `env`: "NAME=VALUE"
  // set in the child's environment besides the test's own.
  Process(const std::vector<std::string>& argv, const std::string& out_prefix,
          const std::vector<std::string>& env = {});
  ~Process();  // SIGKILL if still running, then reap
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  pid_t pid() const { return pid_; }
  // The exit code (128+signal if killed by one), or nullopt if still running after `seconds`.
  std::optional<int> wait_for(double seconds);
  bool running();
  void kill();  // SIGKILL and reap

  std::string out() const;
  std::string err() const;

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
  std::string prefix_;
};

std::string read_file(const std::string& path);

// Polls `predicate` every 10 ms until it holds or `seconds` pass; returns whether it held.
template <typename F>
bool eventually(double seconds, F&& predicate);

}  // namespace swarmform::testing

#include <chrono>
#include <thread>

template <typename F>
bool swarmform::testing::eventually(double seconds, F&& predicate) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    if (predicate()) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}
