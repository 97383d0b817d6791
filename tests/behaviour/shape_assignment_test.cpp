// The assignment of robots to the shape's places (behaviour/shape_assignment.hpp): it finds the
// places from the positions, whatever labels the robots report; spares are left out; with fewer robots than
// places every robot gets one; a mirror image is not fitted away; the Hungarian solve is optimal.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "behaviour/shape_assignment.hpp"

namespace swarmform::shape_metrics {
namespace {

constexpr double kHeading = std::numbers::pi / 2.0;  // shape frame = arena frame

// A 3x3 block, labels row-major.
ShapeMatrix block3() {
  return ShapeMatrix{3, 3, {0, 1, 2, 3, 4, 5, 6, 7, 8}};
}

// An L (no mirror symmetry through a proper rotation).
ShapeMatrix ell() {
  return ShapeMatrix{3, 2, {0, -1, 1, -1, 2, 3}};
}

// The arena position of `label` when the shape is turned by `angle` and moved by `offset`.
Vec2 at(const ShapeMatrix& shape, double spacing, int label, double angle, Vec2 offset) {
  const auto [row, col] = shape.cell_of(label);
  const double x = col * spacing;
  const double y = -row * spacing;
  return {std::cos(angle) * x - std::sin(angle) * y + offset.x,
          std::sin(angle) * x + std::cos(angle) * y + offset.y};
}

// The paper's triangle: no proper rotation maps it onto itself, so the right assignment is unique.
ShapeMatrix triangle() {
  return ShapeMatrix{3, 5, {-1, -1, 0, -1, -1, -1, 1, 2, 3, -1, 4, 5, 6, 7, 8}};
}

TEST(Assignment, SwappedAndLyingLabelsDoNotFoolIt) {
  const ShapeMatrix shape = triangle();
  const ShapeAssigner assigner(shape, 1.0, kHeading);
  // Robot i stands at the place of label (8 - i), turned 0.4 rad, far from the origin.
  std::vector<Vec2> robots;
  for (int i = 0; i < 9; ++i) robots.push_back(at(shape, 1.0, 8 - i, 0.4, {12.0, -3.0}));
  // Labels as the robots report them: 0 and 1 swapped, robot 4 lies (says 0, which robot 0 holds), robot 8
  // says nothing.
  std::vector<int> reported{7, 8, 6, 5, 0, 3, 2, 1, -1};
  const ShapeAssignment a = assigner.solve(robots, reported, true);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(a.label[static_cast<std::size_t>(i)], 8 - i) << "robot " << i;
  EXPECT_EQ(a.assigned, 9u);
  EXPECT_LT(a.error, 1e-9);
  EXPECT_TRUE(a.optimal);

  // Every label a lie (a permutation that keeps nobody in place): still found from the positions.
  std::vector<int> lies(9);
  std::iota(lies.begin(), lies.end(), 0);
  std::rotate(lies.begin(), lies.begin() + 4, lies.end());
  const ShapeAssignment b = assigner.solve(robots, lies, true);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(b.label[static_cast<std::size_t>(i)], 8 - i) << "robot " << i;
  EXPECT_LT(b.error, 1e-9);
}

TEST(Assignment, SparesAreLeftOut) {
  const ShapeMatrix shape = block3();
  const ShapeAssigner assigner(shape, 1.0, kHeading);
  std::vector<Vec2> robots;
  for (int l = 0; l < 9; ++l) robots.push_back(at(shape, 1.0, l, -1.1, {2.0, 2.0}));
  // Spares: one far away, one just outside the block (1.4 m from the nearest place), both claiming labels.
  robots.push_back({-20.0, 5.0});
  robots.push_back(at(shape, 1.0, 2, -1.1, {2.0, 2.0}));
  robots.back().x += 1.4;
  std::vector<int> reported{0, 1, 2, 3, 4, 5, 6, 7, 8, 4, 2};
  const ShapeAssignment a = assigner.solve(robots, reported, true);
  EXPECT_EQ(a.assigned, 9u);
  for (int l = 0; l < 9; ++l) EXPECT_EQ(a.label[static_cast<std::size_t>(l)], l);
  EXPECT_EQ(a.label[9], -1);
  EXPECT_EQ(a.label[10], -1);
  EXPECT_LT(a.error, 1e-9);
}

TEST(Assignment, FewerRobotsThanPlacesEachGetsOne) {
  const ShapeMatrix shape = block3();
  const ShapeAssigner assigner(shape, 1.0, kHeading);
  // Labels 4 and 7 died: 7 robots on the other places, reporting nothing.
  std::vector<Vec2> robots;
  std::vector<int> truth;
  for (int l = 0; l < 9; ++l) {
    if (l == 4 || l == 7) continue;
    robots.push_back(at(shape, 1.0, l, 2.0, {-1.0, 0.5}));
    truth.push_back(l);
  }
  // A guess from the heading alone is 2 rad off; the labels reported are a good guess.
  const ShapeAssignment a = assigner.solve(robots, truth, true);
  EXPECT_EQ(a.assigned, 7u);
  EXPECT_EQ(a.label, truth);
  EXPECT_LT(a.error, 1e-9);
}

TEST(Assignment, MirrorImageIsAnError) {
  const ShapeMatrix shape = ell();
  const ShapeAssigner assigner(shape, 1.0, kHeading);
  std::vector<Vec2> robots;
  for (int l = 0; l < 4; ++l) {
    Vec2 p = at(shape, 1.0, l, 0.0, {});
    p.x = -p.x;  // mirrored
    robots.push_back(p);
  }
  const ShapeAssignment a = assigner.solve(robots, {0, 1, 2, 3}, true);
  EXPECT_GT(a.error, 0.2);
}

// The joint optimum by brute force (as many robots as places): every assignment, each with its Kabsch fit.
double brute_force_error(const ShapeAssigner& assigner, const std::vector<Vec2>& robots) {
  std::vector<int> perm(assigner.places());
  std::iota(perm.begin(), perm.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    best = std::min(best, assigner.evaluate(robots, perm).error);
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

TEST(Assignment, NearFormedNoisyShapesReachTheJointOptimum) {
  const ShapeMatrix shape{2, 3, {0, 1, 2, -1, 3, 4}};
  const ShapeAssigner assigner(shape, 1.0, kHeading);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.08);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    const double a = angle(rng);
    std::vector<Vec2> robots;
    for (int l = 0; l < 5; ++l) {
      Vec2 p = at(shape, 1.0, l, a, {3.0, -2.0});
      robots.push_back({p.x + noise(rng), p.y + noise(rng)});
    }
    std::shuffle(robots.begin(), robots.end(), rng);
    const ShapeAssignment got = assigner.solve(robots, std::vector<int>(5, -1), true);
    EXPECT_NEAR(got.error, brute_force_error(assigner, robots), 1e-9) << "trial " << trial;
  }
}

// The radial bound (error_lower_bound) is a bound: never above the joint optimum, whatever the robots'
// layout: near formed, scattered, mirrored, at a spacing other than 1.
TEST(Assignment, TheRadialBoundIsNeverAboveTheBestError) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const ShapeMatrix& shape : {ShapeMatrix{2, 3, {0, 1, 2, -1, 3, 4}}, ell()}) {
    const double spacing = 0.7;
    const ShapeAssigner assigner(shape, spacing, kHeading);
    const int n = static_cast<int>(assigner.places());
    for (int trial = 0; trial < 60; ++trial) {
      const double a = angle(rng);
      const double sd = spacing * (trial % 3 == 0 ? 0.02 : trial % 3 == 1 ? 0.2 : 0.6);
      std::normal_distribution<double> noise(0.0, sd);
      std::vector<Vec2> robots;
      for (int l = 0; l < n; ++l) {
        Vec2 p = at(shape, spacing, l, a, {3.0, -2.0});
        if (trial % 4 == 3) p.x = 6.0 - p.x;  // mirrored
        robots.push_back({p.x + noise(rng), p.y + noise(rng)});
      }
      if (trial % 5 == 4) {
        for (Vec2& p : robots) p = {4.0 * unit(rng), 4.0 * unit(rng)};  // scattered
      }
      const double bound = assigner.error_lower_bound(robots);
      EXPECT_LE(bound, brute_force_error(assigner, robots) + 1e-9) << "trial " << trial;
    }
  }
}

