// Connected components of the "within range" graph of a set of points: the communication graph of the live
// shape robots, for the fragment / rejoin_graph events (the small obstacle of the paper splits the formation
// and it reunites). Uniform grid of cell size `range` plus union-find, so it stays near O(n), not O(n^2).
#pragma once

#include <cstddef>
#include <vector>

#include "common/types.hpp"

namespace swarmform::world {

// The component index (0..k-1, numbered in order of first appearance) of each point; two points are joined
// when their distance is <= range.
std::vector<std::size_t> range_components(const std::vector<Vec2>& points, double range);

// Number of components of range_components' result.
std::size_t component_count(const std::vector<std::size_t>& components);

}  // namespace swarmform::world
