#include "world_server/world/lidar.hpp"

#include <algorithm>
#include <cmath>

#include "world_server/world/ray_fan.hpp"
#include "world_server/world/sensor_noise.hpp"

namespace swarmform::world {

Lidar::Lidar(const LidarSpec& spec, const std::vector<Obstacle>& statics, double noise_level,
             std::uint64_t seed)
    : spec_(spec), noise_level_(noise_level), rng_(seed, kSaltLidar) {
  set_statics(statics);
  const std::size_t n = spec_.rays;
  for (std::size_t k = 0; k < n; ++k) {
    const double a =
        n == 1 ? 0.0 : -spec_.fov / 2.0 + spec_.fov * static_cast<double>(k) / static_cast<double>(n - 1);
    angle_.push_back(a);
    cos_.push_back(std::cos(a));
    sin_.push_back(std::sin(a));
  }
}

void Lidar::read(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
                 LidarScan& out) const {
  const std::size_t n = angle_.size();
  // Per-thread scratch: the arena-frame directions and the nearest hits (no allocation once warm).
  thread_local std::vector<double> dx, dy, nearest;
  dx.resize(n);
  dy.resize(n);
  nearest.assign(n, kNoHit);
  const double c = std::cos(poses[self].theta), s = std::sin(poses[self].theta);
  for (std::size_t k = 0; k < n; ++k) {
    dx[k] = c * cos_[k] - s * sin_[k];
    dy[k] = s * cos_[k] + c * sin_[k];
  }
  const FanAngles fan{poses[self].theta + angle_.front(),
                      n > 1 ? spec_.fov / static_cast<double>(n - 1) : 0.0};
  cast_ring_rays(self, poses, grid, statics_, spec_.max_range, dx, dy, nearest, fan);
  out.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    out[k].angle = angle_[k];
    out[k].range = std::clamp(nearest[k], spec_.min_range, spec_.max_range);  // kNoHit: max_range
  }
}

void Lidar::sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                      const SpatialGrid& grid, std::vector<LidarScan>& out) {
  read_each(alive, out, [&](std::size_t i, LidarScan& scan) { read(i, poses, grid, scan); });
  if (noise_level_ <= 0.0) return;
  for (std::size_t i = 0; i < alive.size(); ++i) {
    if (!alive[i]) continue;
    for (LidarRay& ray : out[i]) {
      if (ray.range >= spec_.max_range) continue;  // saw nothing: no noise, as the ultrasonic sensors
      ray.range =
          std::clamp(ray.range + rng_.uniform(-noise_level_, noise_level_), spec_.min_range, spec_.max_range);
    }
  }
}

void Lidar::set_statics(const std::vector<Obstacle>& statics) {
  statics_.clear();
  for (const Obstacle& o : statics) statics_.push_back(make_static_shape(o));
}

}  // namespace swarmform::world
