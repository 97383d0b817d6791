// FaultSchedule (world_server/run/fault_schedule.hpp), the kill and fault stage both front ends run: what it
// asks the front end to do at each round, in which order, and when a round is quiet (the lockstep world lets
// a tick's record wait until the next round's packets are out only then: server.cpp,
// record_can_follow_packets).
#include "world_server/run/fault_schedule.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/world/test_scenarios.hpp"
#include "world_server/world/faults.hpp"

namespace {

using namespace swarmform;

world::Scenario scenario() {
  world::Scenario s = world::testing::open_scenario({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  s.kills.push_back({0, 12});
  s.faults.push_back(world::parse_fault("stall:1@5+3"));      // starts at 5, ends at 8
  s.faults.push_back(world::parse_fault("restart:2@9"));      // robot 2 is alive at 9: waits for its death
  s.faults.push_back(world::parse_fault("ultrasonic:3@20"));  // a world fault: its event is the round's too
  return s;
}

// Says what was asked of it, in order; a stall is held by the schedule, a restart waits while robot 2 lives.
struct Journal : world::FaultActions {
  explicit Journal(const world::World& w) : world(w) {}
  void kill(RobotId id) override { said.push_back("kill " + std::to_string(id)); }
  Stall start_stall(const world::Fault& f) override {
    said.push_back("stall " + std::to_string(*f.robot));
    return {false, "held"};
  }
  std::string end_stall(const world::Fault& f, bool stopped) override {
    said.push_back("end " + std::to_string(*f.robot) + (stopped ? " stopped" : " held"));
    return "released";
  }
  std::optional<std::string> restart(const world::Fault& f, Tick t) override {
    said.push_back("restart " + std::to_string(*f.robot) + "@" + std::to_string(t));
    if (world.alive(*f.robot)) return std::nullopt;
    return "done";
  }
  const world::World& world;
  std::vector<std::string> said;
};

TEST(FaultSchedule, ARoundIsQuietOnlyWithNoKillNoFaultEdgeAndNoRestartWaiting) {
  const world::Scenario s = scenario();
  world::World w(s);
  world::RunSession session(w, world::RunOptions{"", "test"});
  world::FaultSchedule schedule(s);
  Journal j(w);
  // A kill is due from its tick until a round did it (12, 21).
  for (const Tick t : {Tick{0}, Tick{4}, Tick{6}, Tick{7}, Tick{10}, Tick{11}})
    EXPECT_TRUE(schedule.quiet_at(t)) << t;
  for (const Tick t : {Tick{5}, Tick{8}, Tick{9}, Tick{12}, Tick{20}})
    EXPECT_FALSE(schedule.quiet_at(t)) << t;
  schedule.at_round(9, session, j);  // robot 2 alive: the restart waits
  EXPECT_FALSE(schedule.quiet_at(10));
  EXPECT_FALSE(schedule.quiet_at(11));
  w.kill(2);
  schedule.at_round(10, session, j);  // its death seen: done
  EXPECT_TRUE(schedule.quiet_at(11));
  schedule.add_kill(11, 3);  // a viewer's kill
  EXPECT_FALSE(schedule.quiet_at(11));
  schedule.at_round(11, session, j);
  schedule.at_round(12, session, j);
  EXPECT_TRUE(schedule.quiet_at(13));
  EXPECT_EQ(j.said.back(), "kill 0");
}

TEST(FaultSchedule, KillsThenStallsThenRestartsEachOnceAtItsTickAndAStallHoldsItsRobotForItsTicks) {
  const world::Scenario s = scenario();
  world::World w(s);
  world::RunSession session(w, world::RunOptions{"", "test"});
  world::FaultSchedule schedule(s);
  Journal j(w);
  std::vector<Tick> held;
  for (Tick t = 0; t < 14; ++t) {
    if (t == 10) w.kill(2);
    schedule.at_round(t, session, j);
    if (schedule.held(1)) held.push_back(t);
    EXPECT_FALSE(schedule.held(0) || schedule.held(2) || schedule.held(3)) << t;
  }
  EXPECT_EQ(held, (std::vector<Tick>{5, 6, 7}));
  EXPECT_EQ(j.said,
            (std::vector<std::string>{"stall 1", "end 1 held", "restart 2@9", "restart 2@10", "kill 0"}));
}

TEST(FaultSchedule, ARestartStillWaitingAtTheEndIsRecordedAsNotDone) {
  const world::Scenario s = scenario();
  world::World w(s);
  world::RunSession session(w, world::RunOptions{"", "test"});
  world::FaultSchedule schedule(s);
  Journal j(w);
  schedule.at_round(9, session, j);
  EXPECT_FALSE(schedule.quiet_at(10));
  schedule.finish(session);
  EXPECT_TRUE(schedule.quiet_at(10));
}

}  // namespace
