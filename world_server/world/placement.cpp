#include "world_server/world/placement.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <unordered_map>

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

// Placed robots bucketed by cell, for the separation test. The cells are kMinSeparation wide, so a test looks
// at the 3x3 cells around a point and each holds a handful of robots, however the robots are spread. (Cells
// sized from the region's area, as they were, assume robots spread evenly over it; but each robot is placed
// near an earlier one, so in a large region they crowd a few cells, and placing 100000 robots in a 10 km
// region scanned thousands of robots per attempt: minutes for a scenario that loads in a second now.) Cells
// are hashed, not an array, since a 10 km region has 6e8 of them.
class PlacedGrid {
 public:
  explicit PlacedGrid(const PlacementRegion& r)
      : x0_(r.centre.x - r.width / 2.0), y0_(r.centre.y - r.height / 2.0) {}
  bool clear(double x, double y, const std::vector<Pose2D>& placed) const {
    const std::int64_t cx = cell_of(x - x0_), cy = cell_of(y - y0_);
    for (std::int64_t j = cy - 1; j <= cy + 1; ++j) {
      for (std::int64_t i = cx - 1; i <= cx + 1; ++i) {
        const auto it = cells_.find(key(i, j));
        if (it == cells_.end()) continue;
        for (std::size_t k : it->second) {
          if (std::hypot(placed[k].x - x, placed[k].y - y) < kMinSeparation) return false;
        }
      }
    }
    return true;
  }
  void add(double x, double y, std::size_t k) {
    cells_[key(cell_of(x - x0_), cell_of(y - y0_))].push_back(k);
  }

 private:
  // From the region's corner: the points are in the region, at most kMaxLength across, so an index fits 32
  // bits.
  static std::int64_t cell_of(double v) { return static_cast<std::int64_t>(std::floor(v / kMinSeparation)); }
  static std::uint64_t key(std::int64_t i, std::int64_t j) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
  }
  double x0_, y0_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

}  // namespace

PlacementRegion default_region(std::size_t n) {
  const double side = std::max(1.5, std::sqrt(0.6 * static_cast<double>(n)));
  return PlacementRegion{Vec2{0.0, 0.0}, side, side};
}

std::optional<std::vector<Pose2D>> place_randomly(std::size_t n, const PlacementRegion& region,
                                                  const Scenario& scenario, std::uint64_t seed,
                                                  const std::vector<Pose2D>& others, std::uint64_t stream) {
  std::vector<StaticShape> statics;
  for (const Obstacle& o : present_statics(scenario, scenario.obstacles))
    statics.push_back(make_static_shape(o));
  // Stream 0 is the one a scenario without groups has always drawn from (its placements, and so every golden
  // hash, unchanged); each later group draws from its own.
  Rng rng(seed, kSaltPlacement + stream);
  const double link = kLinkFraction * scenario.comm_range;
  const double x_lo = region.centre.x - region.width / 2.0, x_hi = region.centre.x + region.width / 2.0;
  const double y_lo = region.centre.y - region.height / 2.0, y_hi = region.centre.y + region.height / 2.0;
  const double body_clear = kRobotRadius + kObstacleClearance;

  std::vector<Pose2D> poses;
  poses.reserve(n);
  // Every placed robot (the other groups' first, then these), for the separation test: a group's robots keep
  // clear of those placed before them, wherever their regions lie.
  std::vector<Pose2D> all = others;
  all.reserve(others.size() + n);
  PlacedGrid grid(region);
  for (std::size_t j = 0; j < others.size(); ++j) grid.add(others[j].x, others[j].y, j);
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
      if (!grid.clear(x, y, all)) continue;
      const double theta = wrap_angle(rng.uniform(-std::numbers::pi, std::numbers::pi));
      poses.push_back(Pose2D{x, y, theta});
      all.push_back(poses.back());
      grid.add(x, y, all.size() - 1);
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
  const auto obstacles = present_statics(scenario, scenario.obstacles);
  for (const Obstacle& o : obstacles) {
    if (point_clearance(p.x, p.y, make_static_shape(o)) < kRobotRadius) {
      return "robot " + std::to_string(k) + " overlaps " +
             (o.name.empty() ? "an obstacle" : "'" + o.name + "'");
    }
  }
  return {};
}

}  // namespace swarmform::world
