// ProcessFaults::quiet_at (world_server/process_faults.hpp): the lockstep world lets a tick's record wait
// until the next round's packets are out only when that round's start does nothing (server.cpp,
// record_can_follow_packets). A round is not quiet when a scheduled fault starts or ends at it, or while a
// restart waits for its robot's death (it may then act at any round).
#include "world_server/process_faults.hpp"

#include <gtest/gtest.h>

#include "robot_agent/controller/builtins.hpp"
#include "world_server/world/faults.hpp"

namespace {

using namespace swarmform;

constexpr const char* kScenario = R"(
shape: SHAPES/triangle.txt
arena: {centre: [0.0, 0.0], width: 10.0, height: 10.0, walls: true}
robots: {count: 4, region: {centre: [0.0, 0.0], width: 4.0, height: 4.0}}
behaviour: random_walk
goal: {x: 3.0, y: 0.0, radius: 0.5}
seed: 3
max_ticks: 100
)";

world::Scenario scenario() {
  std::string text = kScenario;
  text.replace(text.find("SHAPES"), 6, std::string(SWARMFORM_REPO_DIR) + "/shapes");
  world::Scenario s = world::parse_scenario_text(text, "<process_faults_test>", {},
                                                 swarmform::controller::builtin_registry());
  s.faults.push_back(world::parse_fault("stall:1@5+3"));      // starts at 5, ends at 8
  s.faults.push_back(world::parse_fault("restart:2@9"));      // robot 2 is alive at 9: waits for its death
  s.faults.push_back(world::parse_fault("ultrasonic:3@20"));  // a world fault: its event is the round's too
  return s;
}

TEST(ProcessFaultsQuiet, ARoundIsQuietOnlyWithNoFaultEdgeAndNoRestartWaiting) {
  const world::Scenario s = scenario();
  world::World w(s);
  world::RunSession session(w, world::RunOptions{"", "test"});
  server::ProcessFaults faults(s, [](RobotId) { return std::nullopt; });
  for (const Tick t : {Tick{0}, Tick{4}, Tick{6}, Tick{7}, Tick{10}, Tick{21}})
    EXPECT_TRUE(faults.quiet_at(t)) << t;
  for (const Tick t : {Tick{5}, Tick{8}, Tick{9}, Tick{20}}) EXPECT_FALSE(faults.quiet_at(t)) << t;
  faults.at_round(9, session, w);  // robot 2 alive: the restart waits
  EXPECT_FALSE(faults.quiet_at(10));
  EXPECT_FALSE(faults.quiet_at(11));
  w.kill(2);
  faults.at_round(10, session, w);  // its death seen: the restart is asked for (stdout) and done
  EXPECT_TRUE(faults.quiet_at(11));
}

}  // namespace
