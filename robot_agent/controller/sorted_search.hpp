// A branch-free std::lower_bound, for the neighbour table's ids: each tick a robot looks up ~73 senders in
// an order the branch predictor cannot guess, and with std::lower_bound's branches the mispredictions cost
// more than the search's few cache lines (BENCHMARKS.md, P3: the controllers' step 13.75 -> 11.44 us). The
// step is a multiply by the comparison, not a select, which GCC would turn back into a branch. (The
// stigmergy table's lookups, tried the same way, did not get faster: measured within the noise.)
#pragma once

#include <cstddef>

namespace swarmform::controller {

// The first index i of the range [data, data + n), sorted by key_of, with !(key_of(data[i]) < key); n when
// there is none.
template <class T, class Key, class KeyOf>
std::size_t lower_bound_index(const T* data, std::size_t n, const Key& key, KeyOf key_of) {
  std::size_t first = 0;
  std::size_t length = n;
  while (length > 1) {  // the answer is in [first, first + length]
    const std::size_t half = length / 2;
    first += static_cast<std::size_t>(key_of(data[first + half - 1]) < key) * half;
    length -= half;
  }
  return first + static_cast<std::size_t>(length == 1 && key_of(data[first]) < key);
}

}  // namespace swarmform::controller
