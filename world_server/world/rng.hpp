// The world's random numbers: std::mt19937_64 (its output is fixed by the standard) with our own uniform and
// Gaussian transforms, because std::uniform_real_distribution and std::normal_distribution differ between
// standard libraries and a run must replay the same anywhere from the same seed. Each user (placement,
// medium, ultrasonic) has its own stream, derived from the scenario seed and a fixed salt, so adding draws in
// one does not shift the others.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "common/splitmix64.hpp"

namespace swarmform::world {

class Rng {
 public:
  explicit Rng(std::uint64_t seed, std::uint64_t salt) : engine_(splitmix64(seed ^ splitmix64(salt))) {}

  // Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  bool bernoulli(double p) { return p > 0.0 && uniform() < p; }

  // Standard normal, Box-Muller (both values used).
  double gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double mag = std::sqrt(-2.0 * std::log(u1));
    spare_ = mag * std::sin(2.0 * std::numbers::pi * u2);
    has_spare_ = true;
    return mag * std::cos(2.0 * std::numbers::pi * u2);
  }
  double gaussian(double sd) { return sd > 0.0 ? sd * gaussian() : 0.0; }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Salts: one stream per user.
inline constexpr std::uint64_t kSaltPlacement = 1;
inline constexpr std::uint64_t kSaltMedium = 2;
inline constexpr std::uint64_t kSaltUltrasonic = 3;
inline constexpr std::uint64_t kSaltBurstLoss = 4;  // hashed per draw (burst_loss.hpp), not a stream
inline constexpr std::uint64_t kSaltProximity = 5;
inline constexpr std::uint64_t kSaltGround = 6;
inline constexpr std::uint64_t kSaltLight = 7;
inline constexpr std::uint64_t kSaltBattery = 8;
inline constexpr std::uint64_t kSaltLidar = 9;

}  // namespace swarmform::world
