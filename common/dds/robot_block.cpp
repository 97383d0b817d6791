#include "common/dds/robot_block.hpp"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>

namespace swarmform::dds {

namespace {

int exit_code_of(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

}  // namespace

int run_robot_block(const char* name, std::uint32_t first, std::uint32_t count,
                    const std::function<int(std::uint32_t)>& robot, std::ostream& out) {
  if (!block_ids_fit(first, count)) {
    std::cerr << name << ": --id " << first << " --count " << count << ": the ids pass 2^32 - 1\n";
    return 2;
  }
  // The signals the parent takes with sigwait (never a handler); blocked before the first fork so that none
  // is lost between forks. Each child restores the mask it had.
  sigset_t taken, before;
  sigemptyset(&taken);
  sigaddset(&taken, SIGINT);
  sigaddset(&taken, SIGTERM);
  sigaddset(&taken, SIGCHLD);
  if (sigprocmask(SIG_BLOCK, &taken, &before) != 0) throw std::runtime_error("sigprocmask failed");
  const pid_t parent = getpid();
  std::map<pid_t, std::uint32_t> running;  // pid -> robot id
  int worst = 0;

  auto forward = [&](int sig) {
    for (const auto& [pid, id] : running) ::kill(pid, sig);
  };

  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint32_t id = first + i;
    std::cout.flush();  // nothing buffered may be written twice, by the parent and by a child
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) {
      std::cerr << name << ": fork for id " << id << " failed: " << std::strerror(errno) << "; stopping the "
                << running.size() << " robots started\n";
      forward(SIGTERM);
      worst = 1;
      break;
    }
    if (pid == 0) {
      // The child: dies with the parent; a parent already gone (it died before prctl) means stop now.
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent) std::_Exit(128 + SIGTERM);
      sigprocmask(SIG_SETMASK, &before, nullptr);
      const int code = robot(id);
      std::cout.flush();
      std::exit(code);
    }
    running[pid] = id;
    out << name << ": id " << id << " pid " << pid << std::endl;
  }

  while (!running.empty()) {
    int sig = 0;
    if (sigwait(&taken, &sig) != 0) continue;
    if (sig == SIGINT || sig == SIGTERM) {
      forward(sig);
      worst = std::max(worst, 128 + sig);
      continue;
    }
    // SIGCHLD: reap every child that has ended (several may share one signal).
    for (;;) {
      int status = 0;
      const pid_t pid = waitpid(-1, &status, WNOHANG);
      if (pid <= 0) break;
      if (running.erase(pid) == 0) continue;
      worst = std::max(worst, exit_code_of(status));
    }
  }
  sigprocmask(SIG_SETMASK, &before, nullptr);
  return worst;
}

}  // namespace swarmform::dds
