// Unit tests of the Ready phase: boundary roles, leader election, the parent tree (paper III.C 'Ready').
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "robot_agent/controller/boundary.hpp"
#include "robot_agent/controller/leader_election.hpp"
#include "robot_agent/controller/parent_tree.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {
namespace {

ShapeMatrix matrix(int rows, int cols, std::vector<int> cells) {
  return ShapeMatrix{rows, cols, cells};
}

// The paper's kind of triangle, apex pointing +x (the heading):
//   row 0:  0 -1 -1
//   row 1:  1  2 -1
//   row 2:  3  4  5
//   row 3:  6  7 -1
//   row 4:  8 -1 -1
ShapeMatrix triangle() {
  return matrix(5, 3, {0, -1, -1, 1, 2, -1, 3, 4, 5, 6, 7, -1, 8, -1, -1});
}

// Every robot's neighbours (within range) as azimuths, from exact places.
std::vector<NeighbourAzimuth> neighbours_of(const std::vector<Vec2>& places, std::size_t self, double range) {
  std::vector<NeighbourAzimuth> out;
  for (std::size_t j = 0; j < places.size(); ++j) {
    if (j == self) continue;
    const Vec2 rel = vsub(places[j], places[self]);
    if (vnorm(rel) > range) continue;
    out.push_back({static_cast<RobotId>(j), vnorm(rel), std::atan2(rel.y, rel.x)});
  }
  return out;
}

TEST(Boundary, RowEndsOfATriangleAreItsLeftAndRightPerimeter) {
  const auto places = label_places(triangle(), 1.0);
  // Heading +x: left is +y, i.e. row 0 side... the matrix's rows grow along -y, so the top of the file is
  // left.
  std::map<int, BoundaryRole> roles;
  for (std::size_t i = 0; i < places.size(); ++i) {
    roles[static_cast<int>(i)] =
        classify_boundary(neighbours_of(places, i, 1.5), 0.0, 1.5, std::numbers::pi / 6);
  }
  // Column 0 is the back edge; the hypotenuse 0-2-5-7-8 faces forward. Left = +y = towards row 0.
  EXPECT_TRUE(roles[0].left);
  EXPECT_TRUE(roles[0].right == false);          // label 1 stands right below it
  EXPECT_TRUE(roles[2].left);                    // nothing above label 2 (row 0 col 1 is empty)
  EXPECT_TRUE(roles[5].left && roles[5].right);  // the apex: a row of one
  EXPECT_TRUE(roles[8].right);
  EXPECT_FALSE(roles[4].any());  // the centre
  EXPECT_FALSE(roles[3].any());  // 1 above, 6 below
}

TEST(Boundary, DiagonalNeighboursDoNotHideTheSide) {
  // A neighbour at 3pi/4 (back-left diagonal) is outside the pi/6 cone around the left.
  std::vector<NeighbourAzimuth> n{{1, 1.41, 3 * std::numbers::pi / 4}, {2, 1.0, 0.0}};
  const auto role = classify_boundary(n, 0.0, 1.5, std::numbers::pi / 6);
  EXPECT_TRUE(role.left);
  EXPECT_TRUE(role.right);
  // Rotating everything and the heading together changes nothing.
  for (auto& x : n) x.azimuth = wrap_angle(x.azimuth + 2.0);
  EXPECT_EQ(classify_boundary(n, 2.0, 1.5, std::numbers::pi / 6), role);
  // A neighbour straight to the left, but beyond the range, does not count either.
  n.push_back({3, 2.0, 2.0 + std::numbers::pi / 2});
  EXPECT_TRUE(classify_boundary(n, 2.0, 1.5, std::numbers::pi / 6).left);
  n.back().range = 1.0;
  EXPECT_FALSE(classify_boundary(n, 2.0, 1.5, std::numbers::pi / 6).left);
}

TEST(Boundary, EntryRoundTripsLabelAndRole) {
  for (int label : {0, 1, 7, 255}) {
    for (int bits = 0; bits < 4; ++bits) {
      const BoundaryRole role{(bits & 1) != 0, (bits & 2) != 0};
      const auto e = decode_boundary_entry(encode_boundary_entry(label, role));
      EXPECT_EQ(e.label, label);
      EXPECT_EQ(e.role, role);
    }
  }
}

std::vector<LeaderCandidate> triangle_candidates() {
  const auto places = label_places(triangle(), 1.0);
  std::vector<LeaderCandidate> c;
  for (std::size_t i = 0; i < places.size(); ++i) {
    // ids deliberately not equal to labels
    c.push_back({static_cast<RobotId>(100 - i), static_cast<int>(i),
                 classify_boundary(neighbours_of(places, i, 1.5), 0.0, 1.5, std::numbers::pi / 6), true});
  }
  return c;
}

TEST(LeaderElection, FurthestForwardBoundaryRobotWins) {
  const auto places = label_places(triangle(), 1.0);
  auto c = triangle_candidates();
  EXPECT_EQ(elect_leader(c, places, 0.0), RobotId{95});  // label 5, the apex at column 2
  // The order of the table does not matter (every robot holds it in its own order).
  std::reverse(c.begin(), c.end());
  EXPECT_EQ(elect_leader(c, places, 0.0), RobotId{95});
}

TEST(LeaderElection, DeadLeaderIsReplacedAndTiesGoToTheSmallerId) {
  const auto places = label_places(triangle(), 1.0);
  auto c = triangle_candidates();
  for (auto& x : c) {
    if (x.label == 5) x.alive = false;
  }
  // Labels 2 and 7 (column 1) tie along the heading; ids 98 and 93: the smaller id wins.
  EXPECT_EQ(elect_leader(c, places, 0.0), RobotId{93});
  // With no boundary robot alive, anyone may lead.
  for (auto& x : c) x.role = {};
  EXPECT_EQ(elect_leader(c, places, 0.0), RobotId{93});
  for (auto& x : c) x.alive = false;
  EXPECT_FALSE(elect_leader(c, places, 0.0).has_value());
}

// Checks the tree: every present label but the root has a parent that is present, the cost strictly decreases
// along every link (hence no cycle), and walking up from any label reaches the root.
void expect_tree(const ParentTree& t, const std::vector<bool>& present) {
  for (std::size_t v = 0; v < t.parent.size(); ++v) {
    if (!present[v]) {
      EXPECT_EQ(t.parent[v], -1);
      continue;
    }
    if (static_cast<int>(v) == t.root) {
      EXPECT_EQ(t.parent[v], -1);
      continue;
    }
    ASSERT_GE(t.parent[v], 0) << "label " << v << " has no parent";
    EXPECT_TRUE(present[static_cast<std::size_t>(t.parent[v])]);
    EXPECT_LT(t.cost[static_cast<std::size_t>(t.parent[v])], t.cost[v]);
    int at = static_cast<int>(v), steps = 0;
    while (at != t.root && steps++ <= static_cast<int>(t.parent.size()))
      at = t.parent[static_cast<std::size_t>(at)];
    EXPECT_EQ(at, t.root) << "label " << v;
  }
}

TEST(ParentTree, TriangleTreeIsRootedAtTheLeaderAndPrefersNearParentsAhead) {
  const auto places = label_places(triangle(), 1.0);
  std::vector<bool> present(places.size(), true);
  const auto t = build_parent_tree(places, present, 5, 1.0, 2.7, 3.0, 0.0);
  expect_tree(t, present);
  EXPECT_EQ(t.parent[4], 5);  // straight behind the apex
  EXPECT_EQ(t.parent[2], 5);  // diagonal: the only neighbour one hop from the root
  EXPECT_EQ(t.parent[3], 4);  // orthogonal and ahead
}

TEST(ParentTree, RemovingAnyOneRobotKeepsATreeOverTheRest) {
  // A line of 6 (a cut at every inner label) and an L: long links bridge the cut.
  const std::vector<ShapeMatrix> shapes = {matrix(1, 6, {0, 1, 2, 3, 4, 5}),
                                           matrix(3, 3, {0, -1, -1, 1, -1, -1, 2, 3, 4}), triangle()};
  for (const auto& shape : shapes) {
    const auto places = label_places(shape, 1.0);
    for (int root = 0; root < static_cast<int>(places.size()); ++root) {
      for (std::size_t dead = 0; dead < places.size(); ++dead) {
        if (static_cast<int>(dead) == root) continue;
        std::vector<bool> present(places.size(), true);
        present[dead] = false;
        const auto t = build_parent_tree(places, present, root, 1.0, 2.7, 3.0, 0.0);
        SCOPED_TRACE(testing::Message() << "root " << root << " dead " << dead);
        expect_tree(t, present);
      }
    }
  }
}

TEST(ParentTree, CycleCheckOnTheSharedTable) {
  std::map<RobotId, RobotId> parents{{1, 0}, {2, 1}, {3, 2}};
  EXPECT_TRUE(would_close_cycle(parents, 1, 3));   // 1 -> 3 -> 2 -> 1
  EXPECT_FALSE(would_close_cycle(parents, 3, 0));  // 0 is the root
  EXPECT_TRUE(would_close_cycle(parents, 4, 4));
  parents[0] = 2;  // an existing cycle 0-1-2 that 5 must not join
  EXPECT_TRUE(would_close_cycle(parents, 5, 1));
}

}  // namespace
}  // namespace swarmform::controller::motion
