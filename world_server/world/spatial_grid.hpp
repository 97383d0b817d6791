// A uniform grid over the robots' positions, rebuilt once a tick (counting sort into cells, no allocation
// after the first ticks): who is near a point, in O(robots near it) instead of O(N). Used by the medium (who
// hears whom) and the ultrasonic sensors (which robots a ray may hit). The grid covers the bounding box of
// the positions, so robots that wander far (no walls) only make cells coarser, never break it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/types.hpp"

namespace swarmform::world {

class SpatialGrid {
 public:
  // Puts every position in its cell. `cell_size` is a wish (m): it grows when the positions are spread so
  // wide that the grid would have more than max(4096, 4N) cells.
  void build(const std::vector<Pose2D>& poses, double cell_size);

  // Calls fn(index) for every position within `radius` of (x, y) (a superset test is done by cells, then the
  // exact distance here). Indices come in cell order, and in increasing order within a cell.
  template <typename Fn>
  void for_each_near(double x, double y, double radius, Fn&& fn) const {
    for_each_near_offset(x, y, radius, [&](std::uint32_t i, double, double, double) { fn(i); });
  }

  // The same, calling fn(index, dx, dy, d2) with the offset of the position from (x, y) (dx = px - x,
  // dy = py - y, computed as written) and d2 = dx * dx + dy * dy, so callers need not read the pose again.
  //
  // Only the cells a circle of `radius` can reach are walked: row by row, the span of cells within the
  // circle's chord over that row (rows are contiguous in items_, so a span is one run of the arrays). The
  // cells skipped hold no position within `radius`, so the calls and their order are those of walking the
  // whole bounding square. Positions are read from xs_/ys_, copies in cell order (no indirection).
  template <typename Fn>
  void for_each_near_offset(double x, double y, double radius, Fn&& fn) const {
    if (items_.empty()) return;
    // Slack for the rounding of the strip bounds against the cell index computed by division: a superset
    // only costs a distance test.
    constexpr double kSlack = 1e-6;
    const int cy0 = cell_y(y - radius);
    const int cy1 = cell_y(y + radius);
    const double r2 = radius * radius;
    for (int cy = cy0; cy <= cy1; ++cy) {
      const double lo = y0_ + static_cast<double>(cy) * cell_;
      const double gap = std::max({0.0, lo - y, y - (lo + cell_)}) - kSlack;  // y to the row's strip
      const double half = gap > 0.0 ? std::sqrt(std::max(0.0, r2 - gap * gap)) + kSlack : radius;
      if (gap > radius) continue;
      const std::size_t row = static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_);
      const std::uint32_t k0 = start_[row + static_cast<std::size_t>(cell_x(x - half))];
      const std::uint32_t k1 = start_[row + static_cast<std::size_t>(cell_x(x + half)) + 1];
      // The distance test without a branch (about a third of the positions in the span fail it, at
      // random): the positions within `radius` are listed first, then handed over in the same order.
      for (std::uint32_t base = k0; base < k1; base += kBatch) {
        const std::uint32_t stop = std::min<std::uint32_t>(k1, base + kBatch);
        std::uint32_t within[kBatch];
        std::uint32_t count = 0;
        for (std::uint32_t k = base; k < stop; ++k) {
          const double dx = xs_[k] - x;
          const double dy = ys_[k] - y;
          within[count] = k;
          count += dx * dx + dy * dy <= r2 ? 1u : 0u;
        }
        for (std::uint32_t q = 0; q < count; ++q) {
          const std::uint32_t k = within[q];
          const double dx = xs_[k] - x;
          const double dy = ys_[k] - y;
          fn(items_[k], dx, dy, dx * dx + dy * dy);
        }
      }
    }
  }

  double cell_size() const { return cell_; }

 private:
  static constexpr std::uint32_t kBatch = 32;  // positions of a row's span tested before the calls

  int cell_x(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1);
  }
  int cell_y(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1);
  }

  double x0_ = 0.0, y0_ = 0.0, cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_;  // nx*ny+1 offsets into items_
  std::vector<std::uint32_t> items_;  // position indices, grouped by cell
  std::vector<std::uint32_t> cell_of_;
  std::vector<double> xs_, ys_;  // the positions of items_, in the same order
};

}  // namespace swarmform::world
