// Ready phase, part 3 (paper III.C 'Ready'): "each bot with the exception of the 'leader' chooses a parent.
// The relative azimuth and distance are considered while choosing a parent. To avoid deadlock, a common
// parents table with ID of all the bot's parents is broadcast via local stigmergy."
//
// How we guarantee a tree rooted at the leader with no cycles: every robot computes the same shortest-path
// tree over the shape's labels, from the same shared inputs (the leader, the labels held by live robots as
// the stigmergy says, the shape every robot was given), and takes as its parent the robot that holds its
// label's parent label. Along a shortest-path tree the path cost strictly decreases towards the root, so no
// choice can close a cycle. Links: two labels whose places are 8-neighbours in the grid (<= 1.5 grid
// spacings) cost 1; labels further apart but within `link_range` (less than the radio range) cost
// `kLongLinkCost`, so longer links are used only when a dead robot cuts the grid graph (a line, a ring); and
// labels up to `far_range` (the radio range) apart cost `kFarLinkCost`, a last resort (a V without one of
// its arm's robots).
// Among equally short paths the parent is chosen by distance (an orthogonal neighbour before a diagonal
// one), then by relative azimuth (the one most ahead along the heading, so that robots trail their parent),
// then by the smaller label. A dead robot is dropped from the inputs and every robot recomputes: its
// children re-parent, still acyclic. `would_close_cycle` checks a choice against the shared parents table
// while views of the table differ for a few ticks.
#pragma once

#include <limits>
#include <map>
#include <numbers>
#include <vector>

#include "common/shape.hpp"
#include "common/types.hpp"

namespace swarmform::controller::motion {

inline constexpr int kLongLinkCost = 4;
inline constexpr int kFarLinkCost = 16;
inline constexpr int kUnreachable = std::numeric_limits<int>::max();

// Each label's place in the arena frame relative to the matrix's top-left cell: with `shape_heading` = pi/2
// (the default of the `shape_heading` parameter) column along +x and row along -y, `spacing` apart
// (common/shape.hpp); otherwise that grid turned so that row 0 lies towards `shape_heading`. By label.
std::vector<Vec2> label_places(const ShapeMatrix& shape, double spacing,
                               double shape_heading = std::numbers::pi / 2);

struct ParentTree {
  int root = -1;            // the leader's label
  std::vector<int> parent;  // by label: its parent label; -1 for the root, absent or unreachable labels
  std::vector<int> cost;    // by label: path cost from the root; kUnreachable if absent or cut off
};

// Every label's links (the labels within `far_range`, with the cost and length of the link), in ascending
// label order. The places are bucketed in square cells of side the longest link, so each label looks only at
// the 3 x 3 cells about its own: O(L k) for k labels within reach, not every pair (a reach that is zero or
// not finite falls back to one cell: every pair). They depend on the shape alone, not on who is alive.
struct LabelLink {
  std::size_t to;
  int cost;
  double d;
};
using LabelLinks = std::vector<std::vector<LabelLink>>;
LabelLinks label_links(const std::vector<Vec2>& places, double spacing, double link_range, double far_range);

// `present[label]`: the label is held by a live robot. `heading`: common heading (rad, arena frame).
ParentTree build_parent_tree(const std::vector<Vec2>& places, const std::vector<bool>& present, int root,
                             double spacing, double link_range, double far_range, double heading);
// The same over links already found (label_links of the same places and ranges): O(L k log L).
ParentTree build_parent_tree(const LabelLinks& links, const std::vector<Vec2>& places,
                             const std::vector<bool>& present, int root, double heading);

// `label`'s parent in build_parent_tree's tree (-1 for the root, an absent or an unreachable label), without
// the rest of the tree: Dijkstra from the root stops as soon as `label` is settled (every label on one of its
// shortest paths costs less, so is settled by then), and only `label`'s parent is chosen, as
// build_parent_tree chooses it. `cost`: working space (resized here). A robot needs only its own label's
// parent.
int parent_in_tree(const LabelLinks& links, const std::vector<Vec2>& places, const std::vector<bool>& present,
                   int root, double heading, int label, std::vector<int>& cost);

// build_parent_tree, rebuilt only when one of its inputs differs from the last call's (compared in full, so
// the tree is exactly the one build_parent_tree would give). Each robot asks for the tree every tick of Ready
// and Motion; the links (label_links) change only with the shape and ranges, so they are found once; the tree
// is rebuilt over them when the labels live robots hold, the leader's label or the heading change (while the
// views of the stigmergy settle after Ready, or after a death), without a single distance computed.
class ParentTreeCache {
 public:
  const ParentTree& get(const std::vector<Vec2>& places, const std::vector<bool>& present, int root,
                        double spacing, double link_range, double far_range, double heading);
  // get(...).parent[label] (-1 when `label` is out of range), found by parent_in_tree and kept while the
  // inputs and `label` stay the same: in a large shape whose members still learn of each other, `present`
  // changes nearly every tick, and the whole tree cost O(L k log L) a robot each time.
  int parent(const std::vector<Vec2>& places, const std::vector<bool>& present, int root, double spacing,
             double link_range, double far_range, double heading, int label);
  // How many times get() has built the tree, and found the links (for tests).
  std::size_t builds() const { return builds_; }
  std::size_t link_builds() const { return link_builds_; }

 private:
  bool has_links_ = false, has_tree_ = false;
  std::vector<Vec2> places_;
  double spacing_ = 0.0, link_range_ = 0.0, far_range_ = 0.0;
  LabelLinks links_;
  std::vector<bool> present_;
  int root_ = -1;
  double heading_ = 0.0;
  ParentTree tree_;
  std::size_t builds_ = 0, link_builds_ = 0;
  // parent()'s answer and the label it was for (the other inputs are the members above).
  bool has_parent_ = false;
  int label_ = -1, parent_ = -1;
  std::vector<int> cost_;
  bool same_links(const std::vector<Vec2>& places, double spacing, double link_range, double far_range) const;
  void find_links(const std::vector<Vec2>& places, double spacing, double link_range, double far_range);
};

// True when `self` taking `candidate` as its parent would close a cycle in `parents` (id -> parent id; ids
// absent from the map have no parent): i.e. when walking up from `candidate` reaches `self`.
bool would_close_cycle(const std::map<RobotId, RobotId>& parents, RobotId self, RobotId candidate);

}  // namespace swarmform::controller::motion
