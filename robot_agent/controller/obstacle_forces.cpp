#include "robot_agent/controller/obstacle_forces.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

SensorMask mask_neighbour_directions(const UltrasonicArray& readings,
                                     const std::vector<NeighbourBearing>& neighbours, double mask_angle,
                                     double slack) {
  SensorMask mask{};
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    for (const auto& n : neighbours) {
      const double angle = n.uncertainty > 0.0
                               ? mask_angle + std::atan2(n.uncertainty, std::max(n.range, kRobotRadius))
                               : mask_angle;
      if (neighbour_explains_echo(n.bearing, kUltrasonicAngles[s], readings[s], n.range, angle,
                                  slack + n.uncertainty)) {
        mask[s] = true;
        break;
      }
    }
  }
  return mask;
}

ObstacleSense sense_obstacles(const UltrasonicArray& readings, const SensorMask& mask, double theta,
                              const ObstacleParams& params) {
  ObstacleSense out;
  Vec2 body_force;
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    if (mask[s]) continue;
    const double r = std::max(readings[s], kUltrasonicMinRange);
    if (r < out.nearest) {
      out.nearest = r;
      out.nearest_bearing = kUltrasonicAngles[s];
    }
    if (r < params.fusion_range) ++out.sensors_seeing;
    if (r < params.obstacle_range) {
      // eq. (6), pointing away from the echo, zero at the obstacle range.
      const double magnitude = params.m * (1.0 / r - 1.0 / params.obstacle_range);
      body_force = vsub(body_force, vpolar(magnitude, kUltrasonicAngles[s]));
    }
  }
  out.force = vrotate(body_force, theta);

  if (out.sensors_seeing == 0) return out;
  // Size discrimination: the run of adjacent seeing sensors that holds the nearest echo.
  std::size_t nearest_s = 0;
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    if (!mask[s] && kUltrasonicAngles[s] == out.nearest_bearing) nearest_s = s;
  }
  auto sees = [&](std::size_t s) { return !mask[s] && readings[s] < params.fusion_range; };
  std::size_t lo = nearest_s, hi = nearest_s;
  while (lo > 0 && sees(lo - 1)) --lo;
  while (hi + 1 < kUltrasonicCount && sees(hi + 1)) ++hi;
  double span = 0.0;
  for (std::size_t a = lo; a <= hi; ++a) {
    for (std::size_t b = a + 1; b <= hi; ++b) {
      const Vec2 pa = vpolar(readings[a], kUltrasonicAngles[a]);
      const Vec2 pb = vpolar(readings[b], kUltrasonicAngles[b]);
      span = std::max(span, vnorm(vsub(pa, pb)));
    }
  }
  // One sensor: small. Three or more adjacent: large (a post never fills three cones 45 degrees apart).
  // Two: small only if their echoes are nearly as far (the near side of something round; a plane seen by
  // two sensors gives readings in the ratio of the cosines, about 1.4 head-on) and close together.
  const std::size_t run = hi - lo + 1;
  out.run_length = static_cast<int>(run);
  bool small = run == 1;
  if (run == 2) {
    const double ratio =
        std::max(readings[lo], readings[hi]) / std::max(std::min(readings[lo], readings[hi]), 1e-9);
    small = ratio < kRoundRatio && span < params.small_obstacle_width;
  }
  out.size = small ? ObstacleSize::Small : ObstacleSize::Large;
  return out;
}

void EchoMemory::add(const UltrasonicArray& readings, const SensorMask& mask, const Pose2D& pose, Tick tick,
                     double max_range) {
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    if (mask[s] || readings[s] >= max_range) continue;
    const double from_centre = std::max(readings[s], kUltrasonicMinRange) + kRobotRadius;
    echoes_.push_back({vadd({pose.x, pose.y}, vpolar(from_centre, pose.theta + kUltrasonicAngles[s])), tick});
  }
}

