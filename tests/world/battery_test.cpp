// The battery: wheel travel from a robot's true motion, idle and moving discharge against hand-computed
// charges, an empty battery stopping the wheels (the robot alive, still sensing), the reading only for a
// behaviour that declares it, and the scenario's battery fields checked.
#include "world_server/world/battery.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "robot_agent/controller/builtins.hpp"
#include "test_scenarios.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {
namespace {

TEST(Battery, WheelTravelOfStraightSpinAndArc) {
  EXPECT_NEAR(wheel_travel(Pose2D{0, 0, 0}, Pose2D{0.1, 0, 0}), 0.1, 1e-15);
  EXPECT_NEAR(wheel_travel(Pose2D{1, 1, 0.5}, Pose2D{1, 1, 0.5}), 0.0, 1e-15);
  // On the spot by 0.2 rad: each wheel travels 0.2 x half the spacing, one forward, one back.
  EXPECT_NEAR(wheel_travel(Pose2D{0, 0, 0}, Pose2D{0, 0, 0.2}), 0.2 * kWheelSpacing / 2.0, 1e-15);
  // Backwards counts as travel.
  EXPECT_NEAR(wheel_travel(Pose2D{0, 0, 0}, Pose2D{-0.05, 0, 0}), 0.05, 1e-15);
  // An arc where the inner wheel stands still: advance = half the spacing x the turn; mean travel the same.
  const double turn = 0.1;
  const double r = kWheelSpacing / 2.0;  // radius of the centre's arc
  const Pose2D end{r * std::sin(turn), r * (1.0 - std::cos(turn)), turn};
  EXPECT_NEAR(wheel_travel(Pose2D{0, 0, 0}, end), r * turn, 1e-6);  // chord vs arc: within 1e-6
}

TEST(Battery, IdleDrawEmptiesAStillRobotAtTheHandComputedTick) {
  Scenario s = testing::open_scenario({Pose2D{}});
  // 0.0625 J a tick (exact in binary: the tick it runs out is exact too).
  s.battery = BatterySpec{.capacity = 1.0, .idle = 0.625, .moving = 0.0, .start = 1.0};
  s.behaviour = controller::builtin_registry().find("phototaxis");
  ASSERT_NE(s.behaviour, nullptr);
  World w(s);
  EXPECT_EQ(w.perception(0).battery, std::optional<double>(1.0));
  for (int t = 1; t <= 15; ++t) w.step();
  ASSERT_TRUE(w.perception(0).battery.has_value());
  EXPECT_EQ(*w.perception(0).battery, 0.0625);
  EXPECT_FALSE(w.robots()[0].battery_empty_tick.has_value());
  w.step();
  EXPECT_EQ(w.perception(0).battery, std::optional<double>(0.0));
  EXPECT_EQ(w.robots()[0].battery_empty_tick, std::optional<Tick>(16));
  EXPECT_TRUE(w.alive(0));
}

TEST(Battery, MovingDrawFollowsTheDistanceAndAnEmptyBatteryStopsTheWheels) {
  Scenario s = testing::open_scenario({Pose2D{}});
  s.mission.max_speed = 0.1;
  // 10 J a metre of wheel travel, 0.2 J: empty after about 2 cm.
  s.battery = BatterySpec{.capacity = 0.2, .idle = 0.0, .moving = 10.0, .start = 1.0};
  World w(s);
  Command go;
  go.left_speed = go.right_speed = 0.1;
  double travelled = 0.0;
  for (int t = 0; t < 3; ++t) {
    const Pose2D before = w.robots()[0].pose;
    w.apply_command(0, go);
    w.step();
    travelled += wheel_travel(before, w.robots()[0].pose);
  }
  ASSERT_GT(travelled, 0.0);
  EXPECT_NEAR(w.robots()[0].battery, 1.0 - 10.0 * travelled / 0.2, 1e-12);
  // Drive on until it runs out; then the wheels stay still whatever the commands say.
  for (int t = 0; t < 100 && !w.robots()[0].battery_empty_tick; ++t) {
    w.apply_command(0, go);
    w.step();
  }
  ASSERT_TRUE(w.robots()[0].battery_empty_tick.has_value());
  EXPECT_EQ(w.robots()[0].battery, 0.0);
  for (int t = 0; t < 5; ++t) {  // let the body come to rest
    w.apply_command(0, go);
    w.step();
  }
  const Pose2D rest = w.robots()[0].pose;
  for (int t = 0; t < 20; ++t) {
    w.apply_command(0, go);
    w.step();
  }
  EXPECT_NEAR(w.robots()[0].pose.x, rest.x, 1e-6);
  EXPECT_TRUE(w.alive(0));
  // Without a battery in the scenario nothing drains.
  Scenario plain = testing::open_scenario({Pose2D{}});
  World p(plain);
  p.apply_command(0, go);
  p.step();
  EXPECT_EQ(p.robots()[0].battery, 1.0);
}

TEST(Battery, ReadingOnlyForABehaviourThatDeclaresIt) {
  Scenario s = testing::open_scenario({Pose2D{}});
  s.battery = BatterySpec{.capacity = 1.0, .idle = 0.5, .moving = 0.0, .start = 0.5};
  s.behaviour = &controller::random_walk_descriptor();
  World w(s);
  EXPECT_FALSE(w.perception(0).battery.has_value());
  EXPECT_EQ(w.robots()[0].battery, 0.5);  // the truth has it all the same
}

}  // namespace
}  // namespace swarmform::world
