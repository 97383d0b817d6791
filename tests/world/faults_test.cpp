// Scheduled faults (world/faults.hpp): the format's parser and checks, the scenario's `faults:` and --fault
// with file:line or flag errors, and each world fault's effect on the World: a failed wheel does not turn,
// a failed sensor reads its maximum, a loss burst delivers nothing, a range cut hears only nearer robots.
#include "world_server/world/faults.hpp"
#include "robot_agent/controller/builtins.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/input_error.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

using testing::open_scenario;

const std::string kRepo = SWARMFORM_REPO_DIR;
const std::string kOrigin = kRepo + "/scenarios/inline-faults.yaml";

// ---- the format
// --------------------------------------------------------------------------------------------

TEST(FaultFormat, ReadsEveryKind) {
  const Fault stall = parse_fault("stall:3@200+30");
  EXPECT_EQ(stall.kind, FaultKind::Stall);
  EXPECT_EQ(stall.robot, RobotId{3});
  EXPECT_EQ(stall.tick, 200u);
  EXPECT_EQ(stall.duration, Tick{30});
  EXPECT_TRUE(stall.active_at(200));
  EXPECT_TRUE(stall.active_at(229));
  EXPECT_FALSE(stall.active_at(230));
  EXPECT_FALSE(stall.active_at(199));
  EXPECT_FALSE(stall.in_world());

  EXPECT_EQ(parse_fault("kill:0@5").kind, FaultKind::Kill);
  EXPECT_EQ(parse_fault("restart:7@900").kind, FaultKind::Restart);

  const Fault all_sensors = parse_fault("ultrasonic:4@150");
  EXPECT_EQ(all_sensors.part, -1);
  EXPECT_FALSE(all_sensors.duration.has_value());
  EXPECT_TRUE(all_sensors.active_at(1000000));
  EXPECT_EQ(parse_fault("ultrasonic:4/2@150+5").part, 2);

  EXPECT_EQ(parse_fault("wheel:1/left@120").part, 0);
  EXPECT_EQ(parse_fault("wheel:1/right@120").part, 1);

  const Fault loss = parse_fault("loss:all@400+20");
  EXPECT_EQ(loss.kind, FaultKind::Loss);
  EXPECT_FALSE(loss.robot.has_value());
  EXPECT_TRUE(loss.in_world());

  const Fault range = parse_fault("range:2@500+10=1.5");
  EXPECT_EQ(range.kind, FaultKind::Range);
  EXPECT_EQ(range.robot, RobotId{2});
  EXPECT_EQ(range.duration, Tick{10});
  EXPECT_DOUBLE_EQ(range.value, 1.5);
  EXPECT_EQ(range.text, "range:2@500+10=1.5");
}

// Each bad text is refused with a message that names what is wrong.
TEST(FaultFormat, RefusesBadTextsSayingWhatIsWrong) {
  const std::pair<const char*, const char*> cases[] = {
      {"stall:3", "expected KIND:TARGET@TICK"},
      {"3@200", "expected KIND:TARGET@TICK"},
      {"freeze:3@200", "unknown kind 'freeze' (known: kill, stall, restart"},
      {"stall:3@200", "a stall needs its duration"},
      {"kill:3@200+5", "kill takes no duration"},
      {"restart:3@200+5", "restart takes no duration"},
      {"stall:all@200+5", "'all' is a target of loss and range only"},
      {"loss:x@1", "the target 'x' is not a robot id or all"},
      {"stall:-1@1+1", "the target '-1' is not a robot id"},
      {"wheel:1@5", "which wheel"},
      {"wheel:1/middle@5", "the wheel 'middle' is not left or right"},
      {"ultrasonic:1/5@5", "the sensor '5' is not one of 0..4"},
      {"loss:1/2@5", "only ultrasonic (/SENSOR) and wheel"},
      {"loss:1@x", "the tick 'x' is not an integer"},
      {"loss:1@2000000000", "the tick '2000000000' is not an integer in [0, 1000000000]"},
      {"loss:1@5+0", "the duration '+0' is not a tick count >= 1"},
      {"loss:1@5+", "the duration '+' is not a tick count >= 1"},
      {"loss:1@5=2", "=VALUE belongs to range only"},
      {"range:all@5", "a range cut needs the new range"},
      {"range:all@5=-1", "the range '-1' is not a positive number"},
      {"range:all@5=nan", "the range 'nan' is not a positive number"},
      {"range:all@5=1+3", "write +TICKS before =VALUE"},
  };
  for (const auto& [text, what] : cases) {
    try {
      parse_fault(text);
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const FaultSyntaxError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << text << ": " << e.what();
    }
  }
}

