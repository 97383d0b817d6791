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
    if (poses_ == nullptr || poses_->empty()) return;
    const int cx0 = cell_x(x - radius);
    const int cx1 = cell_x(x + radius);
    const int cy0 = cell_y(y - radius);
    const int cy1 = cell_y(y + radius);
    const double r2 = radius * radius;
    for (int cy = cy0; cy <= cy1; ++cy) {
      for (int cx = cx0; cx <= cx1; ++cx) {
        const std::size_t cell = static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) + cx;
        for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
          const std::uint32_t i = items_[k];
          const double dx = (*poses_)[i].x - x;
          const double dy = (*poses_)[i].y - y;
          if (dx * dx + dy * dy <= r2) fn(i);
        }
      }
    }
  }

  double cell_size() const { return cell_; }

 private:
  int cell_x(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1);
  }
  int cell_y(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1);
  }

  const std::vector<Pose2D>* poses_ = nullptr;
  double x0_ = 0.0, y0_ = 0.0, cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_;  // nx*ny+1 offsets into items_
  std::vector<std::uint32_t> items_;  // position indices, grouped by cell
  std::vector<std::uint32_t> cell_of_;
};

}  // namespace swarmform::world