// It is 0 unless there are as many robots as places, tight for robots standing in the shape, and well above
// the formation error (0.1 grid units) for 100 robots scattered over the 10 x 10 block's own square.
TEST(Assignment, TheRadialBoundTellsScatteredRobotsFromAShape) {
  ShapeMatrix block{10, 10, std::vector<int>(100)};
  std::iota(block.cells.begin(), block.cells.end(), 0);
  const ShapeAssigner assigner(block, 0.5, kHeading);
  std::mt19937 rng(3);
  std::vector<Vec2> robots;
  for (int l = 0; l < 100; ++l) robots.push_back(at(block, 0.5, l, 0.4, {7.0, 1.0}));
  std::shuffle(robots.begin(), robots.end(), rng);
  EXPECT_LT(assigner.error_lower_bound(robots), 1e-9);
  robots.pop_back();
  EXPECT_EQ(assigner.error_lower_bound(robots), 0.0);  // 99 robots: which 99 places is unknown
  std::uniform_real_distribution<double> across(-0.25, 4.75);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<Vec2> scattered(100);
    for (Vec2& p : scattered) p = {across(rng), -across(rng)};
    EXPECT_GT(assigner.error_lower_bound(scattered), 0.1) << "trial " << trial;
  }
}

TEST(Assignment, CertificateWithoutFullSolveKeepsTheGuessWhenItCannotProve) {
  const ShapeMatrix shape = block3();
  const ShapeAssigner assigner(shape, 1.0, kHeading);
  std::vector<Vec2> robots;
  for (int l = 0; l < 9; ++l) robots.push_back(at(shape, 1.0, l, 0.0, {}));
  // Two robots in one cell: no certificate; without a full solve the guess stands (an upper bound).
  robots[1] = {0.1, 0.0};
  std::vector<int> guess{0, 1, 2, 3, 4, 5, 6, 7, 8};
  const ShapeAssignment a = assigner.solve(robots, guess, false);
  EXPECT_FALSE(a.optimal);
  EXPECT_EQ(a.label, guess);
  const ShapeAssignment b = assigner.solve(robots, guess, true);
  EXPECT_TRUE(b.optimal);
  EXPECT_LE(b.error, a.error + 1e-12);
}