// ---- the scenario and the flag
// -----------------------------------------------------------------------------

Scenario parse(const std::string& text, const ScenarioOverrides& ov = {}) {
  return parse_scenario_text(text, kOrigin, ov, swarmform::controller::builtin_registry());
}

void expect_rejected(const std::string& text, int line, const std::string& what,
                     const ScenarioOverrides& ov = {}) {
  try {
    parse(text, ov);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

const std::string kHead = "shape: triangle.txt\nrobots: {count: 9}\n";

TEST(ScenarioFaults, FileAndFlagFaultsAreLoadedKillsJoinTheKills) {
  ScenarioOverrides ov;
  ov.faults = {"loss:all@30+5", "kill:4@10"};
  const Scenario s = parse(kHead +
                               "faults:\n"
                               "  - stall:3@200+30\n"
                               "  - kill:2@100\n"
                               "  - restart:2@300\n"
                               "  - wheel:1/left@120\n",
                           ov);
  ASSERT_EQ(s.faults.size(), 4u);  // stall, restart, wheel, then the flag's loss
  EXPECT_EQ(s.faults[0].kind, FaultKind::Stall);
  EXPECT_EQ(s.faults[1].kind, FaultKind::Restart);
  EXPECT_EQ(s.faults[2].kind, FaultKind::Wheel);
  EXPECT_EQ(s.faults[3].kind, FaultKind::Loss);
  ASSERT_EQ(s.kills.size(), 2u);
  EXPECT_EQ(s.kills[0].id, 2u);
  EXPECT_EQ(s.kills[0].tick, 100u);
  EXPECT_EQ(s.kills[1].id, 4u);
}

TEST(ScenarioFaults, BadFaultsInTheFileNameTheirLine) {
  expect_rejected(kHead + "faults: stall:3@200+30\n", 3, "expected a list of faults");
  expect_rejected(kHead + "faults:\n  - {kind: stall}\n", 4, "faults[0]: expected a fault text");
  expect_rejected(kHead + "faults:\n  - loss:all@1\n  - stall:3@200\n", 5,
                  "faults[1]: 'stall:3@200': a stall needs its duration");
  expect_rejected(kHead + "faults:\n  - stall:9@200+5\n", 4,
                  "faults[0]: 'stall:9@200+5': no robot 9 in a run of 9");
  expect_rejected(kHead + "faults:\n  - kill:9@200\n", 4, "faults[0]: kill of robot 9, but there are only 9");
  expect_rejected(kHead + "faults:\n  - range:all@5=3\n", 4,
                  "the cut range 3 m is not below the comm range 3 m");
  expect_rejected(kHead + "faults:\n  - restart:2@50\n", 4, "robot 2 is not killed before tick 50");
  expect_rejected(kHead + "faults:\n  - kill:2@50\n  - restart:2@50\n", 5,
                  "robot 2 is not killed before tick 50");
  expect_rejected(kHead + "faults:\n  - kill:2@10\n  - restart:2@20\n  - restart:2@30\n", 6,
                  "robot 2 is not killed before tick 30 since its restart at tick 20");
  EXPECT_EQ(parse(kHead + "faults:\n  - kill:2@10\n  - restart:2@20\n  - kill:2@25\n  - restart:2@30\n")
                .faults.size(),
            2u);
  expect_rejected(kHead + "faults:\n  - stall:1@10+10\n  - stall:1@19+2\n", 5, "overlaps 'stall:1@10+10'");
}

TEST(ScenarioFaults, BadFlagFaultsNameTheFlag) {
  ScenarioOverrides ov;
  ov.faults = {"wheel:1@5"};
  expect_rejected(kHead, 0, "command line: --fault 'wheel:1@5': which wheel", ov);
  ov.faults = {"restart:1@5"};
  expect_rejected(kHead, 0, "--fault 'restart:1@5': robot 1 is not killed before tick 5", ov);
  ov.faults = {"kill:12@5"};
  expect_rejected(kHead, 0, "--fault 'kill:12@5': kill of robot 12", ov);
  // A restart may follow a kill given with --kill.
  ov.faults = {"restart:1@5"};
  ov.kills = {Kill{1, 4}};
  EXPECT_EQ(parse(kHead, ov).faults.size(), 1u);
}

// ---- the world faults' effects
// -----------------------------------------------------------------------------

Command drive(double l, double r, std::vector<std::uint8_t> msg = {}) {
  Command c;
  c.left_speed = l;
  c.right_speed = r;
  c.message = std::move(msg);
  return c;
}

Scenario with_faults(Scenario s, std::initializer_list<const char*> texts) {
  for (const char* t : texts) s.faults.push_back(parse_fault(t));
  return s;
}

// Where a robot's left (side 0) or right wheel touches the floor.
Vec2 wheel_point(const Pose2D& p, int side) {
  const double half = kWheelSpacing / 2.0 * (side == 0 ? 1.0 : -1.0);
  return {p.x - std::sin(p.theta) * half, p.y + std::cos(p.theta) * half};
}

TEST(WorldFaults, AFailedWheelStopsThatSideOnlyWhileTheFaultLasts) {
  World w(with_faults(open_scenario({Pose2D{0, 0, 0}, Pose2D{0, 3, 0}}), {"wheel:0/left@5+20"}));
  Vec2 left_at_start{};
  for (int t = 0; t < 40; ++t) {
    if (w.tick() == 5) left_at_start = wheel_point(w.robots()[0].pose, 0);
    w.apply_command(0, drive(0.1, 0.1));
    w.apply_command(1, drive(0.1, 0.1));
    w.step();
    if (w.tick() == 25) {
      // 20 ticks on the right wheel only: robot 0 pivoted about its left wheel, which stayed put.
      const Vec2 left = wheel_point(w.robots()[0].pose, 0);
      EXPECT_NEAR(left.x, left_at_start.x, 2e-3);
      EXPECT_NEAR(left.y, left_at_start.y, 2e-3);
      EXPECT_GT(w.robots()[0].pose.theta, 1.0);          // 2 s x 0.1 m/s / 0.1054 m ~ 1.9 rad
      EXPECT_NEAR(w.robots()[1].pose.theta, 0.0, 1e-9);  // the other robot drives straight
    }
  }
  // After the fault both wheels drive again: the heading holds, the robot moves.
  const double theta = w.robots()[0].pose.theta;
  const Pose2D before = w.robots()[0].pose;
  w.apply_command(0, drive(0.1, 0.1));
  w.step();
  EXPECT_NEAR(w.robots()[0].pose.theta, theta, 1e-6);
  EXPECT_GT(std::hypot(w.robots()[0].pose.x - before.x, w.robots()[0].pose.y - before.y), 5e-3);
}

TEST(WorldFaults, AFailedWheelStaysStoppedWhenNoNewCommandComes) {
  // A robot whose last command set both wheels keeps them (no command this tick), but the failed one stops.
  World w(with_faults(open_scenario({Pose2D{0, 0, 0}}), {"wheel:0/right@3"}));
  w.apply_command(0, drive(0.1, 0.1));
  for (int t = 0; t < 3; ++t) w.step();
  const Vec2 right = wheel_point(w.robots()[0].pose, 1);
  for (int t = 0; t < 10; ++t) w.step();
  EXPECT_NEAR(wheel_point(w.robots()[0].pose, 1).x, right.x, 2e-3);
  EXPECT_NEAR(wheel_point(w.robots()[0].pose, 1).y, right.y, 2e-3);
  EXPECT_LT(w.robots()[0].pose.theta, -0.5);  // turned right, about the stopped wheel
}

TEST(WorldFaults, AFailedUltrasonicSensorReadsItsMaximumFromItsTick) {
  // Robots 0 and 1 face each other 0.5 m apart: their sensor 2 (the front) sees the other.
  World w(with_faults(open_scenario({Pose2D{0, 0, 0}, Pose2D{0.5, 0, std::numbers::pi}}),
                      {"ultrasonic:0/2@3+2"}));
  for (int t = 0; t < 6; ++t) {
    const auto& u = w.perception(0).ultrasonic;
    if (w.tick() == 3 || w.tick() == 4) {
      EXPECT_EQ(u[2], kUltrasonicMaxRange) << "tick " << w.tick();
    } else {
      EXPECT_LT(u[2], 0.5) << "tick " << w.tick();
    }
    EXPECT_LT(w.perception(1).ultrasonic[kUltrasonicCount / 2], 0.5);  // the other robot's sensors work
    w.step();
  }
}

TEST(WorldFaults, EverySensorOfARobotFailsWithoutASensorIndexAlsoAfterARevive) {
  World w(with_faults(open_scenario({Pose2D{0, 0, 0}, Pose2D{0.5, 0, 0}, Pose2D{-0.5, 0, 0}}),
                      {"ultrasonic:0@0"}));
  for (double r : w.perception(0).ultrasonic) EXPECT_EQ(r, kUltrasonicMaxRange);
  w.kill(0);
  w.step();
  w.revive(0);
  for (double r : w.perception(0).ultrasonic) EXPECT_EQ(r, kUltrasonicMaxRange);
}

// Three robots in a row 1 m apart, each saying something every tick; returns who robot `r` heard at each
// tick.
std::vector<std::vector<RobotId>> heard(World& w, RobotId r, int ticks) {
  std::vector<std::vector<RobotId>> out;
  for (int t = 0; t < ticks; ++t) {
    for (RobotId id = 0; id < w.robot_count(); ++id)
      w.apply_command(id, drive(0, 0, {static_cast<std::uint8_t>(id)}));
    w.step();
    std::vector<RobotId> senders;
    for (const auto& m : w.perception(r).messages) senders.push_back(m.sender);
    std::sort(senders.begin(), senders.end());
    out.push_back(senders);
  }
  return out;
}

TEST(WorldFaults, ALossBurstForAllDeliversNoMessageDuringTheBurst) {
  World w(with_faults(open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}, Pose2D{2, 0, 0}}), {"loss:all@4+3"}));
  const auto h = heard(w, 1, 10);  // h[k]: the perception of tick k + 1
  for (int k = 0; k < 10; ++k) {
    const Tick t = static_cast<Tick>(k + 1);
    if (t >= 4 && t < 7) {
      EXPECT_TRUE(h[k].empty()) << "tick " << t;
    } else {
      EXPECT_EQ(h[k], (std::vector<RobotId>{0, 2})) << "tick " << t;
    }
  }
}

