// Robot groups in a scenario (docs/scenario-format.md "Groups"): a mixed swarm parses into groups with
// contiguous global ids, each with its own behaviour, parameters and region; every bad group is refused at
// its line; the overrides do what the page says.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/input_error.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "tests/world/scenario_text.hpp"
#include "world_server/world/robot_groups.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {
namespace {

using scenario_text::expect_rejected;
using scenario_text::kOrigin;
using scenario_text::kRepo;
using scenario_text::parse;

// Two groups: line 3 is the first group's item, 6 the second's.
const std::string kTwoGroups = R"(shape: letter_t.txt
groups:
  - name: shapers
    behaviour: {name: paper, params: {shape_heading: 0.0}}
    robots: {count: 8, region: {centre: [0.0, 0.0], width: 2.0, height: 2.0}}
  - name: movers
    behaviour: random_walk
    robots: {count: 4, region: {centre: [7.0, -3.5], width: 3.0, height: 2.0}}
)";

TEST(ScenarioGroups, TheMixedSwarmExampleHasTwoGroupsWithContiguousIdsAndTheirOwnBehaviours) {
  const Scenario s =
      load_scenario(kRepo + "/scenarios/mixed_swarm.yaml", {}, swarmform::controller::builtin_registry());
  ASSERT_EQ(s.groups.size(), 2u);
  ASSERT_EQ(s.robots.size(), 12u);
  EXPECT_EQ(s.groups[0].name, "shapers");
  EXPECT_EQ(s.groups[0].first_id, 0u);
  EXPECT_EQ(s.groups[0].count, 8u);
  EXPECT_EQ(s.groups[0].mission.behaviour, "paper");
  EXPECT_EQ(s.groups[0].mission.params.at("shape_heading"), 0.0);
  EXPECT_EQ(s.groups[1].name, "movers");
  EXPECT_EQ(s.groups[1].first_id, 8u);
  EXPECT_EQ(s.groups[1].count, 4u);
  EXPECT_EQ(s.groups[1].mission.behaviour, "random_walk");
  EXPECT_TRUE(s.groups[1].mission.params.empty());
  // The paper group's shape has as many labels as it has robots.
  EXPECT_EQ(s.mission.shape.label_count(), 8);
  // The run-wide fields are every group's; the scenario's own behaviour is the first group's.
  EXPECT_EQ(s.behaviour->name, "paper");
  EXPECT_EQ(s.mission.behaviour, "paper");
  for (const RobotGroup& g : s.groups) {
    EXPECT_EQ(g.mission.shape.cells, s.mission.shape.cells);
    EXPECT_EQ(g.mission.goal.x, 10.0);
    EXPECT_EQ(g.mission.seed, s.seed);
    EXPECT_EQ(g.mission.comm_range, s.comm_range);
  }
  // Each robot's own group.
  EXPECT_EQ(group_of(s, 0), 0u);
  EXPECT_EQ(group_of(s, 7), 0u);
  EXPECT_EQ(group_of(s, 8), 1u);
  EXPECT_EQ(group_of(s, 11), 1u);
  EXPECT_EQ(behaviour_of(s, 9)->name, "random_walk");
  EXPECT_EQ(mission_of(s, 3).behaviour, "paper");
}

TEST(ScenarioGroups, EachGroupIsPlacedInItsRegionClearOfEveryOtherRobotAndTheSameFromTheSameSeed) {
  const Scenario a = parse(kTwoGroups);
  const Scenario b = parse(kTwoGroups);
  ASSERT_EQ(a.robots.size(), 12u);
  for (std::size_t i = 0; i < a.robots.size(); ++i) {
    EXPECT_EQ(a.robots[i].x, b.robots[i].x);
    EXPECT_EQ(a.robots[i].y, b.robots[i].y);
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_GE(std::hypot(a.robots[i].x - a.robots[j].x, a.robots[i].y - a.robots[j].y), 0.4)
          << i << " " << j;
    }
  }
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_LE(std::abs(a.robots[i].x), 1.0);
    EXPECT_LE(std::abs(a.robots[i].y), 1.0);
  }
  for (std::size_t i = 8; i < 12; ++i) {
    EXPECT_LE(std::abs(a.robots[i].x - 7.0), 1.5);
    EXPECT_LE(std::abs(a.robots[i].y + 3.5), 1.0);
  }
}

