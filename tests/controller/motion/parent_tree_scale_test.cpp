// The parent tree at scale: the bucketed builder gives exactly the tree of the dense all-pairs scan it
// replaced (kept below as the reference), on every shape in shapes/ and the scale blocks, with robots
// missing; and ParentTreeCache rebuilds only when an input changes (the per-tick cost the scale runs could
// not pay).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <queue>
#include <random>

#include "common/shape.hpp"
#include "robot_agent/controller/parent_tree.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {
namespace {

// The all-pairs builder as it was before the buckets (O(L^2)): the reference.
ParentTree dense_tree(const std::vector<Vec2>& places, const std::vector<bool>& present, int root,
                      double spacing, double link_range, double far_range, double heading) {
  auto link_cost = [&](double d) {
    if (d <= 1.5 * spacing) return 1;
    if (d <= link_range) return kLongLinkCost;
    if (d <= far_range) return kFarLinkCost;
    return 0;
  };
  const std::size_t n = places.size();
  ParentTree tree;
  tree.root = root;
  tree.parent.assign(n, -1);
  tree.cost.assign(n, kUnreachable);
  auto live = [&](std::size_t l) { return l < present.size() && present[l]; };
  if (root < 0 || static_cast<std::size_t>(root) >= n || !live(static_cast<std::size_t>(root))) return tree;
  using Item = std::pair<int, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  tree.cost[static_cast<std::size_t>(root)] = 0;
  open.push({0, static_cast<std::size_t>(root)});
  while (!open.empty()) {
    const auto [cost, u] = open.top();
    open.pop();
    if (cost != tree.cost[u]) continue;
    for (std::size_t v = 0; v < n; ++v) {
      if (v == u || !live(v)) continue;
      const int w = link_cost(vnorm(vsub(places[v], places[u])));
      if (w == 0) continue;
      if (cost + w < tree.cost[v]) {
        tree.cost[v] = cost + w;
        open.push({cost + w, v});
      }
    }
  }
  const Vec2 forward = vpolar(1.0, heading);
  for (std::size_t v = 0; v < n; ++v) {
    if (!live(v) || static_cast<int>(v) == root || tree.cost[v] == kUnreachable) continue;
    int best = -1;
    double best_d = 0.0, best_ahead = 0.0;
    for (std::size_t u = 0; u < n; ++u) {
      if (u == v || !live(u) || tree.cost[u] == kUnreachable) continue;
      const Vec2 rel = vsub(places[u], places[v]);
      const double d = vnorm(rel);
      const int w = link_cost(d);
      if (w == 0 || tree.cost[u] + w != tree.cost[v]) continue;
      const double ahead = vdot(rel, forward);
      constexpr double kEps = 1e-9;
      if (best < 0 || d < best_d - kEps || (std::abs(d - best_d) <= kEps && ahead > best_ahead + kEps)) {
        best = static_cast<int>(u);
        best_d = d;
        best_ahead = ahead;
      }
    }
    tree.parent[v] = best;
  }
  return tree;
}

std::vector<std::filesystem::path> shape_files() {
  std::vector<std::filesystem::path> files;
  for (const char* dir : {SWARMFORM_SHAPES_DIR, SWARMFORM_SCALE_SHAPES_DIR}) {
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
      if (e.path().extension() == ".txt") files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ParentTreeScale, BucketedTreeEqualsTheDenseScanOnEveryShapeWithRobotsMissing) {
  const auto files = shape_files();
  ASSERT_GE(files.size(), 9u);  // shapes/ and the three scale blocks
  std::mt19937 rng(17);
  for (const auto& file : files) {
    const ShapeMatrix shape = load_shape_file(file.string());
    // Headings: the default, the paper's, and one that puts the grid off the buckets' axes. Spacings and
    // ranges: the paper's, a grid wider than the radio range (only far links), a long-link range beyond it.
    for (const double heading : {std::numbers::pi / 2, 0.0, 0.7}) {
      for (const auto& [spacing, link_range, far_range] : std::vector<std::tuple<double, double, double>>{
               {1.0, 2.7, 3.0}, {2.5, 2.0, 3.0}, {0.5, 4.0, 1.0}}) {
        const auto places = label_places(shape, spacing, heading);
        const std::size_t n = places.size();
        for (const double missing : {0.0, 0.05, 0.3}) {
          std::vector<bool> present(n, true);
          std::bernoulli_distribution drop(missing);
          for (std::size_t l = 0; l < n; ++l) present[l] = !drop(rng);
          const int root = static_cast<int>(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng));
          present[static_cast<std::size_t>(root)] = true;
          SCOPED_TRACE(testing::Message() << file.filename() << " heading " << heading << " spacing "
                                          << spacing << " missing " << missing << " root " << root);
          const auto got = build_parent_tree(places, present, root, spacing, link_range, far_range, heading);
          const auto want = dense_tree(places, present, root, spacing, link_range, far_range, heading);
          EXPECT_EQ(got.parent, want.parent);
          EXPECT_EQ(got.cost, want.cost);
        }
      }
    }
  }
}

// One label's parent, found by a Dijkstra that stops once that label is settled, is the whole tree's, for
// every label of every shape and block, with robots missing, several leaders and headings.
TEST(ParentTreeScale, OneLabelsParentIsTheWholeTreesForEveryLabel) {
  std::mt19937 rng(11);
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(SWARMFORM_SHAPES_DIR)) {
    if (e.path().extension() == ".txt") files.push_back(e.path());
  }
  for (const char* block : {"block_10x10.txt", "block_20x20.txt"}) {
    files.push_back(std::filesystem::path(SWARMFORM_SCALE_SHAPES_DIR) / block);
  }
  ASSERT_GE(files.size(), 8u);
  std::vector<int> cost;
  for (const auto& file : files) {
    const ShapeMatrix shape = load_shape_file(file.string());
    for (const double heading : {std::numbers::pi / 2, 0.7}) {
      const auto places = label_places(shape, 1.0, heading);
      const auto links = label_links(places, 1.0, 2.7, 3.0);
      const std::size_t n = places.size();
      for (const double missing : {0.0, 0.2}) {
        std::vector<bool> present(n, true);
        std::bernoulli_distribution drop(missing);
        for (std::size_t l = 0; l < n; ++l) present[l] = !drop(rng);
        const int root = static_cast<int>(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng));
        present[static_cast<std::size_t>(root)] = true;
        SCOPED_TRACE(testing::Message() << file.filename() << " heading " << heading << " missing " << missing
                                        << " root " << root);
        const auto tree = build_parent_tree(links, places, present, root, heading);
        ParentTreeCache cache;
        for (std::size_t l = 0; l < n; ++l) {
          const int label = static_cast<int>(l);
          ASSERT_EQ(parent_in_tree(links, places, present, root, heading, label, cost), tree.parent[l]) << l;
          ASSERT_EQ(cache.parent(places, present, root, 1.0, 2.7, 3.0, heading, label), tree.parent[l]) << l;
        }
        EXPECT_EQ(parent_in_tree(links, places, present, root, heading, static_cast<int>(n), cost), -1);
        EXPECT_EQ(parent_in_tree(links, places, present, root, heading, -1, cost), -1);
      }
    }
  }
}