TEST(WorldFaults, ALossBurstForOneRobotCutsOnlyItsMessagesBothWays) {
  World w(with_faults(open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}, Pose2D{2, 0, 0}}), {"loss:0@1+5"}));
  for (int k = 0; k < 3; ++k) {
    for (RobotId id = 0; id < 3; ++id) w.apply_command(id, drive(0, 0, {1}));
    w.step();
    EXPECT_TRUE(w.perception(0).messages.empty());   // it hears nobody
    ASSERT_EQ(w.perception(1).messages.size(), 1u);  // and nobody hears it
    EXPECT_EQ(w.perception(1).messages[0].sender, 2u);
    ASSERT_EQ(w.perception(2).messages.size(), 1u);
    EXPECT_EQ(w.perception(2).messages[0].sender, 1u);
  }
}

TEST(WorldFaults, ARangeCutHidesTheNeighboursBeyondItFromItsTick) {
  // Robot 0 at 0; robots at 1 m and 2.5 m (both within the 3 m comm range).
  World w(
      with_faults(open_scenario({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}, Pose2D{2.5, 0, 0}}), {"range:all@3=1.5"}));
  const auto h = heard(w, 0, 5);
  EXPECT_EQ(h[0], (std::vector<RobotId>{1, 2}));  // tick 1
  EXPECT_EQ(h[1], (std::vector<RobotId>{1, 2}));  // tick 2
  EXPECT_EQ(h[2], (std::vector<RobotId>{1}));     // tick 3: the cut
  EXPECT_EQ(h[4], (std::vector<RobotId>{1}));
}

