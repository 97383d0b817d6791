// The per-robot random generator (docs/behaviour-api.md, "Random numbers"): a stream that is a function of
// the run's seed and the robot's id only, written out so that any language can reproduce it, so a controller
// that draws from it makes the same decisions in-process and multi-process. Standard-library distributions
// are not used: their algorithms differ between standard libraries. Part of the installed behaviour API.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/mission.hpp"
#include "common/splitmix64.hpp"
#include "common/types.hpp"

namespace swarmform::behaviour {

class RobotRandom {
 public:
  static constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ULL;

  RobotRandom(std::uint64_t run_seed, RobotId id)
      : state_(splitmix64(run_seed) ^ (std::uint64_t{id} * kGolden)) {}
  RobotRandom(const Mission& mission, RobotId id) : RobotRandom(mission.seed, id) {}

  // 64 random bits: splitmix64 of the state, then the state advances by kGolden.
  std::uint64_t next() {
    const std::uint64_t out = splitmix64(state_);
    state_ += kGolden;
    return out;
  }
  // [0, 1), 53 bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Box-Muller on two uniform() draws; the second value is not kept.
  double normal(double mean, double sd) {
    const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
    const double u2 = uniform();
    return mean + sd * std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

 private:
  std::uint64_t state_;
};

}  // namespace swarmform::behaviour