TEST(ScenarioGroups, OverlappingRegionsStillKeepTheGroupsApart) {
  const Scenario s = parse(R"(groups:
  - {name: a, behaviour: random_walk, robots: {count: 6, region: {centre: [0.0, 0.0], width: 2.0, height: 2.0}}}
  - {name: b, behaviour: random_walk, robots: {count: 6, region: {centre: [0.5, 0.0], width: 2.0, height: 2.0}}}
)");
  ASSERT_EQ(s.robots.size(), 12u);
  for (std::size_t i = 6; i < 12; ++i) {
    for (std::size_t j = 0; j < 6; ++j) {
      EXPECT_GE(std::hypot(s.robots[i].x - s.robots[j].x, s.robots[i].y - s.robots[j].y), 0.4);
    }
  }
}

TEST(ScenarioGroups, OneGroupIsPlacedExactlyAsTheTopLevelRobotsAre) {
  // Group 0 draws from the stream a scenario without groups uses: the same start from the same seed.
  const Scenario grouped = parse(R"(shape: triangle.txt
groups:
  - {name: only, behaviour: paper, robots: {count: 9, region: {centre: [0.0, 0.0], width: 3.0, height: 3.0}}}
)");
  const Scenario plain = parse(R"(shape: triangle.txt
behaviour: paper
robots: {count: 9, region: {centre: [0.0, 0.0], width: 3.0, height: 3.0}}
)");
  ASSERT_EQ(grouped.robots.size(), plain.robots.size());
  for (std::size_t i = 0; i < plain.robots.size(); ++i) {
    EXPECT_EQ(grouped.robots[i].x, plain.robots[i].x);
    EXPECT_EQ(grouped.robots[i].y, plain.robots[i].y);
    EXPECT_EQ(grouped.robots[i].theta, plain.robots[i].theta);
  }
  EXPECT_TRUE(plain.groups.empty());
}

TEST(ScenarioGroups, ListedPosesAreCheckedAgainstTheEarlierGroupsRobots) {
  expect_rejected(R"(groups:
  - {name: a, behaviour: random_walk, robots: {poses: [[0.0, 0.0], [1.0, 0.0]]}}
  - name: b
    behaviour: random_walk
    robots:
      poses:
        - [1.05, 0.0]
)",
                  7, "robot 2 overlaps robot 1");
}

TEST(ScenarioGroups, EveryBadGroupIsRefusedAtItsLine) {
  // groups beside a top-level robots:, behaviour: or controller:
  expect_rejected("shape: letter_t.txt\nrobots: {count: 3}\n" + kTwoGroups.substr(kTwoGroups.find("groups:")),
                  2, "give groups: or a top-level robots:, not both");
  expect_rejected("behaviour: paper\n" + kTwoGroups, 1, "give groups: or a top-level behaviour:, not both");
  expect_rejected("controller: {k_o: 1.0}\n" + kTwoGroups, 1, "give groups: or a top-level controller:");
  // The list itself.
  expect_rejected("groups: []\n", 1, "groups: expected a non-empty list");
  expect_rejected("groups: {name: a}\n", 1, "groups: expected a non-empty list");
  // An item's keys.
  expect_rejected("groups:\n  - {behaviour: random_walk, robots: {count: 2}}\n", 2,
                  "groups[0]: missing 'name'");
  expect_rejected("groups:\n  - {name: a, robots: {count: 2}}\n", 2, "groups[0]: missing 'behaviour'");
  expect_rejected("groups:\n  - {name: a, behaviour: random_walk}\n", 2, "groups[0]: missing 'robots'");
  expect_rejected("groups:\n  - {name: a, behaviour: random_walk, robots: {count: 2}, colour: red}\n", 2,
                  "colour: unknown key");
  expect_rejected("groups:\n  - name: Big\n    behaviour: random_walk\n    robots: {count: 2}\n", 2,
                  "groups[0].name: 'Big' is not lower_case");
  expect_rejected(R"(groups:
  - {name: a, behaviour: random_walk, robots: {count: 2}}
  - name: a
    behaviour: random_walk
    robots: {count: 2, region: {centre: [5.0, 0.0], width: 2.0, height: 2.0}}
)",
                  3, "groups[1].name: 'a' is given twice");
  // Its behaviour and parameters, checked against its own behaviour's table.
  expect_rejected(R"(groups:
  - {name: a, behaviour: random_walk, robots: {count: 2}}
  - name: b
    behaviour: wobbler
    robots: {count: 2}
)",
                  4, "groups[1].behaviour: unknown behaviour 'wobbler'");
  expect_rejected(R"(shape: letter_t.txt
groups:
  - name: a
    behaviour:
      name: paper
      params:
        k_wobble: 1.0
    robots: {count: 8}
)",
                  7, "groups[0].behaviour.params.k_wobble");
  // random_walk has no parameters: a paper one given to it is refused there, not taken for the paper's.
  expect_rejected(R"(shape: letter_t.txt
groups:
  - {name: a, behaviour: paper, robots: {count: 8}}
  - name: b
    behaviour: {name: random_walk, params: {shape_heading: 0.0}}
    robots: {count: 2, region: {centre: [8.0, 0.0], width: 2.0, height: 2.0}}
)",
                  5, "groups[1].behaviour.params.shape_heading");
  // Its robots.
  expect_rejected(
      "groups:\n  - name: a\n    behaviour: random_walk\n    robots: {region: {centre: [0, 0], "
      "width: 2, height: 2}}\n",
      4, "groups[0].robots: give groups[0].robots.count or groups[0].robots.poses");
  expect_rejected("groups:\n  - name: a\n    behaviour: random_walk\n    robots: {count: 0}\n", 4,
                  "groups[0].robots.count: must be in [1, 100000]");
  expect_rejected(
      "groups:\n  - name: a\n    behaviour: random_walk\n    robots:\n      count: 50\n      region: "
      "{centre: [0, 0], width: 1, height: 1}\n",
      5, "groups[0].robots: cannot place 50 robots");
}

