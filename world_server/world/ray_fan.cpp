#include "world_server/world/ray_fan.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace swarmform::world {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// fn(k) for every ray k of n that may meet a body within `radius` of (ox, oy) (offset from the ray's
// centre). A ray leaves the centre's half-line at the ring, so it meets the body only if the half-line does:
// its angle is within asin(radius / distance) of the body's bearing.
template <class Fn>
void rays_towards(double ox, double oy, double radius, FanAngles fan, std::size_t n, Fn&& fn) {
  const double d2 = ox * ox + oy * oy;
  if (n < kFanCullRays || fan.step <= 0.0 || d2 <= radius * radius) {
    for (std::size_t k = 0; k < n; ++k) fn(k);
    return;
  }
  const double half = std::asin(radius / std::sqrt(d2)) + 1e-9;  // the margin keeps a grazing ray
  double rel = std::atan2(oy, ox) - fan.first;
  rel -= kTwoPi * std::floor(rel / kTwoPi);  // [0, 2 pi); its window may wrap past either end
  const double last = static_cast<double>(n - 1);
  for (const double c : {rel - kTwoPi, rel, rel + kTwoPi}) {
    const double lo = std::max(std::ceil((c - half) / fan.step), 0.0);
    const double hi = std::min(std::floor((c + half) / fan.step), last);
    for (double k = lo; k <= hi; k += 1.0) fn(static_cast<std::size_t>(k));
  }
}

}  // namespace

void cast_ring_rays(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
                    const std::vector<StaticShape>& statics, double range, std::span<const double> dx,
                    std::span<const double> dy, std::span<double> nearest, FanAngles fan) {
  const Pose2D& me = poses[self];
  const std::size_t n = nearest.size();
  auto cast = [&](std::size_t k, auto&& hit) {
    nearest[k] =
        std::min(nearest[k], hit(me.x + kRobotRadius * dx[k], me.y + kRobotRadius * dy[k], dx[k], dy[k]));
  };
  // A robot whose centre is farther than this from the reading robot's centre cannot be hit by any ray.
  const double robot_reach = kRobotRadius + range + kRobotRadius;
  grid.for_each_near(me.x, me.y, robot_reach, [&](std::uint32_t j) {
    if (j == self) return;
    const Pose2D& other = poses[j];
    rays_towards(other.x - me.x, other.y - me.y, kRobotRadius, fan, n, [&](std::size_t k) {
      cast(k, [&](double ox, double oy, double ux, double uy) {
        return ray_circle(ox, oy, ux, uy, other.x, other.y, kRobotRadius);
      });
    });
  });
  for (const StaticShape& st : statics) {
    const double cx = me.x - st.cx, cy = me.y - st.cy, far = kRobotRadius + range + st.bound + 1e-6;
    if (cx * cx + cy * cy > far * far) continue;
    rays_towards(-cx, -cy, st.bound, fan, n, [&](std::size_t k) {
      cast(k, [&](double ox, double oy, double ux, double uy) { return ray_static(ox, oy, ux, uy, st); });
    });
  }
}

}  // namespace swarmform::world
