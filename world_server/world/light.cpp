#include "world_server/world/light.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "world_server/world/sensor_noise.hpp"

namespace swarmform::world {
namespace {

constexpr double kMaxLightDistance = 2.5;  // ARGoS ComputeReading: nothing past this (distance / intensity)

// The fraction along a->b (2-D) where the segment enters the circle (c, r); > 1 or kNoHit when it does not.
double entry_circle(double ax, double ay, double dx, double dy, double len, double cx, double cy, double r) {
  return ray_circle(ax, ay, dx / len, dy / len, cx, cy, r) / len;
}

}  // namespace

LightSensors::LightSensors(const std::vector<LightSource>& lights, const std::vector<Obstacle>& statics,
                           double noise_level, std::uint64_t seed)
    : lights_(lights), noise_level_(noise_level), rng_(seed, kSaltLight) {
  set_statics(statics);
}

bool LightSensors::hidden(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
                          const LightSource& l) const {
  const Pose2D& me = poses[self];
  const double dx = l.position.x - me.x, dy = l.position.y - me.y;
  const double len = std::hypot(dx, dy);
  if (len <= 0.0) return false;  // right under the light
  // The ray rises from the floor (0 at the robot) to l.height at the light: a prism hides the light when the
  // ray enters it no higher than its top (it only rises from there).
  auto below = [&](double f, double top) { return f <= 1.0 && f * l.height <= top; };
  for (const StaticShape& st : statics_) {
    const double f = ray_static(me.x, me.y, dx / len, dy / len, st) / len;
    if (below(f, kStaticHeight)) return true;
  }
  // Robots near the segment: small grid queries at points kProbeStep apart along it, each wide enough that
  // every body the segment crosses is within one (its centre lies within R of a point of the segment, which
  // lies within half a step of a probe). One query round the midpoint would hold every robot within half the
  // segment's length: O(N) a light at large N. A robot met by two probes is tested twice (the same answer).
  constexpr double kProbeStep = 0.5;  // m
  const int probes = static_cast<int>(std::ceil(len / kProbeStep));
  bool blocked = false;
  for (int k = 0; k <= probes && !blocked; ++k) {
    const double f = std::min(1.0, k * kProbeStep / len);
    grid.for_each_near(
        me.x + f * dx, me.y + f * dy, kProbeStep / 2.0 + kRobotRadius + 1e-9, [&](std::uint32_t j) {
          if (blocked || j == self) return;
          const double entry = entry_circle(me.x, me.y, dx, dy, len, poses[j].x, poses[j].y, kRobotRadius);
          if (below(entry, kRobotHeight)) blocked = true;
        });
  }
  return blocked;
}

LightReading LightSensors::read(std::size_t self, const std::vector<Pose2D>& poses,
                                const SpatialGrid& grid) const {
  LightReading out{};
  const Pose2D& me = poses[self];
  for (const LightSource& l : lights_) {
    const double dx = l.position.x - me.x, dy = l.position.y - me.y;
    const double d = std::sqrt(dx * dx + dy * dy + l.height * l.height) / l.intensity;
    if (d > kMaxLightDistance) continue;
    if (hidden(self, poses, grid, l)) continue;
    const double value = std::exp(-2.0 * d);
    const double bearing = wrap_angle(std::atan2(dy, dx) - me.theta);
    for (std::size_t k = 0; k < kLightCount; ++k) {
      const double a = std::abs(wrap_angle(bearing - kProximityAngles[k]));
      if (a > std::numbers::pi / 2.0) continue;
      out[k] += value * (1.0 - 2.0 * a / std::numbers::pi);
    }
  }
  for (double& v : out) v = std::min(v, 1.0);
  return out;
}

void LightSensors::sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                             const SpatialGrid& grid, std::vector<LightReading>& out) {
  // Every vector is one per robot: poses.size() == alive.size().
  read_all(
      alive, out, [&](std::size_t i) { return read(i, poses, grid); }, rng_, noise_level_);
}

void LightSensors::set_statics(const std::vector<Obstacle>& statics) {
  statics_.clear();
  for (const Obstacle& o : statics) statics_.push_back(make_static_shape(o));
}

}  // namespace swarmform::world
