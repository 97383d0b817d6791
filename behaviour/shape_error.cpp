// The shape error (docs/recording-format.md): the label grid is fitted onto the robots that hold its labels
// by the best proper rigid motion (rotation + translation; no scaling, no reflection), and the RMS of what is
// left over is given in grid units.
//
// The fit is the Kabsch/Umeyama solution, which in the plane has a closed form: with both point sets centred
// (p_i the grid places, q_i the robots), sum_i |R p_i - q_i|^2 is least for the rotation angle
//   theta = atan2( sum_i p_i x q_i , sum_i p_i . q_i )
// (maximising sum_i q_i . R p_i = cos(theta) S_dot + sin(theta) S_cross). Only proper rotations are searched,
// so a mirrored formation is measured as the error it is, not fitted away.
#include "behaviour/shape_error.hpp"

#include <cmath>

namespace swarmform::shape_metrics {

namespace {

// Place of each label on the grid (m): column along +x, row along -y (common/shape.hpp). Index: label.
std::vector<std::optional<Vec2>> label_places(const ShapeMatrix& shape, double grid_spacing) {
  std::vector<std::optional<Vec2>> places;
  for (int row = 0; row < shape.rows; ++row) {
    for (int col = 0; col < shape.cols; ++col) {
      const int label = shape.at(row, col);
      if (label < 0) continue;
      if (static_cast<std::size_t>(label) >= places.size())
        places.resize(static_cast<std::size_t>(label) + 1);
      places[static_cast<std::size_t>(label)] = Vec2{col * grid_spacing, -row * grid_spacing};
    }
  }
  return places;
}

}  // namespace

std::optional<double> shape_error(const ShapeMatrix& shape, double grid_spacing,
                                  const std::vector<LabelledPosition>& robots) {
  if (grid_spacing <= 0.0) return std::nullopt;
  const auto places = label_places(shape, grid_spacing);

  // Pairs (grid place, robot position). A label not in the shape is skipped; a label held by two robots (a
  // conflict not yet resolved) counts twice, as it stands in the arena.
  std::vector<Vec2> grid;
  std::vector<Vec2> arena;
  grid.reserve(robots.size());
  arena.reserve(robots.size());
  for (const auto& r : robots) {
    if (r.label < 0 || static_cast<std::size_t>(r.label) >= places.size()) continue;
    const auto& place = places[static_cast<std::size_t>(r.label)];
    if (!place) continue;
    grid.push_back(*place);
    arena.push_back(r.position);
  }
  if (grid.size() < 2) return std::nullopt;

  const double n = static_cast<double>(grid.size());
  Vec2 grid_mean;
  Vec2 arena_mean;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    grid_mean = {grid_mean.x + grid[i].x, grid_mean.y + grid[i].y};
    arena_mean = {arena_mean.x + arena[i].x, arena_mean.y + arena[i].y};
  }
  grid_mean = {grid_mean.x / n, grid_mean.y / n};
  arena_mean = {arena_mean.x / n, arena_mean.y / n};

  double s_dot = 0.0;
  double s_cross = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double px = grid[i].x - grid_mean.x, py = grid[i].y - grid_mean.y;
    const double qx = arena[i].x - arena_mean.x, qy = arena[i].y - arena_mean.y;
    s_dot += px * qx + py * qy;
    s_cross += px * qy - py * qx;
  }
  const double angle = std::atan2(s_cross, s_dot);
  const double c = std::cos(angle);
  const double s = std::sin(angle);

  // The residual is summed explicitly (not from the closed-form minimum) so that a perfect fit gives ~1e-16,
  // not the square root of a cancellation error.
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double px = grid[i].x - grid_mean.x, py = grid[i].y - grid_mean.y;
    const double dx = c * px - s * py + arena_mean.x - arena[i].x;
    const double dy = s * px + c * py + arena_mean.y - arena[i].y;
    sum_sq += dx * dx + dy * dy;
  }
  return std::sqrt(sum_sq / n) / grid_spacing;
}

}  // namespace swarmform::shape_metrics
