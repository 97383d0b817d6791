// wakeup_cost: what one UDP round trip costs in CPU on this machine, with and without a thread hand-off on
// the answering side (bench/scale/README.md, "Where the run's CPU goes"). An agent-tick is at least one such
// round trip: the world's packet wakes Cyclone's receive thread, which wakes the agent's main thread through
// a condition variable (the waitset), which writes the command. Both variants run in one process, alternated,
// so that the ratio is measured in the same minutes:
//   direct   the receiving thread answers itself (one wake-up on the answering side);
//   handoff  the receiving thread hands each datagram to a second thread, which answers (two wake-ups).
// Prints one JSON line: CPU and wall µs per round trip for each, medians over --rounds, and their ratio.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

namespace {

double seconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

// A UDP socket bound to an ephemeral loopback port; its address in `at`.
int bound_socket(sockaddr_in& at) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) throw std::runtime_error("socket failed");
  at = {};
  at.sin_family = AF_INET;
  at.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof at;
  if (bind(fd, reinterpret_cast<sockaddr*>(&at), sizeof at) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&at), &len) != 0) {
    throw std::runtime_error("bind failed");
  }
  return fd;
}

struct Cost {
  double cpu_us = 0;
  double wall_us = 0;
};

// `trips` round trips of a `packet_bytes` datagram answered with `reply_bytes`; the process's CPU per trip.
Cost round_trips(bool handoff, int trips, std::size_t packet_bytes, std::size_t reply_bytes) {
  sockaddr_in agent_at{}, world_at{};
  const int agent = bound_socket(agent_at);
  const int world = bound_socket(world_at);
  std::mutex m;
  std::condition_variable cv;
  int pending = 0;
  const std::vector<char> reply(reply_bytes, 0);
  const auto answer = [&] {
    (void)sendto(agent, reply.data(), reply.size(), 0, reinterpret_cast<const sockaddr*>(&world_at),
                 sizeof world_at);
  };
  std::thread receiver([&] {
    std::vector<char> buf(65536);
    for (int i = 0; i < trips; ++i) {
      (void)recv(agent, buf.data(), buf.size(), 0);
      if (!handoff) {
        answer();
        continue;
      }
      const std::lock_guard lock(m);
      ++pending;
      cv.notify_one();
    }
  });
  std::thread main_thread([&] {
    if (!handoff) return;
    for (int i = 0; i < trips; ++i) {
      std::unique_lock lock(m);
      cv.wait(lock, [&] { return pending > 0; });
      --pending;
      lock.unlock();
      answer();
    }
  });
  const std::vector<char> packet(packet_bytes, 0);
  std::vector<char> got(65536);
  const double cpu0 = seconds(CLOCK_PROCESS_CPUTIME_ID), wall0 = seconds(CLOCK_MONOTONIC);
  for (int i = 0; i < trips; ++i) {
    (void)sendto(world, packet.data(), packet.size(), 0, reinterpret_cast<const sockaddr*>(&agent_at),
                 sizeof agent_at);
    (void)recv(world, got.data(), got.size(), 0);
  }
  const double cpu1 = seconds(CLOCK_PROCESS_CPUTIME_ID), wall1 = seconds(CLOCK_MONOTONIC);
  receiver.join();
  main_thread.join();
  close(agent);
  close(world);
  return {(cpu1 - cpu0) / trips * 1e6, (wall1 - wall0) / trips * 1e6};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "wakeup_cost: CPU of one loopback UDP round trip, answered directly or through a thread hand-off"};
  int rounds = 5, trips = 20000;
  std::size_t packet_bytes = 1000, reply_bytes = 200;
  app.add_option("--rounds", rounds, "alternated rounds of each variant (the median is printed)")
      ->check(CLI::Range(1, 100));
  app.add_option("--trips", trips, "round trips a round")->check(CLI::Range(100, 10000000));
  app.add_option("--packet-bytes", packet_bytes,
                 "the datagram's size (an emulator packet: ~1,000 B at 64 robots)")
      ->check(CLI::Range(1, 60000));
  app.add_option("--reply-bytes", reply_bytes, "the answer's size (a command: ~200 B)")
      ->check(CLI::Range(1, 60000));
  CLI11_PARSE(app, argc, argv);
  std::array<std::vector<double>, 2> cpu, wall;
  try {
    for (int r = 0; r < rounds; ++r) {
      for (const bool handoff : {false, true}) {
        const Cost c = round_trips(handoff, trips, packet_bytes, reply_bytes);
        cpu[handoff].push_back(c.cpu_us);
        wall[handoff].push_back(c.wall_us);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wakeup_cost: %s\n", e.what());
    return 1;
  }
  std::printf(
      "{\"rounds\": %d, \"trips\": %d, \"direct\": {\"cpu_us\": %.2f, \"wall_us\": %.2f}, "
      "\"handoff\": {\"cpu_us\": %.2f, \"wall_us\": %.2f}, \"handoff_over_direct_cpu\": %.3f}\n",
      rounds, trips, median(cpu[0]), median(wall[0]), median(cpu[1]), median(wall[1]),
      median(cpu[1]) / median(cpu[0]));
  return 0;
}
