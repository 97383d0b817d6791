// The cost of the assignment of robots to places (behaviour/shape_assignment.hpp), for the figures
// in behaviour/README.md. Square blocks of side x side labels with as many robots, each robot 3 cm
// (RMS) off its place, the block turned 0.3 rad; robots listed in a shuffled order.
//   assignment_cost [--sides 10,20,32] [--repeat 20]
// Prints, per size, in CPU ms: one tick's evaluation seeded by the right labels (the certificate; what every
// tick from formation on costs), one Hungarian solve of the robots against the fitted places (what a tick
// costs when the certificate fails), and a solve from no guess at all (the fallback: the shape laid at a few
// angles, each improved greedily, the best refined with Hungarian solves), with its solve count, and the
// same for robots scattered at random over the block's area (not formed: the worst case), and the radial
// bound that rules those out before formation (bound_ms, and its value in grid units: above 0.1 rules out).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "behaviour/shape_assignment.hpp"

namespace {

using namespace swarmform;
// CPU seconds of this process per call (the machine is shared: wall time would count the others' work).
template <class F>
double seconds_per_call(int repeat, F&& f) {
  const std::clock_t start = std::clock();
  for (int k = 0; k < repeat; ++k) f();
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC / repeat;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "assignment_cost: the time the shape measurement's robot-to-place assignment takes for square blocks"};
  std::vector<int> sides{10, 20, 32};
  int repeat = 20;
  app.add_option("--sides", sides, "block sides (labels = side^2)")->delimiter(',');
  app.add_option("--repeat", repeat, "calls timed per figure (the Hungarian ones: a quarter, at least 1)");
  CLI11_PARSE(app, argc, argv);

  std::printf("%7s %14s %14s %14s %8s %14s %8s %10s %8s\n", "labels", "certified_ms", "hungarian_ms",
              "no_guess_ms", "solves", "scattered_ms", "solves", "bound_ms", "bound");
  for (const int side : sides) {
    ShapeMatrix shape{side, side, std::vector<int>(static_cast<std::size_t>(side * side))};
    std::iota(shape.cells.begin(), shape.cells.end(), 0);
    const std::size_t n = shape.cells.size();
    const shape_metrics::ShapeAssigner assigner(shape, 1.0, 1.5707963267948966);
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.03 / std::sqrt(2.0));
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<Vec2> robots(n);
    std::vector<int> labels(n);
    const double a = 0.3;
    for (std::size_t i = 0; i < n; ++i) {
      const int l = static_cast<int>(order[i]);
      const double x = l % side;
      const double y = -(l / side);
      robots[i] = {std::cos(a) * x - std::sin(a) * y + 5.0 + noise(rng),
                   std::sin(a) * x + std::cos(a) * y - 2.0 + noise(rng)};
      labels[i] = l;
    }
    const double certified = seconds_per_call(repeat, [&] {
      const auto r = assigner.solve(robots, labels, false);
      if (!r.optimal) std::printf("  (not certified)\n");
    });
    // The Hungarian solve as the tracker meets it: robots against the places of the fitted shape.
    std::vector<Vec2> fitted(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double x = static_cast<double>(j % static_cast<std::size_t>(side));
      const double y = -static_cast<double>(j / static_cast<std::size_t>(side));
      fitted[j] = {std::cos(a) * x - std::sin(a) * y + 5.0, std::sin(a) * x + std::cos(a) * y - 2.0};
    }
    std::vector<double> cost(n * n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) {
        const double dx = robots[i].x - fitted[j].x;
        const double dy = robots[i].y - fitted[j].y;
        cost[i * n + j] = dx * dx + dy * dy;
      }
    }
    const int slow = std::max(1, repeat / 4);
    const double hung = seconds_per_call(slow, [&] { (void)shape_metrics::hungarian(cost, n, n); });
    std::size_t solves = 0;
    double error = 0.0;
    const double no_guess = seconds_per_call(slow, [&] {
      const auto r = assigner.solve(robots, std::vector<int>(n, -1), true);
      solves = r.full_solves;
      error = r.error;
    });
    // Not formed: the robots scattered at random over the block's area, at rest, reporting their labels (the
    // worst the tracker meets: robots at rest that do not stand in the shape).
    std::uniform_real_distribution<double> across(0.0, side);
    std::vector<Vec2> scattered(n);
    for (Vec2& p : scattered) p = {across(rng), -across(rng)};
    std::size_t scattered_solves = 0;
    const double scattered_s = seconds_per_call(slow, [&] {
      const auto r = assigner.solve(scattered, labels, true);
      scattered_solves = r.full_solves;
    });
    // What the shape metrics do instead before formation (shape_metrics.cpp): the radial bound, which rules
    // the scattered robots out when it is above the formation error.
    double bound = 0.0;
    const double bound_s = seconds_per_call(repeat, [&] { bound = assigner.error_lower_bound(scattered); });
    std::printf(
        "%7zu %14.3f %14.1f %14.1f %8zu %14.1f %8zu %10.3f %8.3f   (error from no guess %.3f grid units)\n",
        n, certified * 1e3, hung * 1e3, no_guess * 1e3, solves, scattered_s * 1e3, scattered_solves,
        bound_s * 1e3, bound, error);
  }
  return 0;
}
