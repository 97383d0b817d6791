// ProcessFaults::quiet_at (world_server/process_faults.hpp): the lockstep world lets a tick's record wait
// until the next round's packets are out only when that round's start does nothing (server.cpp,
// record_can_follow_packets). A round is not quiet when a scheduled fault starts or ends at it, or while a
// restart waits for its robot's death (it may then act at any round).
#include "world_server/process_faults.hpp"

#include <gtest/gtest.h>

#include "tests/world/test_scenarios.hpp"
#include "world_server/world/faults.hpp"

namespace {

using namespace swarmform;

world::Scenario scenario() {
  world::Scenario s = world::testing::open_scenario({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
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
