// splitmix64 (Steele, Lea & Flood): one step of the generator, used as a mixing function. Every input bit
// moves about half the output bits, so neighbouring inputs (seed ^ id for ids 0, 1, 2...) give unrelated
// outputs. Seeds the robots' and the world's random streams, and hashes stigmergy entries.
#pragma once

#include <cstdint>

namespace swarmform {

constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace swarmform
