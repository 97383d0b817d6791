#include "world_server/world/ultrasonic.hpp"

#include <algorithm>
#include <cmath>

#include "world_server/world/parallel_for.hpp"

namespace swarmform::world {
namespace {

// A ray from the centre must travel this far to see something at the maximum range from the surface.
constexpr double kReach = kUltrasonicMaxRange + kRobotRadius;
const double kCosCone = std::cos(kConeHalfAngle);
const double kSinCone = std::sin(kConeHalfAngle);

}  // namespace

Ultrasonic::Ultrasonic(const std::vector<Obstacle>& statics, double noise_sd, std::uint64_t seed)
    : noise_sd_(noise_sd), rng_(seed, kSaltUltrasonic) {
  set_statics(statics);
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    axis_cos_[s] = std::cos(kUltrasonicAngles[s]);
    axis_sin_[s] = std::sin(kUltrasonicAngles[s]);
    for (int r = 0; r < kRaysPerSensor; ++r) {
      const double f = kRaysPerSensor == 1 ? 0.0 : -1.0 + 2.0 * r / (kRaysPerSensor - 1);
      const double angle = kUltrasonicAngles[s] + f * kConeHalfAngle;
      ray_cos_[s * kRaysPerSensor + static_cast<std::size_t>(r)] = std::cos(angle);
      ray_sin_[s * kRaysPerSensor + static_cast<std::size_t>(r)] = std::sin(angle);
    }
  }
}

UltrasonicReading Ultrasonic::read(std::size_t self, const std::vector<Pose2D>& poses,
                                   const SpatialGrid& grid) const {
  // One scratch per thread (the pool's workers in sense_all, the harness's when a world defers its readings,
  // World::defer_perceptions): reads run at once, each for its own robot, and allocate nothing once warm.
  thread_local Scratch scratch;
  return read_with(self, poses, grid, scratch);
}

UltrasonicReading Ultrasonic::read_with(std::size_t self, const std::vector<Pose2D>& poses,
                                        const SpatialGrid& grid, Scratch& scratch) const {
  const Pose2D& me = poses[self];
  const double ch = std::cos(me.theta), sh = std::sin(me.theta);
  // Each sensor's axis in the arena frame.
  std::array<double, kUltrasonicCount> axis_x, axis_y;
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    axis_x[s] = ch * axis_cos_[s] - sh * axis_sin_[s];
    axis_y[s] = sh * axis_cos_[s] + ch * axis_sin_[s];
  }
  // Robots whose body can be within reach go to the candidate list of every sensor whose cone can touch
  // them: the angle between the sensor's axis and the robot's centre is at most the cone's half-angle plus
  // the body's angular half-width asin(R/d). Each candidate is stored as its offset and |offset|^2 - R^2, so
  // the ray test below is a dot product, a compare and (rarely) a square root. Two passes, so that the
  // second has no branch to mispredict: every robot within reach with its cone bound (computed once), then
  // each sensor's list filled without branches (a slot written for every robot, kept when the test holds).
  scratch.reach.clear();
  grid.for_each_near_offset(me.x, me.y, kReach + kRobotRadius,
                            [&](std::uint32_t j, double dx, double dy, double d2) {
                              if (j == self) return;
                              const double c = d2 - kRobotRadius * kRobotRadius;
                              double bound = -kNoHit;  // bodies overlap: every sensor reads the minimum
                              // d cos(cone + a) with sin a = R / d: cos(cone) sqrt(d^2 - R^2) - sin(cone) R,
                              // one square root. The slack (1e-9 m, a million times the rounding of either
                              // form) keeps the set a superset of what the exact bound admits; the rays below
                              // decide exactly, so extra candidates change nothing.
                              if (c > 0.0) bound = kCosCone * std::sqrt(c) - kSinCone * kRobotRadius - 1e-9;
                              scratch.reach.push_back(Reach{Candidate{dx, dy, c}, bound});
                            });
  const std::size_t in_reach = scratch.reach.size();
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    std::vector<Candidate>& list = scratch.cands[s];
    if (list.size() < in_reach) list.resize(in_reach);
    std::size_t kept = 0;
    for (const Reach& r : scratch.reach) {
      list[kept] = r.cand;
      kept += r.cand.x * axis_x[s] + r.cand.y * axis_y[s] >= r.bound ? 1 : 0;
    }
    scratch.count[s] = kept;
  }
  // Static bodies within reach (by their true distance: a wall's bounding circle would hold everyone).
  // A static whose bounding circle is out of reach by the squared distance is skipped before the exact
  // clearance (a square root, or a box's frame): most robots are far from every obstacle.
  scratch.near_statics.clear();
  for (const StaticShape& st : statics_) {
    const double ox = me.x - st.cx, oy = me.y - st.cy, far = kReach + st.bound + 1e-6;
    if (ox * ox + oy * oy > far * far) continue;
    if (point_clearance(me.x, me.y, st) <= kReach) scratch.near_statics.push_back(&st);
  }

  UltrasonicReading out;
  for (std::size_t s = 0; s < kUltrasonicCount; ++s) {
    double nearest = kNoHit;
    for (std::size_t r = 0; r < static_cast<std::size_t>(kRaysPerSensor); ++r) {
      // The ray's direction: the robot-frame offset rotated by the heading.
      const std::size_t k = s * kRaysPerSensor + r;
      const double dx = ch * ray_cos_[k] - sh * ray_sin_[k];
      const double dy = sh * ray_cos_[k] + ch * ray_sin_[k];
      for (std::size_t q = 0; q < scratch.count[s]; ++q) {
        const Candidate& c = scratch.cands[s][q];
        // ray_circle with the ray starting at the origin.
        const double along = c.x * dx + c.y * dy;
        if (along <= 0.0) continue;
        const double disc = along * along - c.c;
        if (disc < 0.0) continue;
        nearest = std::min(nearest, c.c <= 0.0 ? 0.0 : along - std::sqrt(disc));
      }
      for (const StaticShape* st : scratch.near_statics)
        nearest = std::min(nearest, ray_static(me.x, me.y, dx, dy, *st));
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
  parallel::for_range(
      poses.size(),
      [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t i = begin; i < end; ++i) {
          if (alive[i]) out[i] = read(i, poses, grid);
        }
      },
      parallel::kMinRobotsPerWorker);
  if (noise_sd_ <= 0.0) return;
  for (std::size_t i = 0; i < poses.size(); ++i) {  // id order: the stream of the serial loop before
    if (!alive[i]) continue;
    for (double& v : out[i]) {
      if (v >= kUltrasonicMaxRange) continue;  // "nothing seen" stays exact
      v = std::clamp(v + rng_.gaussian(noise_sd_), kUltrasonicMinRange, kUltrasonicMaxRange);
    }
  }
}

void Ultrasonic::set_statics(const std::vector<Obstacle>& statics) {
  statics_.clear();
  for (const Obstacle& o : statics) statics_.push_back(make_static_shape(o));
}

}  // namespace swarmform::world
