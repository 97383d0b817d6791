// The Khepera IV's 8 light sensors, after ARGoS's Khepera IV plug-in (ilpincy/argos3-kheperaiv:
// kheperaiv_entity.cpp puts them on the proximity ring, kheperaiv_light_rotzonly_sensor.cpp reads them):
//   - sensor k faces kProximityAngles[k] (k x 45 degrees from the heading), as the infrared ring;
//   - each light source (scenario `lights`: position, height, intensity I > 0) that the robot sees is a
//     reading of exp(-2 d) at d = |robot -> light| / I (3-D distance from the robot's centre on the floor to
//     the light; 0 past d = 2.5), scaled for sensor k by 1 - 2 a / pi, a the angle between the sensor and the
//     light's direction (0 past 90 degrees); the sources' readings add up;
//   - a source is hidden when the straight line from the robot's centre (on the floor) to the light passes
//     through a wall, an obstacle or another robot below its top (a body is a prism: walls and obstacles
//     kStaticHeight tall, robots kRobotHeight);
//   - noise (scenario `noise.light`, ARGoS's noise_level): uniform in [-level, +level] on every reading; each
//     reading is then clamped to [0, 1]; drawn in robot id order from its own stream.
// ARGoS spreads a light over the nearest sensor and two on each side with a spacing constant of pi/12 (the
// foot-bot's 24-sensor ring); on the Khepera's 45-degree ring that window is every sensor within 90 degrees
// of the light, which is what this model sums over, exactly.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/rng.hpp"
#include "world_server/world/spatial_grid.hpp"

namespace swarmform::world {

using LightReading = std::array<double, kLightCount>;

class LightSensors {
 public:
  LightSensors(const std::vector<LightSource>& lights, const std::vector<Obstacle>& statics,
               double noise_level, std::uint64_t seed);

  // The noiseless reading of robot `self` at poses[self]; `grid` holds `poses` (every robot: dead ones
  // hide lights too). Thread-safe (reads only).
  LightReading read(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid) const;

  // Whether the segment from the robot's centre to light `l` is blocked (exposed for the tests).
  bool hidden(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
              const LightSource& l) const;

  // Readings for every robot with alive[i] != 0: noiseless on the worker pool, noise in id order after.
  void sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive, const SpatialGrid& grid,
                 std::vector<LightReading>& out);

  // The obstacles it sees from now on (present_statics: world events moved, added or removed some).
  void set_statics(const std::vector<Obstacle>& statics);

 private:
  std::vector<LightSource> lights_;
  std::vector<StaticShape> statics_;
  double noise_level_;
  Rng rng_;
};

}  // namespace swarmform::world
