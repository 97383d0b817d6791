#include "robot_agent/controller/parent_tree.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numbers>
#include <queue>
#include <utility>

#include "robot_agent/controller/vec2_math.hpp"

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

LabelLinks label_links(const std::vector<Vec2>& places, double spacing, double link_range, double far_range) {
  const std::size_t n = places.size();
  const double reach = std::max({1.5 * spacing, link_range, far_range});
  const bool bucketed = std::isfinite(reach) && reach > 0.0;
  // Cell coordinates, clamped so that a far-off place cannot overflow; a clamped cell only holds more labels.
  constexpr double kCellLimit = 1e6;
  auto cell = [&](double v) {
    return bucketed ? static_cast<std::int64_t>(std::clamp(std::floor(v / reach), -kCellLimit, kCellLimit))
                    : 0;
  };
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::size_t>> cells;
  for (std::size_t l = 0; l < n; ++l) cells[{cell(places[l].x), cell(places[l].y)}].push_back(l);
  LabelLinks links(n);
  for (std::size_t u = 0; u < n; ++u) {
    const std::int64_t cx = cell(places[u].x), cy = cell(places[u].y);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        if (!bucketed && (dx != 0 || dy != 0)) continue;
        auto it = cells.find({cx + dx, cy + dy});
        if (it == cells.end()) continue;
        for (const std::size_t v : it->second) {
          if (v == u) continue;
          const double d = vnorm(vsub(places[v], places[u]));
          const int w = link_cost(d, spacing, link_range, far_range);
          if (w != 0) links[u].push_back({v, w, d});
        }
      }
    }
    std::sort(links[u].begin(), links[u].end(),
              [](const LabelLink& a, const LabelLink& b) { return a.to < b.to; });
  }
  return links;
}

ParentTree build_parent_tree(const std::vector<Vec2>& places, const std::vector<bool>& present, int root,
                             double spacing, double link_range, double far_range, double heading) {
  return build_parent_tree(label_links(places, spacing, link_range, far_range), places, present, root,
                           heading);
}

namespace {

// The parent build_parent_tree gives `v`, from settled costs: among the labels on one of v's shortest paths,
// the nearest, then the most ahead, then the smallest label. Deterministic, and the cost strictly decreases
// along every parent link.
int choose_parent(const LabelLinks& links, const std::vector<Vec2>& places, const std::vector<bool>& present,
                  const std::vector<int>& cost, Vec2 forward, std::size_t v) {
  auto live = [&](std::size_t l) { return l < present.size() && present[l]; };
  int best = -1;
  double best_d = 0.0, best_ahead = 0.0;
  for (const LabelLink& link : links[v]) {  // ascending labels
    const std::size_t u = link.to;
    if (!live(u) || cost[u] == kUnreachable || cost[u] + link.cost != cost[v]) continue;
    const double d = link.d;
    const double ahead = vdot(vsub(places[u], places[v]), forward);
    constexpr double kEps = 1e-9;
    const bool better =
        best < 0 || d < best_d - kEps || (std::abs(d - best_d) <= kEps && ahead > best_ahead + kEps);
    if (better) {  // u grows, so on a full tie the smaller label (found first) stays
      best = static_cast<int>(u);
      best_d = d;
      best_ahead = ahead;
    }
  }
  return best;
}

// Dijkstra over the labels held by live robots, from `root`, until `stop` is settled (never, for the whole
// tree: stop = places.size()). The costs are integers, so they do not depend on the order in which links are
// relaxed. `cost` must hold kUnreachable everywhere but the root (0) on entry.
void settle(const LabelLinks& links, const std::vector<bool>& present, std::size_t root, std::size_t stop,
            std::vector<int>& cost) {
  auto live = [&](std::size_t l) { return l < present.size() && present[l]; };
  using Item = std::pair<int, std::size_t>;  // (cost, label)
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  open.push({0, root});
  while (!open.empty()) {
    const auto [c, u] = open.top();
    open.pop();
    if (c != cost[u]) continue;
    if (u == stop) return;
    for (const LabelLink& link : links[u]) {
      if (!live(link.to)) continue;
      if (c + link.cost < cost[link.to]) {
        cost[link.to] = c + link.cost;
        open.push({c + link.cost, link.to});
      }
    }
  }
}

}  // namespace

