// check_mission: what an agent refuses in a mission off the wire (common/mission_check.hpp).
#include <gtest/gtest.h>

#include <limits>

#include "common/input_error.hpp"
#include "common/mission_check.hpp"

namespace {

using swarmform::InputError;
using swarmform::Mission;

Mission line_of_three() {
  Mission m;
  m.shape.rows = 1;
  m.shape.cols = 3;
  m.shape.cells = {0, 1, 2};
  return m;
}

std::string refusal(const Mission& m) {
  try {
    swarmform::check_mission(m, "<mission>");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MissionCheck, AWellFormedMissionPasses) {
  EXPECT_EQ(refusal(line_of_three()), "");
}

TEST(MissionCheck, AShapeTheParserWouldRefuseIsRefused) {
  Mission m = line_of_three();
  m.shape.cells = {0, 0, 1};
  EXPECT_NE(refusal(m).find("appears twice"), std::string::npos);
  m.shape.cells = {0, -1, 1};
  EXPECT_NE(refusal(m).find("8-connected"), std::string::npos);
  m.shape.cells = {0, 1, 7};
  EXPECT_NE(refusal(m).find("out of range"), std::string::npos);
  m.shape.cells = {0, 1, -3};
  EXPECT_NE(refusal(m).find("below -1"), std::string::npos);
  m.shape.cells = {0, 1};
  EXPECT_NE(refusal(m).find("1x3 with 2 cells"), std::string::npos);
}

TEST(MissionCheck, NumbersTheControllerDividesByOrStepsWithMustBeFiniteAndPositive) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Mission m = line_of_three();
  m.tick_rate = 0.0;
  EXPECT_NE(refusal(m).find("tick_rate"), std::string::npos);
  m = line_of_three();
  m.grid_spacing = nan;
  EXPECT_NE(refusal(m).find("grid_spacing"), std::string::npos);
  m = line_of_three();
  m.goal.x = std::numeric_limits<double>::infinity();
  EXPECT_NE(refusal(m).find("goal"), std::string::npos);
  m = line_of_three();
  m.goal_radius = -1.0;
  EXPECT_NE(refusal(m).find("goal_radius"), std::string::npos);
  m = line_of_three();
  m.params["ready_timeout"] = nan;
  EXPECT_NE(refusal(m).find("ready_timeout"), std::string::npos);
}

}  // namespace
