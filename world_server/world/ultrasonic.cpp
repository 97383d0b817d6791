#include "world_server/world/ultrasonic.hpp"

#include <algorithm>
#include <cmath>

namespace swarmform::world {
namespace {

// A ray from the centre must travel this far to see something at the maximum range from the surface.
constexpr double kReach = kUltrasonicMaxRange + kRobotRadius;

}  // namespace

Ultrasonic::Ultrasonic(const std::vector<Obstacle>& statics, double noise_sd, std::uint64_t seed)
    : noise_sd_(noise_sd), rng_(seed, kSaltUltrasonic) {
  for (const Obstacle& o : statics) statics_.push_back(make_static_shape(o));
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    for (int r = 0; r < kRaysPerSensor; ++r) {
      const double f = kRaysPerSensor == 1 ? 0.0 : -1.0 + 2.0 * r / (kRaysPerSensor - 1);
      ray_offsets_[s * kRaysPerSensor + static_cast<std::size_t>(r)] =
          kUltrasonicAngles[s] + f * kConeHalfAngle;
    }
  }
}

UltrasonicReading Ultrasonic::read(std::size_t self, const std::vector<Pose2D>& poses,
                                   const SpatialGrid& grid) const {
  const Pose2D& me = poses[self];
  // Robots whose body can be within reach: centre within kReach + one radius.
  candidates_.clear();
  grid.for_each_near(me.x, me.y, kReach + kRobotRadius, [&](std::uint32_t j) {
    if (j != self) candidates_.push_back(j);
  });

  UltrasonicReading out;
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    double nearest = kNoHit;
    for (int r = 0; r < kRaysPerSensor; ++r) {
      const double a = me.theta + ray_offsets_[s * kRaysPerSensor + static_cast<std::size_t>(r)];
      const double dx = std::cos(a);
      const double dy = std::sin(a);
      for (std::uint32_t j : candidates_) {
        nearest = std::min(nearest, ray_circle(me.x, me.y, dx, dy, poses[j].x, poses[j].y, kRobotRadius));
      }
      for (const StaticShape& st : statics_) {
        // Skip shapes whose bounding circle is beyond reach.
        const double cx = st.cx - me.x, cy = st.cy - me.y;
        const double reach = kReach + st.bound;
        if (cx * cx + cy * cy > reach * reach) continue;
        nearest = std::min(nearest, ray_static(me.x, me.y, dx, dy, st));
      }
    }
    const double surface = nearest - kRobotRadius;
    out[s] = surface > kUltrasonicMaxRange ? kUltrasonicMaxRange
                                           : std::clamp(surface, kUltrasonicMinRange, kUltrasonicMaxRange);
  }
  return out;
}

void Ultrasonic::sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                           const SpatialGrid& grid, std::vector<UltrasonicReading>& out) {
  out.resize(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!alive[i]) continue;
    out[i] = read(i, poses, grid);
    if (noise_sd_ <= 0.0) continue;
    for (double& v : out[i]) {
      if (v >= kUltrasonicMaxRange) continue;  // "nothing seen" stays exact
      v = std::clamp(v + rng_.gaussian(noise_sd_), kUltrasonicMinRange, kUltrasonicMaxRange);
    }
  }
}

}  // namespace swarmform::world