TEST(ScenarioGroups, AShapeFormingGroupWithoutACountHasTheShapesLabelCount) {
  const Scenario s = parse(R"(shape: letter_t.txt
groups:
  - {name: a, behaviour: paper, robots: {region: {centre: [0.0, 0.0], width: 2.0, height: 2.0}}}
  - {name: b, behaviour: random_walk, robots: {count: 3, region: {centre: [8.0, 0.0], width: 2.0, height: 2.0}}}
)");
  EXPECT_EQ(s.groups[0].count, 8u);
  EXPECT_EQ(s.groups[1].first_id, 8u);
}

TEST(ScenarioGroups, ParamOverridesGoToTheFirstGroupOrTheNamedOne) {
  ScenarioOverrides ov;
  ov.params = {{"shape_heading=0.5", "shape_heading", 0.5}};
  EXPECT_EQ(parse(kTwoGroups, ov).groups[0].mission.params.at("shape_heading"), 0.5);
  ov.params = {{"shapers.shape_heading=0.25", "shapers.shape_heading", 0.25}};
  const Scenario s = parse(kTwoGroups, ov);
  EXPECT_EQ(s.groups[0].mission.params.at("shape_heading"), 0.25);
  EXPECT_EQ(s.mission.params.at("shape_heading"), 0.25);  // the first group's is the scenario's
  ov.params = {{"walkers.k=1", "walkers.k", 1.0}};
  expect_rejected(kTwoGroups, 0, "--param walkers.k=1: no robot group 'walkers' (groups: shapers, movers)",
                  ov, "command line");
  ov.params = {{"movers.shape_heading=1", "movers.shape_heading", 1.0}};
  expect_rejected(kTwoGroups, 0, "--param movers.shape_heading=1", ov, "command line");
  // GROUP.NAME in a scenario without groups.
  ScenarioOverrides dotted;
  dotted.params = {{"a.b=1", "a.b", 1.0}};
  expect_rejected("shape: triangle.txt\n", 0,
                  "GROUP.NAME names a robot group, and this scenario has no groups:", dotted, "command line");
}

TEST(ScenarioGroups, RobotsAndBehaviourOverridesAreRefusedNamingWhy) {
  ScenarioOverrides ov;
  ov.robots = 20;
  expect_rejected(kTwoGroups, 0, "--robots: the scenario has groups:", ov, "command line");
  ScenarioOverrides ob;
  ob.behaviour = "random_walk";
  expect_rejected(kTwoGroups, 0, "--behaviour: the scenario has groups:", ob, "command line");
}

}  // namespace
}  // namespace swarmform::world