TEST(ParentTreeScale, CacheKeepsOneLabelsParentWhileItsInputsStay) {
  const auto places = label_places(load_shape_file(SWARMFORM_SCALE_SHAPES_DIR "/block_10x10.txt"), 1.0);
  std::vector<bool> present(places.size(), true);
  ParentTreeCache cache;
  const int first = cache.parent(places, present, 0, 1.0, 2.7, 3.0, 0.0, 42);
  for (int tick = 0; tick < 50; ++tick)
    EXPECT_EQ(cache.parent(places, present, 0, 1.0, 2.7, 3.0, 0.0, 42), first);
  EXPECT_EQ(cache.builds(), 1u);
  present[first] = false;  // the parent died: another one
  const int second = cache.parent(places, present, 0, 1.0, 2.7, 3.0, 0.0, 42);
  EXPECT_EQ(cache.builds(), 2u);
  EXPECT_NE(second, first);
  EXPECT_EQ(second, build_parent_tree(places, present, 0, 1.0, 2.7, 3.0, 0.0).parent[42]);
  cache.parent(places, present, 0, 1.0, 2.7, 3.0, 0.0, 43);  // another label
  EXPECT_EQ(cache.builds(), 3u);
  EXPECT_EQ(cache.link_builds(), 1u);
}

TEST(ParentTreeScale, CacheRebuildsOnlyWhenAnInputChanges) {
  const auto places = label_places(load_shape_file(SWARMFORM_SCALE_SHAPES_DIR "/block_10x10.txt"), 1.0);
  std::vector<bool> present(places.size(), true);
  ParentTreeCache cache;
  const auto first = cache.get(places, present, 0, 1.0, 2.7, 3.0, 0.0);
  for (int tick = 0; tick < 50; ++tick) cache.get(places, present, 0, 1.0, 2.7, 3.0, 0.0);
  EXPECT_EQ(cache.builds(), 1u);
  EXPECT_EQ(first.parent, build_parent_tree(places, present, 0, 1.0, 2.7, 3.0, 0.0).parent);

  present[5] = false;  // a robot died
  const auto after_death = cache.get(places, present, 0, 1.0, 2.7, 3.0, 0.0);
  EXPECT_EQ(cache.builds(), 2u);
  EXPECT_EQ(after_death.parent[5], -1);
  EXPECT_EQ(after_death.parent, build_parent_tree(places, present, 0, 1.0, 2.7, 3.0, 0.0).parent);

  cache.get(places, present, 1, 1.0, 2.7, 3.0, 0.0);  // a new leader
  EXPECT_EQ(cache.builds(), 3u);
  cache.get(places, present, 1, 1.0, 2.7, 3.0, 0.5);  // another heading
  EXPECT_EQ(cache.builds(), 4u);
  EXPECT_EQ(cache.link_builds(), 1u);  // deaths, leaders and headings reuse the links
  auto moved = places;
  moved[7].x += 1e-12;  // another shape, however slightly
  cache.get(moved, present, 1, 1.0, 2.7, 3.0, 0.5);
  EXPECT_EQ(cache.builds(), 5u);
  EXPECT_EQ(cache.link_builds(), 2u);
  cache.get(moved, present, 1, 1.0, 2.7, 3.0, 0.5);
  EXPECT_EQ(cache.builds(), 5u);
  const auto& other_range = cache.get(moved, present, 1, 1.0, 2.0, 2.5, 0.5);  // other ranges: new links
  EXPECT_EQ(cache.link_builds(), 3u);
  EXPECT_EQ(other_range.parent, build_parent_tree(moved, present, 1, 1.0, 2.0, 2.5, 0.5).parent);
}

}  // namespace
}  // namespace swarmform::controller::motion
