#include "world_server/world/proximity.hpp"

#include <algorithm>
#include <cmath>

#include "world_server/world/ray_fan.hpp"
#include "world_server/world/sensor_noise.hpp"

namespace swarmform::world {

double proximity_value(double d) {
  if (d < kProximitySaturation) return 1.0;
  if (d > kProximityRange) return 0.0;  // kNoHit too
  return std::clamp(4.14 * std::exp(-33.0 * d) - 0.085, 0.0, 1.0);
}

Proximity::Proximity(const std::vector<Obstacle>& statics, double noise_level, std::uint64_t seed)
    : noise_level_(noise_level), rng_(seed, kSaltProximity) {
  set_statics(statics);
}

ProximityReading Proximity::read(std::size_t self, const std::vector<Pose2D>& poses,
                                 const SpatialGrid& grid) const {
  const Pose2D& me = poses[self];
  std::array<double, kProximityCount> nearest;
  nearest.fill(kNoHit);
  std::array<double, kProximityCount> dx, dy;  // each sensor's direction, arena frame
  for (std::size_t k = 0; k < kProximityCount; ++k) {
    const double a = me.theta + kProximityAngles[k];
    dx[k] = std::cos(a);
    dy[k] = std::sin(a);
  }
  cast_ring_rays(self, poses, grid, statics_, kProximityRange, dx, dy, nearest);
  ProximityReading out;
  for (std::size_t k = 0; k < kProximityCount; ++k) out[k] = proximity_value(nearest[k]);
  return out;
}

void Proximity::sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                          const SpatialGrid& grid, std::vector<ProximityReading>& out) {
  // Every vector is one per robot: poses.size() == alive.size().
  read_all(
      alive, out, [&](std::size_t i) { return read(i, poses, grid); }, rng_, noise_level_);
}

void Proximity::set_statics(const std::vector<Obstacle>& statics) {
  statics_.clear();
  for (const Obstacle& o : statics) statics_.push_back(make_static_shape(o));
}

}  // namespace swarmform::world
