// For information, not a test: the wall time of World::step for N robots with no controllers (every robot
// drives slowly forward and broadcasts 32 bytes every tick). Usage: world_step_timing [N] [ticks]
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <new>
#include <string>

#include "world_server/world/placement.hpp"
#include "world_server/world/world.hpp"

// Counts heap allocations, to show the step does not churn memory once warm.
static std::atomic<std::size_t> g_allocations{0};
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

int main(int argc, char** argv) {
  using namespace swarmform;
  using namespace swarmform::world;
  if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::printf(
        "usage: %s [N=1000] [TICKS=50]\n  prints the cost of World::step for N robots placed at random, "
        "each\n"
        "  driving an arc and broadcasting 32 bytes every tick (no controllers). For information only.\n",
        argv[0]);
    return 0;
  }
  const std::size_t n = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 1000;
  const int ticks = argc > 2 ? std::atoi(argv[2]) : 50;
  Scenario s;
  s.walls = false;
  s.seed = 1;
  const PlacementRegion region = default_region(n);
  auto poses = place_randomly(n, region, s, s.seed);
  if (!poses) {
    std::fprintf(stderr, "cannot place %zu robots\n", n);
    return 1;
  }
  s.robots = *poses;
  World w(s);
  Command c;
  c.left_speed = 0.05;
  c.right_speed = 0.06;
  c.message.assign(32, 7);
  // Wall time, and this thread's CPU time (which a busy shared machine inflates much less).
  auto cpu_now = [] {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  };
  double total = 0.0, cpu = 0.0;
  std::size_t allocations_after_warmup = 0;
  for (int t = 0; t < ticks; ++t) {
    if (t == 5) allocations_after_warmup = g_allocations;
    for (RobotId i = 0; i < n; ++i) w.apply_command(i, c);
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_now();
    w.step();
    cpu += cpu_now() - c0;
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  allocations_after_warmup = g_allocations - allocations_after_warmup;
  std::size_t heard = 0;
  for (RobotId i = 0; i < n; ++i) heard += w.perception(i).messages.size();
  const double robot_ticks = ticks * static_cast<double>(n);
  std::printf(
      "N=%zu region %.1f m square: World::step %.2f ms/tick wall, %.2f ms/tick CPU = %.2f us CPU per "
      "robot-tick "
      "(%.0f robot-ticks per CPU second); %.1f messages heard per robot; %.1f heap allocations per tick "
      "after "
      "5 ticks\n",
      n, region.width, 1e3 * total / ticks, 1e3 * cpu / ticks, 1e6 * cpu / robot_ticks, robot_ticks / cpu,
      static_cast<double>(heard) / static_cast<double>(n),
      ticks > 5 ? static_cast<double>(allocations_after_warmup) / (ticks - 5) : 0.0);
  return 0;
}
