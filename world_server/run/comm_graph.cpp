#include "world_server/run/comm_graph.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace swarmform::world {

namespace {

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) {
      parent[i] = parent[parent[i]];
      i = parent[i];
    }
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

std::int64_t cell_key(std::int64_t cx, std::int64_t cy) {
  return (cx << 32) ^ (cy & 0xffffffff);
}

}  // namespace

std::vector<std::size_t> range_components(const std::vector<Vec2>& points, double range) {
  const std::size_t n = points.size();
  UnionFind uf(n);
  if (range > 0.0 && n > 1) {
    // Points into cells of side `range`: a neighbour within range is in the same or one of the 8 cells
    // around.
    std::unordered_map<std::int64_t, std::vector<std::size_t>> cells;
    cells.reserve(n);
    std::vector<std::pair<std::int64_t, std::int64_t>> cell_of(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto cx = static_cast<std::int64_t>(std::floor(points[i].x / range));
      const auto cy = static_cast<std::int64_t>(std::floor(points[i].y / range));
      cell_of[i] = {cx, cy};
      cells[cell_key(cx, cy)].push_back(i);
    }
    const double range_sq = range * range;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto it = cells.find(cell_key(cell_of[i].first + dx, cell_of[i].second + dy));
          if (it == cells.end()) continue;
          for (const std::size_t j : it->second) {
            if (j <= i) continue;
            const double ddx = points[i].x - points[j].x;
            const double ddy = points[i].y - points[j].y;
            if (ddx * ddx + ddy * ddy <= range_sq) uf.join(i, j);
          }
        }
      }
    }
  }
  // Renumber roots 0..k-1 in order of first appearance.
  std::vector<std::size_t> component(n);
  std::unordered_map<std::size_t, std::size_t> number;
  for (std::size_t i = 0; i < n; ++i) {
    const auto root = uf.find(i);
    component[i] = number.try_emplace(root, number.size()).first->second;
  }
  return component;
}

std::size_t component_count(const std::vector<std::size_t>& components) {
  std::size_t k = 0;
  for (const auto c : components) k = std::max(k, c + 1);
  return k;
}

}  // namespace swarmform::world
