// robots.csv's behaviour columns in a mixed swarm (docs/recording-format.md "Robot groups"): the union of the
// groups' telemetry columns in group order, each robot's values under its own behaviour's names and the
// columns its behaviour lacks left empty.
#include "world_server/run/telemetry_columns.hpp"

#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "world_server/run/recorder.hpp"

namespace swarmform::world {
namespace {

namespace fs = std::filesystem;

constexpr std::array kFirstColumns = {behaviour::TelemetryColumn{"a", ""},
                                      behaviour::TelemetryColumn{"shared", ""}};
constexpr std::array kSecondColumns = {behaviour::TelemetryColumn{"shared", ""},
                                       behaviour::TelemetryColumn{"b", ""}};

behaviour::Descriptor with_columns(std::span<const behaviour::TelemetryColumn> columns) {
  behaviour::Descriptor d;
  d.name = "x";
  d.telemetry = columns;
  return d;
}

TEST(TelemetryColumns, AMixedSwarmRecordsTheUnionEachRobotUnderItsOwnNames) {
  const behaviour::Descriptor first = with_columns(kFirstColumns), second = with_columns(kSecondColumns);
  Scenario s;
  s.robots.resize(3);
  s.behaviour = &first;
  s.groups = {RobotGroup{"one", 0, 2, {}, &first}, RobotGroup{"two", 2, 1, {}, &second}};
  const TelemetryColumns c = telemetry_columns(s);
  EXPECT_EQ(c.names, (std::vector<std::string>{"a", "shared", "b"}));
  ASSERT_EQ(c.of_robot.size(), 3u);
  EXPECT_EQ(c.of_robot[0], (std::vector<int>{0, 1, -1}));
  EXPECT_EQ(c.of_robot[2], (std::vector<int>{-1, 0, 1}));

  const fs::path dir = fs::temp_directory_path() / ("swarmform-columns-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  {
    RecordingWriter writer(dir.string(), c.names, 0, c.of_robot);
    std::vector<RobotTruth> robots(3);
    for (RobotId i = 0; i < 3; ++i) robots[i].id = i;
    robots[0].telemetry.extra = {1.5, 2.5};  // a, shared
    robots[2].telemetry.extra = {3.5, 4.5};  // shared, b
    writer.write_rows(0, robots);
  }
  std::ifstream in(dir / "robots.csv");
  std::string header, row0, row1, row2;
  std::getline(in, header);
  std::getline(in, row0);
  std::getline(in, row1);
  std::getline(in, row2);
  EXPECT_NE(header.find(",leds,a,shared,b"), std::string::npos) << header;
  EXPECT_EQ(row0.substr(row0.size() - 9), ",1.5,2.5,") << row0;
  EXPECT_EQ(row1.substr(row1.size() - 3), ",,,") << row1;  // nothing said yet: every column empty
  EXPECT_EQ(row2.substr(row2.size() - 9), ",,3.5,4.5") << row2;
  fs::remove_all(dir);
}

TEST(TelemetryColumns, WithoutGroupsTheBehavioursColumnsAsTheyAre) {
  const behaviour::Descriptor first = with_columns(kFirstColumns);
  Scenario s;
  s.robots.resize(2);
  s.behaviour = &first;
  const TelemetryColumns c = telemetry_columns(s);
  EXPECT_EQ(c.names, (std::vector<std::string>{"a", "shared"}));
  EXPECT_EQ(c.of_robot, (std::vector<std::vector<int>>(2, std::vector<int>{0, 1})));
}

// The known columns (label, parent, leader, net_force) are robots.csv's own: not among the behaviour's
// columns, and found where the behaviour puts them.
TEST(TelemetryColumns, TheKnownColumnsAreNotRecordedTwice) {
  static constexpr std::array kWithKnown = {behaviour::TelemetryColumn{"leader", ""},
                                            behaviour::TelemetryColumn{"a", ""},
                                            behaviour::TelemetryColumn{"net_force", ""}};
  const behaviour::Descriptor d = with_columns(kWithKnown);
  Scenario s;
  s.robots.resize(2);
  s.behaviour = &d;
  const TelemetryColumns c = telemetry_columns(s);
  EXPECT_EQ(c.names, std::vector<std::string>{"a"});
  EXPECT_EQ(c.of_robot, (std::vector<std::vector<int>>(2, std::vector<int>{1})));
  ASSERT_EQ(c.known.size(), 2U);
  EXPECT_EQ(c.known[1].leader, 0);
  EXPECT_EQ(c.known[1].net_force, 2);
  EXPECT_EQ(c.known[1].label, -1);
}

}  // namespace
}  // namespace swarmform::world
