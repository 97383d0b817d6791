// The shape error of robots that hold labels (docs/recording-format.md): RMS distance of each robot from its
// label's place after the best rigid fit (rotation and translation, no scaling) of the label grid onto the
// robots, in grid units (divided by the grid spacing). Part of the shape measurement library a shape-forming
// behaviour's experiment may use (shape_metrics.hpp).
#pragma once

#include <optional>
#include <vector>

#include "common/shape.hpp"
#include "common/types.hpp"

namespace swarmform::shape_metrics {

// A robot's position with the label it holds.
struct LabelledPosition {
  int label = -1;
  Vec2 position;  // m, arena frame
};

// Labels held by no live robot are left out; nullopt for fewer than 2 robots.
std::optional<double> shape_error(const ShapeMatrix& shape, double grid_spacing,
                                  const std::vector<LabelledPosition>& robots);

}  // namespace swarmform::shape_metrics
