#include "tests/support/process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace swarmform::testing {

Process::Process(const std::vector<std::string>& argv, const std::string& out_prefix,
                 const std::vector<std::string>& env)
    : prefix_(out_prefix) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string out = out_prefix + ".out";
  const std::string err = out_prefix + ".err";
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0) _exit(126);
    dup2(o, STDOUT_FILENO);
    dup2(e, STDERR_FILENO);
    // The test runner may have blocked signals; the child starts clean.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    for (const std::string& var : env) {
      const auto eq = var.find('=');
      if (eq == std::string::npos || setenv(var.substr(0, eq).c_str(), var.c_str() + eq + 1, 1) != 0)
        _exit(126);
    }
    execv(args[0], args.data());
    _exit(127);
  }
}

Process::~Process() {
  kill();
}

bool Process::running() {
  if (status_ || pid_ <= 0) return false;
  int st = 0;
  const pid_t r = waitpid(pid_, &st, WNOHANG);
  if (r == pid_) {
    status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    return false;
  }
  return true;
}

std::optional<int> Process::wait_for(double seconds) {
  eventually(seconds, [&] { return !running(); });
  return status_;
}

void Process::kill() {
  if (running()) {
    ::kill(pid_, SIGKILL);
    int st = 0;
    waitpid(pid_, &st, 0);
    status_ = 128 + SIGKILL;
  }
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string Process::out() const {
  return read_file(prefix_ + ".out");
}
std::string Process::err() const {
  return read_file(prefix_ + ".err");
}

}  // namespace swarmform::testing
