// The Khepera IV's 4 ground sensors underneath, after ARGoS's Khepera IV plug-in (ilpincy/argos3-kheperaiv:
// kheperaiv_measures.cpp KHEPERAIV_IR_SENSORS_GROUND_OFFSET, kheperaiv_ground_rotzonly_sensor.cpp): each
// reads the floor's grey level (floor.hpp: 0 black, 1 white) at one point, offset in the robot frame by
// kGroundOffsets (x ahead, y to the left), turned with the robot's heading. Noise (scenario `noise.ground`,
// ARGoS's noise_level): uniform in [-level, +level] added to each reading, clamped to [0, 1], drawn in robot
// id order from its own stream.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/floor.hpp"
#include "world_server/world/rng.hpp"

namespace swarmform::world {

// m, robot frame: front-left, left, right, front-right (ARGoS's order).
inline constexpr std::array<Vec2, kGroundCount> kGroundOffsets = {
    Vec2{0.06140, 0.01}, Vec2{0.02060, 0.059}, Vec2{0.02060, -0.059}, Vec2{0.06140, -0.01}};

using GroundReading = std::array<double, kGroundCount>;

class Ground {
 public:
  Ground(Floor floor, Vec2 arena_centre, double width, double height, double noise_level, std::uint64_t seed);

  // The noiseless reading of a robot at `pose`.
  GroundReading read(const Pose2D& pose) const;

  // Readings for every robot with alive[i] != 0 (others left as they were), noise drawn in id order.
  void sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                 std::vector<GroundReading>& out);

 private:
  Floor floor_;
  Vec2 centre_;
  double width_, height_;
  double noise_level_;
  Rng rng_;
};

}  // namespace swarmform::world
