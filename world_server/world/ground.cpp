#include "world_server/world/ground.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "world_server/world/sensor_noise.hpp"

namespace swarmform::world {

Ground::Ground(Floor floor, Vec2 arena_centre, double width, double height, double noise_level,
               std::uint64_t seed)
    : floor_(std::move(floor)),
      centre_(arena_centre),
      width_(width),
      height_(height),
      noise_level_(noise_level),
      rng_(seed, kSaltGround) {}

GroundReading Ground::read(const Pose2D& pose) const {
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  GroundReading out;
  for (std::size_t k = 0; k < kGroundCount; ++k) {
    const Vec2 o = kGroundOffsets[k];
    out[k] =
        floor_grey(floor_, centre_, width_, height_, pose.x + c * o.x - s * o.y, pose.y + s * o.x + c * o.y);
  }
  return out;
}

void Ground::sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                       std::vector<GroundReading>& out) {
  // A few point lookups a robot: cheaper than the worker pool's hand-off.
  out.resize(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!alive[i]) continue;
    out[i] = read(poses[i]);
    if (noise_level_ > 0.0) add_uniform_noise(out[i], rng_, noise_level_);
  }
}

}  // namespace swarmform::world
