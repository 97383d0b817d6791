// The Khepera IV's optional lidar, after ARGoS's Khepera IV plug-in (ilpincy/argos3-kheperaiv):
// kheperaiv_measures.cpp gives the fan (KHEPERAIV_LIDAR_ANGLE_SPAN 210 degrees,
// KHEPERAIV_LIDAR_SENSORS_RING_RANGE 0.02 to 4.0 m, the fan's radius KHEPERAIV_LIDAR_SENSORS_FAN_RADIUS = the
// body's 0.0704 m) and kheperaiv_lidar_default_sensor.cpp its use (682 readings unless num_readings says
// otherwise, the first ray at -span/2 and the last at +span/2, evenly spaced, a uniform noise_level added to
// each reading). Here:
//   - ray k of N (scenario `lidar.rays`) points at -fov/2 + k fov/(N-1) in the robot frame (counter-clockwise
//     from the heading; 0 when N = 1); it starts on the body's edge and is cast by ray_fan.hpp against every
//     other robot (alive or dead) and every static body;
//   - its range is the distance from the edge to the nearest hit, clamped to [min_range, max_range]; nothing
//     within max_range reads exactly max_range (ARGoS reads 0 there; a range that is always a distance is
//     what this project's ultrasonic sensors do too);
//   - noise (scenario `noise.lidar`, m): uniform in [-level, +level] added to each ray that hit something,
//     clamped again, drawn in robot id order then ray order from the lidar's own stream.
// Only 2-D: ARGoS's fan sits 0.14 m up; every body here is a column, robots included.
#pragma once

#include <cstdint>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/lidar_spec.hpp"
#include "world_server/world/rng.hpp"
#include "world_server/world/spatial_grid.hpp"

namespace swarmform::world {

using LidarScan = std::vector<LidarRay>;

class Lidar {
 public:
  Lidar(const LidarSpec& spec, const std::vector<Obstacle>& statics, double noise_level, std::uint64_t seed);

  // The noiseless scan of robot `self` at poses[self] into `out` (resized to the ray count, its storage
  // reused); `grid` holds `poses` (every robot, alive or dead). Thread-safe (reads only).
  void read(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
            LidarScan& out) const;

  // Scans for every robot with alive[i] != 0 (others' entries left as they were): noiseless scans on the
  // worker pool, then the noise drawn in id order on the calling thread.
  void sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive, const SpatialGrid& grid,
                 std::vector<LidarScan>& out);

  // The obstacles it sees from now on (present_statics: world events moved, added or removed some).
  void set_statics(const std::vector<Obstacle>& statics);

 private:
  LidarSpec spec_;
  std::vector<StaticShape> statics_;
  double noise_level_;
  Rng rng_;
  std::vector<double> angle_, cos_, sin_;  // each ray's robot-frame angle, its cosine and sine
};

}  // namespace swarmform::world
