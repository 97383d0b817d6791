// The Khepera IV's ring of 8 infrared proximity sensors, after ARGoS's Khepera IV plug-in
// (ilpincy/argos3-kheperaiv: kheperaiv_entity.cpp puts the ring, kheperaiv_measures.cpp gives its numbers,
// kheperaiv_proximity_default_sensor.cpp turns a distance into a reading):
//   - sensor k (0..7) sits on the body's edge (ring radius = body radius 0.0704 m) at kProximityAngles[k] =
//     k * 45 degrees, counter-clockwise from the heading, and looks straight out along that direction;
//   - one ray a sensor, 0.12 m long, from the sensor outward, against every other robot (alive or dead) and
//     every static body; d is the distance from the sensor to the nearest hit;
//   - reading: 1 when d < 0.04 m (saturated: touching or nearly), 0 when nothing is within 0.12 m, and
//     4.14 exp(-33 d) - 0.085 in between (ARGoS's fit of the real sensor), clamped to [0, 1];
//   - noise (scenario `noise.proximity`, ARGoS's noise_level): uniform in [-level, +level], added to every
//     reading (also to 0) and clamped to [0, 1] again, drawn in robot id order from its own stream.
// Only 2-D: every body in the world stands taller than the ring's 0.0145 m elevation.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/rng.hpp"
#include "world_server/world/spatial_grid.hpp"

namespace swarmform::world {

inline constexpr double kProximityRange = 0.12;       // m, KHEPERAIV_IR_SENSORS_RING_RANGE
inline constexpr double kProximitySaturation = 0.04;  // m: closer reads 1 (CalculateReading)

using ProximityReading = std::array<double, kProximityCount>;

// The noiseless reading for a distance d from the sensor (kNoHit: nothing within range).
double proximity_value(double d);

class Proximity {
 public:
  Proximity(const std::vector<Obstacle>& statics, double noise_level, std::uint64_t seed);

  // The noiseless reading of robot `self` at poses[self]; `grid` holds `poses` (every robot, alive or dead).
  // Thread-safe (reads only).
  ProximityReading read(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid) const;

  // Readings for every robot with alive[i] != 0 (others' entries left as they were): noiseless readings on
  // the worker pool, then the noise drawn in id order on the calling thread (the same stream whatever the
  // worker count).
  void sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive, const SpatialGrid& grid,
                 std::vector<ProximityReading>& out);

  // The obstacles it sees from now on (present_statics: world events moved, added or removed some).
  void set_statics(const std::vector<Obstacle>& statics);

 private:
  std::vector<StaticShape> statics_;
  double noise_level_;
  Rng rng_;
};

}  // namespace swarmform::world
