// What the Khepera IV's sensors share: reading every live robot in parallel before drawing the noise, and the
// [0, 1] sensors' (proximity, light, ground) ARGoS `noise_level` noise.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "world_server/world/parallel_for.hpp"
#include "world_server/world/rng.hpp"

namespace swarmform::world {

// Each value plus a uniform draw in [-level, level], clamped to [0, 1] (ARGoS's noise on these sensors).
template <typename Reading>
void add_uniform_noise(Reading& reading, Rng& rng, double level) {
  for (double& v : reading) v = std::clamp(v + rng.uniform(-level, level), 0.0, 1.0);
}

// `read(i, out[i])` for every live robot, in parallel (the reads are independent; each writes its own slot).
template <typename Reading, typename ReadInto>
void read_each(const std::vector<char>& alive, std::vector<Reading>& out, ReadInto read) {
  out.resize(alive.size());
  parallel::for_range(
      alive.size(),
      [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t i = begin; i < end; ++i) {
          if (alive[i]) read(i, out[i]);
        }
      },
      parallel::kMinRobotsPerWorker);
}

// `read(i)` for every live robot, in parallel, then the noise in id order from the sensor's one stream: the
// same draws whatever the number of workers.
template <typename Reading, typename Read>
void read_all(const std::vector<char>& alive, std::vector<Reading>& out, Read read, Rng& rng, double level) {
  read_each(alive, out, [&](std::size_t i, Reading& r) { r = read(i); });
  if (level <= 0.0) return;
  for (std::size_t i = 0; i < alive.size(); ++i) {
    if (alive[i]) add_uniform_noise(out[i], rng, level);
  }
}

}  // namespace swarmform::world
