// The one ray caster of the sensors whose rays leave a robot's ring outward (the infrared ring, the lidar):
// ray k starts on the body's edge, at (x, y) + kRobotRadius * (dx[k], dy[k]), and looks along the arena-frame
// unit vector (dx[k], dy[k]). Its distance is measured from that start to the nearest body within `range`:
// every other robot (alive or dead) found through the grid, and every static body. Only 2-D: every body is a
// column taller than the sensors.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/spatial_grid.hpp"

namespace swarmform::world {

// Ray k's arena-frame angle is first + k * step (mod 2 pi), when the caller knows it: a fan of many rays
// then tests each body against the rays within its angular extent only. step 0: unknown, every ray is tested.
struct FanAngles {
  double first = 0.0;
  double step = 0.0;
};

// From this many rays on, a body's rays are found from its angular extent (an atan2 and an asin a body)
// rather than by testing every ray. Below, testing them all is cheaper. The result is the same either way:
// only rays that cannot reach the body are skipped.
inline constexpr std::size_t kFanCullRays = 16;

// nearest[k] = min(nearest[k], distance along ray k to the nearest body) for bodies that may lie within
// `range` of the ring (farther ones are skipped; a hit beyond range may still be reported: compare with it).
// The caller fills nearest with kNoHit first. `self` is not seen. Thread-safe (reads only).
void cast_ring_rays(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
                    const std::vector<StaticShape>& statics, double range, std::span<const double> dx,
                    std::span<const double> dy, std::span<double> nearest, FanAngles fan = {});

}  // namespace swarmform::world
