// A clean Ctrl-C for a DDS process: SIGINT and SIGTERM are blocked in every thread (construct this first in
// main, before any DDS thread exists, so they inherit the mask) and taken by one watcher thread with sigwait,
// which sets a flag and wakes the main thread's Waiter. No work happens in a signal handler.
#pragma once

#include <atomic>
#include <thread>

#include "common/dds/waiter.hpp"

namespace swarmform::dds {

class SignalWatch {
 public:
  SignalWatch();
  ~SignalWatch();
  SignalWatch(const SignalWatch&) = delete;
  SignalWatch& operator=(const SignalWatch&) = delete;

  // The waiter to wake when a signal comes (nullptr: none). Call before waiting on it.
  void notify(Waiter* waiter);
  bool stop_requested() const { return signal_.load() != 0; }
  int signal() const { return signal_.load(); }

 private:
  void run();
  std::atomic<int> signal_{0};
  std::atomic<bool> quitting_{false};
  std::atomic<Waiter*> waiter_{nullptr};
  std::thread thread_;
};

}  // namespace swarmform::dds