// The total cost of the columns `got` picks for each row; every column at most once.
double assignment_cost(const std::vector<double>& cost, std::size_t cols, const std::vector<int>& got) {
  std::vector<char> taken(cols, 0);
  double sum = 0.0;
  for (std::size_t r = 0; r < got.size(); ++r) {
    const auto c = static_cast<std::size_t>(got[r]);
    EXPECT_LT(c, cols);
    EXPECT_FALSE(taken[c]) << "column " << c << " taken twice";
    taken[c] = 1;
    sum += cost[r * cols + c];
  }
  return sum;
}

// Three kinds of matrices, so that the warm start (each row's cheapest column, when free) meets both
// distinct and shared cheapest columns: uniform costs; small integers (ties everywhere); and robots scattered
// about a few places (squared distances, several rows wanting one column).
TEST(Hungarian, MatchesBruteForceOnRectangularMatrices) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::uniform_int_distribution<int> small(0, 3);
  for (int trial = 0; trial < 120; ++trial) {
    const std::size_t rows = 1 + static_cast<std::size_t>(trial % 6);
    const std::size_t cols = rows + static_cast<std::size_t>(trial % 3);
    std::vector<double> cost(rows * cols);
    if (trial % 3 == 0) {
      for (double& c : cost) c = u(rng);
    } else if (trial % 3 == 1) {
      for (double& c : cost) c = small(rng);
    } else {
      std::vector<Vec2> places(cols), robots(rows);
      for (Vec2& q : places) q = Vec2{u(rng), u(rng)};
      for (Vec2& r : robots) {
        const Vec2& near = places[static_cast<std::size_t>(small(rng)) % cols];
        r = Vec2{near.x + 0.1 * u(rng), near.y};
      }
      for (std::size_t r = 0; r < rows; ++r) {
        for (std::size_t c = 0; c < cols; ++c) {
          const double dx = robots[r].x - places[c].x, dy = robots[r].y - places[c].y;
          cost[r * cols + c] = dx * dx + dy * dy;
        }
      }
    }
    const auto got = hungarian(cost, rows, cols);
    const double got_sum = assignment_cost(cost, cols, got);
    std::vector<int> cols_perm(cols);
    std::iota(cols_perm.begin(), cols_perm.end(), 0);
    double best = std::numeric_limits<double>::infinity();
    do {
      double s = 0.0;
      for (std::size_t r = 0; r < rows; ++r) s += cost[r * cols + static_cast<std::size_t>(cols_perm[r])];
      best = std::min(best, s);
    } while (std::next_permutation(cols_perm.begin(), cols_perm.end()));
    EXPECT_NEAR(got_sum, best, 1e-9) << rows << "x" << cols << ", trial " << trial;
  }
}

// Too large for brute force: an optimum's total does not depend on the order of the rows, so the same robots
// listed in another order must cost the same (a solve that stopped at a local optimum would not).
TEST(Hungarian, TheOptimumDoesNotDependOnTheRowOrder) {
  std::mt19937 rng(11);
  std::normal_distribution<double> off(0.0, 0.6);
  for (const std::size_t side : {6u, 12u}) {
    const std::size_t cols = side * side, rows = cols - side / 2;
    std::vector<Vec2> robots(rows);
    for (std::size_t r = 0; r < rows; ++r) {
      robots[r] = Vec2{static_cast<double>(r % side) + off(rng), static_cast<double>(r / side) + off(rng)};
    }
    std::vector<std::size_t> order(rows);
    std::iota(order.begin(), order.end(), 0);
    double first = -1.0;
    for (int shuffle = 0; shuffle < 4; ++shuffle) {
      std::shuffle(order.begin(), order.end(), rng);
      std::vector<double> cost(rows * cols);
      for (std::size_t r = 0; r < rows; ++r) {
        for (std::size_t c = 0; c < cols; ++c) {
          const double dx = robots[order[r]].x - static_cast<double>(c % side);
          const double dy = robots[order[r]].y - static_cast<double>(c / side);
          cost[r * cols + c] = dx * dx + dy * dy;
        }
      }
      const double sum = assignment_cost(cost, cols, hungarian(cost, rows, cols));
      if (first < 0.0) first = sum;
      EXPECT_NEAR(sum, first, 1e-9) << side << " x " << side << ", shuffle " << shuffle;
    }
  }
}

}  // namespace
}  // namespace swarmform::shape_metrics
