#include "world_server/world/spatial_grid.hpp"

namespace swarmform::world {

void SpatialGrid::build(const std::vector<Pose2D>& poses, double cell_size) {
  const std::size_t n = poses.size();
  items_.clear();
  if (n == 0) return;
  double xmin = poses[0].x, xmax = poses[0].x, ymin = poses[0].y, ymax = poses[0].y;
  for (const Pose2D& p : poses) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  const double max_cells = std::max(4096.0, 4.0 * static_cast<double>(n));
  cell_ = std::max(cell_size, 1e-3);
  // Coarsen until the grid is small enough (rare: robots spread over a huge area).
  while (((xmax - xmin) / cell_ + 1.0) * ((ymax - ymin) / cell_ + 1.0) > max_cells) cell_ *= 2.0;
  x0_ = xmin;
  y0_ = ymin;
  nx_ = static_cast<int>(std::floor((xmax - xmin) / cell_)) + 1;
  ny_ = static_cast<int>(std::floor((ymax - ymin) / cell_)) + 1;
  const std::size_t cells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);

  // Counting sort: count per cell, prefix sums, then fill in index order (so each cell is sorted).
  start_.assign(cells + 1, 0);
  cell_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t cell =
        static_cast<std::size_t>(cell_y(poses[i].y)) * static_cast<std::size_t>(nx_) + cell_x(poses[i].x);
    cell_of_[i] = static_cast<std::uint32_t>(cell);
    ++start_[cell + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  items_.resize(n);
  // Fill using start_ as a cursor, then shift back.
  for (std::size_t i = 0; i < n; ++i) items_[start_[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  for (std::size_t c = cells; c > 0; --c) start_[c] = start_[c - 1];
  start_[0] = 0;
  xs_.resize(n);
  ys_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    xs_[k] = poses[items_[k]].x;
    ys_[k] = poses[items_[k]].y;
  }
}

}  // namespace swarmform::world