ParentTree build_parent_tree(const LabelLinks& links, const std::vector<Vec2>& places,
                             const std::vector<bool>& present, int root, double heading) {
  const std::size_t n = places.size();
  ParentTree tree;
  tree.root = root;
  tree.parent.assign(n, -1);
  tree.cost.assign(n, kUnreachable);
  auto live = [&](std::size_t l) { return l < present.size() && present[l]; };
  if (root < 0 || static_cast<std::size_t>(root) >= n || !live(static_cast<std::size_t>(root))) return tree;
  tree.cost[static_cast<std::size_t>(root)] = 0;
  settle(links, present, static_cast<std::size_t>(root), n, tree.cost);  // n: no label stops it
  const Vec2 forward = vpolar(1.0, heading);
  for (std::size_t v = 0; v < n; ++v) {
    if (!live(v) || static_cast<int>(v) == root || tree.cost[v] == kUnreachable) continue;
    tree.parent[v] = choose_parent(links, places, present, tree.cost, forward, v);
  }
  return tree;
}

int parent_in_tree(const LabelLinks& links, const std::vector<Vec2>& places, const std::vector<bool>& present,
                   int root, double heading, int label, std::vector<int>& cost) {
  const std::size_t n = places.size();
  auto live = [&](std::size_t l) { return l < present.size() && present[l]; };
  if (root < 0 || static_cast<std::size_t>(root) >= n || !live(static_cast<std::size_t>(root))) return -1;
  if (label < 0 || static_cast<std::size_t>(label) >= n || !live(static_cast<std::size_t>(label)) ||
      label == root)
    return -1;
  cost.assign(n, kUnreachable);
  cost[static_cast<std::size_t>(root)] = 0;
  settle(links, present, static_cast<std::size_t>(root), static_cast<std::size_t>(label), cost);
  if (cost[static_cast<std::size_t>(label)] == kUnreachable) return -1;
  return choose_parent(links, places, present, cost, vpolar(1.0, heading), static_cast<std::size_t>(label));
}

bool ParentTreeCache::same_links(const std::vector<Vec2>& places, double spacing, double link_range,
                                 double far_range) const {
  // Compared with ==: any change rebuilds (a NaN never compares equal, so it rebuilds every call).
  return has_links_ && spacing == spacing_ && link_range == link_range_ && far_range == far_range_ &&
         std::equal(places.begin(), places.end(), places_.begin(), places_.end(),
                    [](Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; });
}

void ParentTreeCache::find_links(const std::vector<Vec2>& places, double spacing, double link_range,
                                 double far_range) {
  links_ = label_links(places, spacing, link_range, far_range);
  places_ = places;
  spacing_ = spacing;
  link_range_ = link_range;
  far_range_ = far_range;
  has_links_ = true;
  has_tree_ = false;
  has_parent_ = false;
  ++link_builds_;
}

int ParentTreeCache::parent(const std::vector<Vec2>& places, const std::vector<bool>& present, int root,
                            double spacing, double link_range, double far_range, double heading, int label) {
  if (!same_links(places, spacing, link_range, far_range)) find_links(places, spacing, link_range, far_range);
  if (has_parent_ && label == label_ && root == root_ && heading == heading_ && present == present_)
    return parent_;
  parent_ = parent_in_tree(links_, places_, present, root, heading, label, cost_);
  label_ = label;
  present_ = present;
  root_ = root;
  heading_ = heading;
  has_parent_ = true;
  has_tree_ = false;  // present_, root_ and heading_ now describe parent_
  ++builds_;
  return parent_;
}

const ParentTree& ParentTreeCache::get(const std::vector<Vec2>& places, const std::vector<bool>& present,
                                       int root, double spacing, double link_range, double far_range,
                                       double heading) {
  if (!same_links(places, spacing, link_range, far_range)) find_links(places, spacing, link_range, far_range);
  if (!has_tree_ || root != root_ || heading != heading_ || present != present_) {
    tree_ = build_parent_tree(links_, places_, present, root, heading);
    has_parent_ = false;  // present_, root_ and heading_ now describe tree_
    present_ = present;
    root_ = root;
    heading_ = heading;
    has_tree_ = true;
    ++builds_;
  }
  return tree_;
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
