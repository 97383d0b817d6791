#include "common/dds/signal_watch.hpp"

#include <pthread.h>
#include <signal.h>

#include <stdexcept>

namespace swarmform::dds {

namespace {
// SIGUSR2 only ends the watcher (sent by the destructor to its own thread).
sigset_t watched_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGUSR2);
  return set;
}
}  // namespace

SignalWatch::SignalWatch() {
  const sigset_t set = watched_set();
  if (pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) throw std::runtime_error("pthread_sigmask failed");
  thread_ = std::thread([this] { run(); });
}

SignalWatch::~SignalWatch() {
  quitting_.store(true);
  waiter_.store(nullptr);
  pthread_kill(thread_.native_handle(), SIGUSR2);
  thread_.join();
}

void SignalWatch::notify(Waiter* waiter) {
  waiter_.store(waiter);
}

void SignalWatch::run() {
  const sigset_t set = watched_set();
  for (;;) {
    int sig = 0;
    if (sigwait(&set, &sig) != 0) continue;
    if (quitting_.load()) return;
    if (sig == SIGUSR2) continue;
    signal_.store(sig);
    if (Waiter* w = waiter_.load()) {
      try {
        w->wake();
      } catch (const DdsError&) {
        // The waiter is being torn down; the flag is set and will be seen.
      }
    }
  }
}

}  // namespace swarmform::dds
