// Every shape in shapes/: the Ready phase's decisions computed the way each robot computes them (boundary
// from the neighbours' azimuths, leader from the shared roles, parents from the shared tree) give a tree
// rooted at the leader, with every robot and after removing any one robot (the dead leader replaced by the
// same election). Headings: the default (pi/2) and towards +x (the paper's run).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "common/shape.hpp"
#include "robot_agent/controller/boundary.hpp"
#include "robot_agent/controller/leader_election.hpp"
#include "robot_agent/controller/parent_tree.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {
namespace {

std::vector<std::filesystem::path> shape_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(SWARMFORM_SHAPES_DIR)) {
    if (e.path().extension() == ".txt") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(EveryShape, ParentLinksFormATreeRootedAtTheLeaderAlsoWithoutAnyOneRobot) {
  const auto files = shape_files();
  ASSERT_GE(files.size(), 6u);
  for (const auto& file : files) {
    const ShapeMatrix shape = load_shape_file(file.string());
    for (const double heading : {std::numbers::pi / 2, 0.0}) {
      const auto places = label_places(shape, 1.0, heading);
      const std::size_t n = places.size();
      // Ids are labels shifted, so that an id never equals its label by accident.
      auto id_of = [](std::size_t label) { return static_cast<RobotId>(label + 10); };
      std::vector<LeaderCandidate> candidates;
      for (std::size_t i = 0; i < n; ++i) {
        std::vector<NeighbourAzimuth> around;
        for (std::size_t j = 0; j < n; ++j) {
          const Vec2 rel = vsub(places[j], places[i]);
          if (j != i && vnorm(rel) <= 3.0) around.push_back({id_of(j), vnorm(rel), std::atan2(rel.y, rel.x)});
        }
        candidates.push_back({id_of(i), static_cast<int>(i),
                              classify_boundary(around, heading, 1.5, std::numbers::pi / 6), true});
      }
      for (std::size_t removed = 0; removed <= n; ++removed) {  // removed == n: nobody removed
        SCOPED_TRACE(testing::Message()
                     << file.filename() << " heading " << heading << " removed " << removed);
        auto c = candidates;
        std::vector<bool> present(n, true);
        if (removed < n) {
          c[removed].alive = false;
          present[removed] = false;
        }
        const auto leader = elect_leader(c, places, heading);
        ASSERT_TRUE(leader.has_value());
        const int root = static_cast<int>(*leader) - 10;
        ASSERT_NE(static_cast<std::size_t>(root), removed);
        const auto tree = build_parent_tree(places, present, root, 1.0, 2.7, 3.0, heading);
        for (std::size_t v = 0; v < n; ++v) {
          if (!present[v] || static_cast<int>(v) == root) continue;
          int at = static_cast<int>(v);
          std::size_t steps = 0;
          while (at != root && at >= 0 && steps++ <= n) {
            const int next = tree.parent[static_cast<std::size_t>(at)];
            ASSERT_GE(next, 0) << "label " << at << " has no parent";
            ASSERT_TRUE(present[static_cast<std::size_t>(next)]);
            ASSERT_LE(
                vnorm(vsub(places[static_cast<std::size_t>(next)], places[static_cast<std::size_t>(at)])),
                3.0);
            at = next;
          }
          EXPECT_EQ(at, root) << "label " << v << " does not reach the leader";
        }
      }
    }
  }
}

}  // namespace
}  // namespace swarmform::controller::motion
