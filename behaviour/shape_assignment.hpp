// Which live robot stands at which place of the shape, judged from the true positions alone: the best
// assignment of robots to places together with the best proper rigid fit (rotation + translation, no
// reflection, no scaling) of the shape's places onto them. Rectangular: with more robots than places the
// farthest ones are left out (spares); with fewer, every robot gets a place and the empty places are left
// out.
//
// The joint optimum (fit and assignment) is found by alternating the two from a starting guess (the previous
// assignment, or the labels the robots report: a guess only, the result is judged on the positions):
//   fit the places to the guessed pairs (2-D Kabsch) -> the optimal assignment for that fit -> refit -> ...
// until the assignment stops changing. The optimal assignment for a fit costs O(robots) when a certificate
// holds (below) and a Hungarian solve, O(k^2 K) for k = min(robots, places), K = max, when it does not.
// world_server/run/README.md has the reasons and the measured cost.
//
// The certificate: the places lie on a grid, so the place nearest to a robot is found by rounding its
// position in the shape's frame. Every robot's cost is at least its squared distance to its nearest place (a
// lower bound for a robot whose grid cell holds no place). If the robots taking their nearest places cover
// min(robots, places) distinct places and no left-out robot's lower bound is below the largest cost taken,
// no other assignment can cost less: that assignment is optimal for this fit.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "common/shape.hpp"
#include "common/types.hpp"

namespace swarmform::shape_metrics {

// Arena position of a shape-frame point p: R(angle) p + translation.
struct RigidFit {
  double angle = 0.0;  // rad
  Vec2 translation;    // m
  Vec2 apply(Vec2 p) const;
  Vec2 invert(Vec2 q) const;  // the shape-frame point that lands on q
};

struct ShapeAssignment {
  std::vector<int> label;  // per robot (index into the positions given): its place's label, -1 left out
  RigidFit fit;
  std::size_t assigned = 0;                                // robots with a place
  double error = std::numeric_limits<double>::infinity();  // RMS distance to the fitted places, grid units
  bool optimal = false;         // the assignment is proven optimal for `fit` (certificate or Hungarian)
  std::size_t full_solves = 0;  // Hungarian solves this call needed
};

class ShapeAssigner {
 public:
  // `heading`: the arena angle of the shape's "up" (the controller's shape_heading); with no usable guess,
  // the fit starts from the shape turned that way, centred on the robots.
  ShapeAssigner(const ShapeMatrix& shape, double grid_spacing, double heading);

  std::size_t places() const { return places_.size(); }
  Vec2 place(int label) const { return places_[static_cast<std::size_t>(label)]; }  // shape frame, m

  // The best assignment of `robots` (arena positions) to the places, starting from `guess` (a label per
  // robot, -1 none; invalid and repeated labels are ignored). `full_solve`: whether a Hungarian solve is
  // allowed when the certificate fails; if not, the result keeps the guess's assignment (optimal = false) and
  // its error is an upper bound of the best one's.
  ShapeAssignment solve(const std::vector<Vec2>& robots, const std::vector<int>& guess,
                        bool full_solve) const;

  // The place nearest to an arena point under `fit` (its label, -1 if the point's grid cell holds none) and
  // the distance to it (m).
  std::pair<int, double> nearest_place(Vec2 point, const RigidFit& fit) const;

  // The fit and error of a given assignment (no search).
  ShapeAssignment evaluate(const std::vector<Vec2>& robots, const std::vector<int>& labels) const;

  // A lower bound on the error (grid units) of every assignment of `robots` to the places under every proper
  // rigid fit, when there are exactly as many robots as places (else 0). O(n log n) and no solve: robots at
  // rest far from the shape are known not to stand in it without the Hungarian solves that would find their
  // best assignment (~0.5 s at 1024 robots, world_server/run/README.md).
  double error_lower_bound(const std::vector<Vec2>& robots) const;

 private:
  // Shape-frame place of a label: column along +x, row along -y, one grid spacing apart (common/shape.hpp).
  std::vector<Vec2> places_;
  std::vector<double> place_radii_;  // m: each place's distance from the places' centroid, ascending
  ShapeMatrix shape_;
  double spacing_;
  double heading_;

  RigidFit fit_pairs(const std::vector<Vec2>& robots, const std::vector<int>& labels) const;
  bool certified_assignment(const std::vector<Vec2>& robots, const RigidFit& fit,
                            std::vector<int>& out) const;
  void hungarian_assignment(const std::vector<Vec2>& robots, const RigidFit& fit,
                            std::vector<int>& out) const;
  std::vector<int> clean_guess(const std::vector<int>& guess) const;
  std::vector<double> candidate_angles(const std::vector<Vec2>& robots) const;
  ShapeAssignment refine(const std::vector<Vec2>& robots, RigidFit fit, std::vector<int> labels,
                         bool full_solve) const;
};

// Rectangular linear assignment: cost is rows x cols (row-major), rows <= cols. Returns the column of each
// row, minimising the total cost. O(rows^2 cols).
std::vector<int> hungarian(const std::vector<double>& cost, std::size_t rows, std::size_t cols);

}  // namespace swarmform::shape_metrics
