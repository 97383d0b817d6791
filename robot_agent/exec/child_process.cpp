// fork + exec by hand rather than posix_spawn: the child must ask for SIGKILL at its parent's death
// (prctl), which posix_spawn cannot do. Between fork and exec only async-signal-safe calls are made: the
// agent has DDS threads running, and a fork copies only the calling one.
#include "robot_agent/exec/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

extern char** environ;

namespace swarmform::agent {

namespace {

std::runtime_error os_error(const std::string& what) {
  return std::runtime_error(what + ": " + std::strerror(errno));
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

}  // namespace

ChildProcess::ChildProcess(const std::string& command, const std::string& env_name,
                           const std::string& env_value) {
  // A write to a child that has exited must fail with EPIPE, not kill the agent with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);

  // Everything the child needs is built before the fork: it may not allocate afterwards.
  const std::string shell_line = "exec " + command;
  std::vector<char*> argv = {const_cast<char*>("/bin/sh"), const_cast<char*>("-c"),
                             const_cast<char*>(shell_line.c_str()), nullptr};
  const std::string env_entry = env_name + "=" + env_value;
  std::vector<char*> envp;
  const std::string prefix = env_name + "=";
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    if (std::strncmp(*e, prefix.c_str(), prefix.size()) != 0) envp.push_back(*e);
  }
  envp.push_back(const_cast<char*>(env_entry.c_str()));
  envp.push_back(nullptr);

  int in_pipe[2];   // agent -> child stdin
  int out_pipe[2];  // child stdout -> agent
  if (::pipe2(in_pipe, O_CLOEXEC) != 0) throw os_error("pipe");
  if (::pipe2(out_pipe, O_CLOEXEC) != 0) {
    ::close(in_pipe[0]);
    ::close(in_pipe[1]);
    throw os_error("pipe");
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int saved = errno;
    for (int fd : {in_pipe[0], in_pipe[1], out_pipe[0], out_pipe[1]}) ::close(fd);
    errno = saved;
    throw os_error("fork");
  }
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the parent died before prctl took effect
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    for (int s = 1; s < NSIG; ++s) ::sigaction(s, &dfl, nullptr);  // ignored dispositions survive exec
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);  // the agent blocks SIGINT/SIGTERM in every thread
    // dup2 onto itself keeps close-on-exec: clear it by hand then (fd 0 or 1 was free in the agent).
    auto onto = [](int fd, int target) {
      if (fd == target) return ::fcntl(fd, F_SETFD, 0) == 0;
      return ::dup2(fd, target) == target;
    };
    if (!onto(in_pipe[0], STDIN_FILENO) || !onto(out_pipe[1], STDOUT_FILENO)) ::_exit(127);
    ::close_range(3, ~0U, 0);  // no DDS socket or other agent descriptor leaks into the behaviour
    ::execve("/bin/sh", argv.data(), envp.data());
    ::_exit(127);
  }
  pid_ = pid;
  ::close(in_pipe[0]);
  ::close(out_pipe[1]);
  to_child_ = in_pipe[1];
  from_child_ = out_pipe[0];
  // Writes never block: a child that stops reading is a timeout (flush), not a hung agent.
  ::fcntl(to_child_, F_SETFL, ::fcntl(to_child_, F_GETFL) | O_NONBLOCK);
}

ChildProcess::~ChildProcess() {
  kill_and_reap();
}

ChildProcess::Read ChildProcess::read_line(std::chrono::milliseconds timeout, std::string& line,
                                           std::size_t max_line) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (const auto nl = buffer_.find('\n'); nl != std::string::npos) {
      if (nl > max_line) return Read::TooLong;
      line.assign(buffer_, 0, nl);
      buffer_.erase(0, nl + 1);
      return Read::Line;
    }
    if (buffer_.size() > max_line) return Read::TooLong;
    if (from_child_ < 0) return Read::Exited;
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return Read::Timeout;
    pollfd p{from_child_, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(left.count()));
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw os_error("poll on the behaviour's stdout");
    }
    if (ready == 0) return Read::Timeout;
    char chunk[4096];
    const ssize_t n = ::read(from_child_, chunk, sizeof chunk);
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      close_fd(from_child_);
      return Read::Exited;
    }
    if (n == 0) {
      close_fd(from_child_);
      return Read::Exited;
    }
    buffer_.append(chunk, static_cast<std::size_t>(n));
  }
}

void ChildProcess::queue_line(const std::string& line) {
  pending_ += line;
  pending_.push_back('\n');
}

ChildProcess::Write ChildProcess::flush(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!pending_.empty()) {
    if (to_child_ < 0) return Write::Closed;
    const ssize_t n = ::write(to_child_, pending_.data(), pending_.size());
    if (n > 0) {
      pending_.erase(0, static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno != EAGAIN) {
      close_fd(to_child_);  // EPIPE: the child closed its stdin or exited
      return Write::Closed;
    }
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return Write::Timeout;
    pollfd p{to_child_, POLLOUT, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) < 0 && errno != EINTR) {
      throw os_error("poll on the behaviour's stdin");
    }
  }
  return Write::Done;
}

bool ChildProcess::reap(std::chrono::milliseconds wait) {
  if (reaped_) return true;
  if (pid_ <= 0) return false;
  const auto deadline = std::chrono::steady_clock::now() + wait;
  for (;;) {
    const pid_t r = ::waitpid(pid_, &status_, WNOHANG);
    if (r == pid_ || (r < 0 && errno == ECHILD)) {
      reaped_ = true;
      return true;
    }
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

std::string ChildProcess::exit_description(std::chrono::milliseconds grace) {
  if (!reap(grace)) return "is still running";
  if (WIFEXITED(status_)) return "exited with code " + std::to_string(WEXITSTATUS(status_));
  if (WIFSIGNALED(status_)) {
    const int s = WTERMSIG(status_);
    return "was killed by signal " + std::to_string(s) + " (" + ::strsignal(s) + ")";
  }
  return "ended";
}

void ChildProcess::kill_and_reap(std::chrono::milliseconds grace) {
  close_fd(to_child_);  // end of its input: a well-behaved child exits by itself
  if (pid_ > 0 && !reap(grace)) {
    ::kill(pid_, SIGKILL);
    while (::waitpid(pid_, &status_, 0) < 0 && errno == EINTR) {
    }
    reaped_ = true;
  }
  close_fd(from_child_);
}

}  // namespace swarmform::agent
