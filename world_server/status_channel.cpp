#include "world_server/status_channel.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

namespace swarmform::server {

StatusChannel::StatusChannel(int fd) : fd_(fd) {
  // Not handed on to anything the world starts: the launcher sees end-of-file when the world exits.
  if (fd_ >= 0) (void)::fcntl(fd_, F_SETFD, FD_CLOEXEC);
}

StatusChannel::~StatusChannel() {
  if (fd_ >= 0) ::close(fd_);
}

void StatusChannel::emit(const std::string& event, nlohmann::ordered_json fields) {
  if (fd_ < 0) return;
  nlohmann::ordered_json line = {{"v", kStatusVersion}, {"event", event}};
  for (auto& [key, value] : fields.items()) line[key] = std::move(value);
  // One write per line (a pipe takes up to PIPE_BUF bytes atomically); a partial write is finished.
  const std::string text = line.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  // A reader that has gone must not end the run: SIGPIPE is held in this thread for the write, and the one it
  // raised (EPIPE) taken back before the mask is restored.
  sigset_t pipe_set;
  sigset_t old_set;
  sigemptyset(&pipe_set);
  sigaddset(&pipe_set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_set, &old_set);
  std::size_t done = 0;
  int error = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : EIO;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  if (error == EPIPE) {
    const timespec now{0, 0};
    while (sigtimedwait(&pipe_set, nullptr, &now) == SIGPIPE) {
    }
  }
  pthread_sigmask(SIG_SETMASK, &old_set, nullptr);
  if (error != 0) {
    std::cerr << "world_server: --status-fd " << fd_ << ": cannot write (" << std::strerror(error)
              << "); no more status lines\n";
    ::close(fd_);
    fd_ = -1;
  }
}

void StatusChannel::emit_and_print(const std::string& event, nlohmann::ordered_json fields,
                                   const std::string& human) {
  fields["line"] = human;
  emit(event, std::move(fields));
  std::fputs((human + "\n").c_str(), stdout);
  std::fflush(stdout);
}

}  // namespace swarmform::server
