#include "robot_agent/controller/parent_tree.hpp"

#include <cmath>
#include <functional>
#include <numbers>
#include <queue>
#include <utility>

#include "robot_agent/controller/motion_math.hpp"

namespace swarmform::controller::motion {

std::vector<Vec2> label_places(const ShapeMatrix& shape, double spacing, double shape_heading) {
  const double turn = shape_heading - std::numbers::pi / 2;
  std::vector<Vec2> places;
  for (int r = 0; r < shape.rows; ++r) {
    for (int c = 0; c < shape.cols; ++c) {
      const int label = shape.at(r, c);
      if (label < 0) continue;
      if (static_cast<std::size_t>(label) >= places.size())
        places.resize(static_cast<std::size_t>(label) + 1);
      places[static_cast<std::size_t>(label)] = vrotate({c * spacing, -r * spacing}, turn);
    }
  }
  return places;
}

namespace {

// Link cost between two labels `d` apart; 0 = no link.
int link_cost(double d, double spacing, double link_range, double far_range) {
  if (d <= 1.5 * spacing) return 1;
  if (d <= link_range) return kLongLinkCost;
  if (d <= far_range) return kFarLinkCost;
  return 0;
}

}  // namespace

ParentTree build_parent_tree(const std::vector<Vec2>& places, const std::vector<bool>& present, int root,
                             double spacing, double link_range, double far_range, double heading) {
  const std::size_t n = places.size();
  ParentTree tree;
  tree.root = root;
  tree.parent.assign(n, -1);
  tree.cost.assign(n, kUnreachable);
  auto live = [&](std::size_t l) { return l < present.size() && present[l]; };
  if (root < 0 || static_cast<std::size_t>(root) >= n || !live(static_cast<std::size_t>(root))) return tree;

  // Dijkstra over the labels held by live robots (n <= a few hundred: a dense scan is fine).
  using Item = std::pair<int, std::size_t>;  // (cost, label)
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  tree.cost[static_cast<std::size_t>(root)] = 0;
  open.push({0, static_cast<std::size_t>(root)});
  while (!open.empty()) {
    const auto [cost, u] = open.top();
    open.pop();
    if (cost != tree.cost[u]) continue;
    for (std::size_t v = 0; v < n; ++v) {
      if (v == u || !live(v)) continue;
      const int w = link_cost(vnorm(vsub(places[v], places[u])), spacing, link_range, far_range);
      if (w == 0) continue;
      if (cost + w < tree.cost[v]) {
        tree.cost[v] = cost + w;
        open.push({cost + w, v});
      }
    }
  }

  // Each label's parent among the labels that lie on one of its shortest paths: nearest, then most ahead,
  // then smallest label. Deterministic, and the cost strictly decreases along every parent link.
  const Vec2 forward = vpolar(1.0, heading);
  for (std::size_t v = 0; v < n; ++v) {
    if (!live(v) || static_cast<int>(v) == root || tree.cost[v] == kUnreachable) continue;
    int best = -1;
    double best_d = 0.0, best_ahead = 0.0;
    for (std::size_t u = 0; u < n; ++u) {
      if (u == v || !live(u) || tree.cost[u] == kUnreachable) continue;
      const Vec2 rel = vsub(places[u], places[v]);
      const double d = vnorm(rel);
      const int w = link_cost(d, spacing, link_range, far_range);
      if (w == 0 || tree.cost[u] + w != tree.cost[v]) continue;
      const double ahead = vdot(rel, forward);
      constexpr double kEps = 1e-9;
      const bool better =
          best < 0 || d < best_d - kEps || (std::abs(d - best_d) <= kEps && ahead > best_ahead + kEps);
      if (better) {  // u grows, so on a full tie the smaller label (found first) stays
        best = static_cast<int>(u);
        best_d = d;
        best_ahead = ahead;
      }
    }
    tree.parent[v] = best;
  }
  return tree;
}

bool would_close_cycle(const std::map<RobotId, RobotId>& parents, RobotId self, RobotId candidate) {
  RobotId at = candidate;
  for (std::size_t steps = 0; steps <= parents.size() + 1; ++steps) {
    if (at == self) return true;
    auto it = parents.find(at);
    if (it == parents.end()) return false;
    at = it->second;
  }
  return true;  // a cycle not through self already exists: do not join it
}

}  // namespace swarmform::controller::motion