Vec2 EchoMemory::force(Vec2 position, Tick tick, double m, double obstacle_range, Tick max_age) {
  std::erase_if(echoes_, [&](const Echo& e) { return e.tick + max_age < tick; });
  constexpr int kSectors = 8;
  std::array<double, kSectors> nearest;
  nearest.fill(obstacle_range);
  std::array<Vec2, kSectors> direction{};
  for (const auto& e : echoes_) {
    const Vec2 rel = vsub(e.point, position);
    const double r = std::max(vnorm(rel) - kRobotRadius, kUltrasonicMinRange);
    if (r >= obstacle_range) continue;
    const double a = std::atan2(rel.y, rel.x);
    const int k =
        static_cast<int>(std::floor((a + std::numbers::pi) / (2 * std::numbers::pi) * kSectors)) % kSectors;
    if (r < nearest[static_cast<std::size_t>(k)]) {
      nearest[static_cast<std::size_t>(k)] = r;
      direction[static_cast<std::size_t>(k)] = vpolar(1.0, a);
    }
  }
  Vec2 f;
  for (std::size_t k = 0; k < kSectors; ++k) {
    if (nearest[k] >= obstacle_range) continue;
    f = vsub(f, vscale(direction[k], m * (1.0 / nearest[k] - 1.0 / obstacle_range)));  // eq. (6)
  }
  return f;
}

std::vector<Vec2> EchoMemory::points(Tick tick, Tick max_age) {
  std::erase_if(echoes_, [&](const Echo& e) { return e.tick + max_age < tick; });
  std::vector<Vec2> out;
  out.reserve(echoes_.size());
  for (const auto& e : echoes_) out.push_back(e.point);
  return out;
}

std::optional<Vec2> EchoMemory::nearest(Vec2 position, Tick tick, double within, Tick max_age) {
  std::erase_if(echoes_, [&](const Echo& e) { return e.tick + max_age < tick; });
  std::optional<Vec2> best;
  double best_r = within;
  for (const auto& e : echoes_) {
    const double r = vnorm(vsub(e.point, position));
    if (r < best_r) {
      best_r = r;
      best = e.point;
    }
  }
  return best;
}

std::optional<Vec2> EchoMemory::surface(Vec2 position, Tick tick, double within, Tick max_age) {
  const auto best = nearest(position, tick, within, max_age);
  if (!best) return std::nullopt;
  constexpr double kSurfaceBand = 0.05;  // m: readings this close to the nearest are the same surface
  const double d = vnorm(vsub(*best, position));
  if (d < 1e-9) return best;
  Vec2 sum;
  for (const auto& e : echoes_) {
    const Vec2 rel = vsub(e.point, position);
    const double r = vnorm(rel);
    if (r <= d + kSurfaceBand && r > 1e-9) sum = vadd(sum, vscale(rel, 1.0 / r));
  }
  const double n = vnorm(sum);
  if (n < 1e-9) return best;  // echoes all round, cancelling out: the nearest one is as good as any
  return vadd(position, vscale(sum, d / n));
}

std::optional<double> EchoMemory::across(Vec2 position, Vec2 surface, Tick tick, double within,
                                         Tick max_age) {
  std::erase_if(echoes_, [&](const Echo& e) { return e.tick + max_age < tick; });
  const Vec2 away = vsub(position, surface);
  const double a = vnorm(away);
  if (a < 1e-9) return std::nullopt;
  const Vec2 u = vscale(away, 1.0 / a);
  const double cos_cone = std::cos(std::numbers::pi / 3);
  std::optional<double> best;
  for (const auto& e : echoes_) {
    const Vec2 rel = vsub(e.point, position);
    const double r = vnorm(rel);
    if (r >= within || r < 1e-9 || vdot(rel, u) < cos_cone * r) continue;
    if (!best || r < *best) best = r;
  }
  return best;
}

bool EchoMemory::gap_ahead(Vec2 position, Vec2 d, double obstacle_range, double clearance, Tick tick,
                           Tick max_age) {
  std::erase_if(echoes_, [&](const Echo& e) { return e.tick + max_age < tick; });
  const double length = obstacle_range + kRobotRadius;
  bool left = false, right = false;
  for (const auto& e : echoes_) {
    const Vec2 rel = vsub(e.point, position);
    if (vnorm(rel) - kRobotRadius >= obstacle_range) continue;
    const double along = vdot(rel, d);
    const double across = rel.y * d.x - rel.x * d.y;  // > 0: left of d
    const double t = std::clamp(along, 0.0, length);
    if (std::hypot(along - t, across) < clearance) return false;  // on the way
    if (along > 0.0) (across > 0.0 ? left : right) = true;
  }
  return left && right;
}

}  // namespace swarmform::controller::motion
