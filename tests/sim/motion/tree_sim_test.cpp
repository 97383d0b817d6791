// The parent links form a tree rooted at the leader for every shape in shapes/, and again after removing any
// one robot (each robot of each shape in turn, killed once the formation moves). Robots start on their
// places (preformed.hpp) so that this checks the Ready and motion phases alone, whatever the formation does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

#include "common/shape.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "tests/sim/motion/preformed.hpp"
#include "tests/sim/motion/sim_checks.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::sim_motion {
namespace {

std::string repo(const std::string& rel) {
  return std::string(SWARMFORM_REPO_DIR) + "/" + rel;
}

std::vector<std::filesystem::path> shape_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(repo("shapes"))) {
    if (e.path().extension() == ".txt") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

world::Scenario open_field_with(const std::string& shape) {
  auto s =
      world::load_scenario(repo("scenarios/open_field.yaml"), {}, swarmform::controller::builtin_registry());
  s.mission.shape = load_shape_file(shape);
  return preformed_scenario(s, {0.0, 0.0});
}

class MotionTree : public testing::TestWithParam<std::string> {};

TEST_P(MotionTree, FormsATreeRootedAtTheLeaderAlsoWithoutAnyOneRobot) {
  constexpr Tick kKillTick = 130;   // ready_timeout is 40: the formation is moving
  constexpr Tick kCheckTick = 200;  // the kill + neighbour_timeout (20) + flooding, with margin
  const auto scenario = open_field_with(repo("shapes/" + GetParam()));
  const auto n = static_cast<RobotId>(scenario.robots.size());
  {
    PreformedRun run(scenario, {0.0, 0.0});
    run.run(kKillTick);
    EXPECT_EQ(tree_problem(run.world.robots()), "") << "nobody removed";
  }
  for (RobotId removed = 0; removed < n; ++removed) {
    PreformedRun run(scenario, {0.0, 0.0});
    run.run(kKillTick);
    run.kill(removed);
    run.run(kCheckTick);
    EXPECT_EQ(tree_problem(run.world.robots()), "") << "robot " << removed << " removed";
  }
}

std::vector<std::string> shape_names() {
  std::vector<std::string> names;
  for (const auto& f : shape_files()) names.push_back(f.filename().string());
  return names;
}

TEST(MotionTreeShapes, EveryShapeFileIsCovered) {
  EXPECT_GE(shape_names().size(), 6u);
}

INSTANTIATE_TEST_SUITE_P(Shapes, MotionTree, testing::ValuesIn(shape_names()),
                         [](const testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param.substr(0, param.param.find('.'));
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace swarmform::sim_motion
