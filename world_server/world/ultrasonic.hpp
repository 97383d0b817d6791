// The Khepera IV's five ultrasonic sensors, after ARGoS's proximity sensors but as cones:
// each sensor at kUltrasonicAngles casts kRaysPerSensor rays spread over +-kConeHalfAngle around its axis,
// from the robot's CENTRE (a ray starting on the surface could start inside a touching body), against every
// other robot (alive or dead) and every static body, analytically. A ray's distance is measured from the
// robot's SURFACE (centre distance minus kRobotRadius); a reading is the minimum over its cone's rays,
// clamped to [kUltrasonicMinRange, kUltrasonicMaxRange], and exactly kUltrasonicMaxRange when nothing is
// within range. Gaussian noise (scenario `noise.ultrasonic`) is added to readings that saw something, then
// clamped again.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/rng.hpp"
#include "world_server/world/spatial_grid.hpp"

namespace swarmform::world {

inline constexpr int kRaysPerSensor = 5;
inline constexpr double kConeHalfAngle = 0.2617993877991494;  // rad, 15 degrees

using UltrasonicReading = std::array<double, kUltrasonicCount>;

class Ultrasonic {
 public:
  Ultrasonic(const std::vector<Obstacle>& statics, double noise_sd, std::uint64_t seed);

  // The noiseless reading of robot `self` standing at poses[self]; `grid` holds `poses` (all robots, alive
  // or dead: every body is seen). Several threads may read at once (each has its own scratch).
  UltrasonicReading read(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid) const;

  // Whether sense_all adds noise (then its readings depend on the order of the draws, not only on the poses).
  bool noisy() const { return noise_sd_ > 0.0; }

  // Readings for every robot with alive[i] != 0; others' entries are left as they were. The noiseless
  // readings are computed on the worker pool (parallel_for.hpp), each robot's into its own slot; the noise is
  // then drawn in id order on the calling thread, so the stream is the same whatever the worker count.
  void sense_all(const std::vector<Pose2D>& poses, const std::vector<char>& alive, const SpatialGrid& grid,
                 std::vector<UltrasonicReading>& out);

  // The obstacles it sees from now on (present_statics: world events moved, added or removed some).
  void set_statics(const std::vector<Obstacle>& statics);

 private:
  std::vector<StaticShape> statics_;
  double noise_sd_;
  Rng rng_;
  // Robot-frame ray directions (cos, sin of each ray's angle), sensor by sensor.
  std::array<double, kUltrasonicCount * kRaysPerSensor> ray_cos_{}, ray_sin_{};
  std::array<double, kUltrasonicCount> axis_cos_{}, axis_sin_{};  // robot-frame sensor axes
  // Scratch for a read, reused across calls (no allocation once warm): per sensor, the robots its cone may
  // touch, as offsets from the reading robot and |offset|^2 - R^2. One per thread (read()).
  struct Candidate {
    double x, y, c;
  };
  struct Reach {
    Candidate cand;
    double bound;  // the cone test: a sensor whose axis . offset >= bound may see it (-inf: overlapping)
  };
  struct Scratch {
    std::vector<Reach> reach;                                    // every robot within reach
    std::array<std::vector<Candidate>, kUltrasonicCount> cands;  // per sensor: buffers, count[s] used
    std::array<std::size_t, kUltrasonicCount> count{};
    std::vector<const StaticShape*> near_statics;
  };
  UltrasonicReading read_with(std::size_t self, const std::vector<Pose2D>& poses, const SpatialGrid& grid,
                              Scratch& scratch) const;
};

}  // namespace swarmform::world