TEST(WorldFaults, ARangeCutOfOneRobotLimitsEveryPairWithIt) {
  // Robot 2's radio is cut to 1 m: robot 0 (2 m away) no longer hears it nor is heard by it; 1 and 2 still
  // are.
  World w(
      with_faults(open_scenario({Pose2D{0, 0, 0}, Pose2D{1.5, 0, 0}, Pose2D{2, 0, 0}}), {"range:2@1=1.0"}));
  EXPECT_EQ(heard(w, 0, 2).back(), (std::vector<RobotId>{1}));
  EXPECT_EQ(heard(w, 2, 1).back(), (std::vector<RobotId>{1}));
  EXPECT_EQ(heard(w, 1, 1).back(), (std::vector<RobotId>{0, 2}));
}

TEST(WorldFaults, EdgesAndDescriptionsForTheEvents) {
  const std::vector<Fault> faults = {parse_fault("wheel:1/left@10+5"), parse_fault("stall:2@10+5"),
                                     parse_fault("range:all@10=1")};
  const auto at10 = world_fault_edges(faults, 10);
  ASSERT_EQ(at10.size(), 2u);  // the stall is a process fault
  EXPECT_TRUE(at10[0].start);
  EXPECT_EQ(describe_world_fault(*at10[0].fault, true),
            "wheel:1/left@10+5: the left wheel of robot 1 stops for 5 ticks");
  EXPECT_EQ(describe_world_fault(*at10[1].fault, true),
            "range:all@10=1: the message range of every robot is cut to 1 m");
  const auto at15 = world_fault_edges(faults, 15);
  ASSERT_EQ(at15.size(), 1u);
  EXPECT_FALSE(at15[0].start);
  EXPECT_TRUE(world_fault_edges(faults, 11).empty());
}

}  // namespace
}  // namespace swarmform::world
