#include "world_server/world/placement.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "world_server/world/geometry.hpp"
#include "world_server/world/rng.hpp"

namespace swarmform::world {
namespace {

// Attempts per robot before the region is declared too small.
constexpr int kAttempts = 4000;

bool inside_arena(double x, double y, const Scenario& s, double margin) {
  if (!s.walls) return true;
  return std::abs(x - s.arena_centre.x) <= s.arena_width / 2.0 - margin &&
         std::abs(y - s.arena_centre.y) <= s.arena_height / 2.0 - margin;
}

double min_clearance(double x, double y, const std::vector<StaticShape>& statics) {
  double c = kNoHit;
  for (const StaticShape& s : statics) c = std::min(c, point_clearance(x, y, s));
  return c;
}

// Placed robots bucketed by cell, for the separation test.
class PlacedGrid {
 public:
  PlacedGrid(const PlacementRegion& r, std::size_t n) {
    const double area = std::max(r.width * r.height, 1e-6);
    cell_ =
        std::max(kMinSeparation, std::sqrt(area / (4.0 * static_cast<double>(std::max<std::size_t>(n, 1)))));
    x0_ = r.centre.x - r.width / 2.0;
    y0_ = r.centre.y - r.height / 2.0;
    nx_ = static_cast<int>(r.width / cell_) + 1;
    ny_ = static_cast<int>(r.height / cell_) + 1;
    cells_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  }
  bool clear(double x, double y, const std::vector<Pose2D>& placed) const {
    const int cx = cx_of(x), cy = cy_of(y);
    for (int j = std::max(cy - 1, 0); j <= std::min(cy + 1, ny_ - 1); ++j) {
      for (int i = std::max(cx - 1, 0); i <= std::min(cx + 1, nx_ - 1); ++i) {
        for (std::size_t k : cells_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + i]) {
          if (std::hypot(placed[k].x - x, placed[k].y - y) < kMinSeparation) return false;
        }
      }
    }
    return true;
  }
  void add(double x, double y, std::size_t k) {
    cells_[static_cast<std::size_t>(cy_of(y)) * static_cast<std::size_t>(nx_) + cx_of(x)].push_back(k);
  }

 private:
  int cx_of(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1);
  }
  int cy_of(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1);
  }
  double cell_ = 1.0, x0_ = 0.0, y0_ = 0.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<std::size_t>> cells_;
};

}  // namespace

PlacementRegion default_region(std::size_t n) {
  const double side = std::max(1.5, std::sqrt(0.6 * static_cast<double>(n)));
  return PlacementRegion{Vec2{0.0, 0.0}, side, side};
}

std::optional<std::vector<Pose2D>> place_randomly(std::size_t n, const PlacementRegion& region,
                                                  const Scenario& scenario, std::uint64_t seed) {
  std::vector<StaticShape> statics;
  for (const Obstacle& o : static_obstacles(scenario)) statics.push_back(make_static_shape(o));
  Rng rng(seed, kSaltPlacement);
  const double link = kLinkFraction * scenario.comm_range;
  const double x_lo = region.centre.x - region.width / 2.0, x_hi = region.centre.x + region.width / 2.0;
  const double y_lo = region.centre.y - region.height / 2.0, y_hi = region.centre.y + region.height / 2.0;
  const double body_clear = kRobotRadius + kObstacleClearance;

  std::vector<Pose2D> poses;
  poses.reserve(n);
  PlacedGrid grid(region, n);
  for (std::size_t k = 0; k < n; ++k) {
    bool placed = false;
    for (int attempt = 0; attempt < kAttempts && !placed; ++attempt) {
      double x, y;
      if (k == 0) {
        x = rng.uniform(x_lo, x_hi);
        y = rng.uniform(y_lo, y_hi);
      } else {
        // Near a uniformly chosen earlier robot: uniform in the disc of radius `link` around it.
        const std::size_t j =
            std::min(static_cast<std::size_t>(rng.uniform() * static_cast<double>(k)), k - 1);
        const double a = rng.uniform(-std::numbers::pi, std::numbers::pi);
        const double r = link * std::sqrt(rng.uniform());
        x = poses[j].x + r * std::cos(a);
        y = poses[j].y + r * std::sin(a);
        if (x < x_lo || x > x_hi || y < y_lo || y > y_hi) continue;
      }
      if (!inside_arena(x, y, scenario, body_clear)) continue;
      if (min_clearance(x, y, statics) < body_clear) continue;
      if (!grid.clear(x, y, poses)) continue;
      const double theta = wrap_angle(rng.uniform(-std::numbers::pi, std::numbers::pi));
      poses.push_back(Pose2D{x, y, theta});
      grid.add(x, y, k);
      placed = true;
    }
    if (!placed) return std::nullopt;
  }
  return poses;
}

std::string check_listed_pose(const std::vector<Pose2D>& poses, std::size_t k, const Scenario& scenario) {
  const Pose2D& p = poses[k];
  std::ostringstream why;
  for (std::size_t j = 0; j < k; ++j) {
    const double d = std::hypot(poses[j].x - p.x, poses[j].y - p.y);
    if (d < 2.0 * kRobotRadius) {
      why << "robot " << k << " overlaps robot " << j << " (centres " << d << " m apart, bodies need "
          << 2.0 * kRobotRadius << ")";
      return why.str();
    }
  }
  if (!inside_arena(p.x, p.y, scenario, 0.0)) return "robot " + std::to_string(k) + " is outside the arena";
  const auto obstacles = static_obstacles(scenario);
  for (const Obstacle& o : obstacles) {
    if (point_clearance(p.x, p.y, make_static_shape(o)) < kRobotRadius) {
      return "robot " + std::to_string(k) + " overlaps " +
             (o.name.empty() ? "an obstacle" : "'" + o.name + "'");
    }
  }
  return {};
}

}  // namespace swarmform::world
