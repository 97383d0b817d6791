// The stages of a tick in Motion (motion_phase.cpp's motion_velocity), each on its own: the desired motion
// (desired_motion.hpp), Algorithm 2's mask over the neighbours heard and missed and the size latch
// (obstacle_view.hpp), pinned detection (progress_window.hpp), the
// approach's trigger and echoes (approach_stage.hpp), the boundary episode's Bug rules (boundary_episode.hpp)
// the slide (obstacle_response.hpp) and an arrived follower's watch over its place (place_watch.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "robot_agent/controller/approach_stage.hpp"
#include "robot_agent/controller/boundary_episode.hpp"
#include "robot_agent/controller/desired_motion.hpp"
#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/obstacle_response.hpp"
#include "robot_agent/controller/obstacle_view.hpp"
#include "robot_agent/controller/place_watch.hpp"
#include "robot_agent/controller/progress_window.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {
namespace {

TEST(DesiredMotion, TheLeaderCruisesToItsTargetAndArrivesWithinItsStopDistance) {
  const MotionParams p;
  const Desire far = leader_desire({0, 0}, {5, 0}, 0.3, 0.0, p);
  EXPECT_EQ(far.arrival, Arrival::None);
  EXPECT_NEAR(far.velocity.x, p.cruise_speed, 1e-12);
  EXPECT_NEAR(far.velocity.y, 0.0, 1e-12);
  EXPECT_TRUE(far.place_still);
  EXPECT_FALSE(far.alone);
  EXPECT_EQ(far.place.x, 5.0);
  EXPECT_NEAR(far.m, p.m_obstacle * p.cruise_speed, 1e-12);  // eq. (7)
  EXPECT_EQ(leader_desire({4.8, 0}, {5, 0}, 0.3, 0.0, p).arrival, Arrival::WithShape);
}

TEST(DesiredMotion, TheLeaderSlowsForAStrainedShapeButNeverBelowItsSlowest) {
  const MotionParams p;
  const double keep_up = 1.5 * p.max_speed;
  const double half = vnorm(leader_desire({0, 0}, {5, 0}, 0.3, keep_up + 0.5 * p.strain_scale, p).velocity);
  EXPECT_NEAR(half, 0.5 * p.cruise_speed, 1e-12);
  const double strained = vnorm(leader_desire({0, 0}, {5, 0}, 0.3, keep_up + 10.0, p).velocity);
  EXPECT_NEAR(strained, 0.3 * p.cruise_speed, 1e-12);
  // Its obstacle gain follows its pull, down to the floor of a tenth of the cruise.
  EXPECT_NEAR(obstacle_gain(0.0, p), 0.1 * p.m_obstacle * p.cruise_speed, 1e-12);
}

TEST(DesiredMotion, ACutOffRobotMakesForItsOwnTargetAndArrivesAlone) {
  const MotionParams p;
  const Desire d = cut_off_desire({0, 0}, {0, 3}, p);
  EXPECT_TRUE(d.alone);
  EXPECT_TRUE(d.place_still);
  ASSERT_TRUE(d.to_parent.has_value());
  EXPECT_EQ(vnorm(*d.to_parent), 0.0);
  EXPECT_NEAR(d.velocity.y, p.max_speed, 1e-12);
  EXPECT_EQ(cut_off_desire({0, 2.95}, {0, 3}, p).arrival, Arrival::Alone);
}

TEST(DesiredMotion, AFollowerThatDoesNotHearItsParentUsesWhereItWasAndFollowsItsVelocity) {
  const MotionParams p;
  const NeighbourTable none;  // the parent not heard this tick
  FollowerDesire follower;
  ParentView parent;
  parent.id = 4;
  parent.reference = {1.0, 0.0};
  parent.last_position = Vec2{2.0, 1.0};
  parent.last_velocity = {0.05, 0.0};
  const Desire d = follower.step(none, {1.0, 1.0}, 100, 10.0, parent, p);
  ASSERT_TRUE(d.to_parent.has_value());
  EXPECT_NEAR(d.to_parent->x, 1.0, 1e-12);
  EXPECT_NEAR(d.to_parent->y, 0.0, 1e-12);
  // At its place (the parent one reference away): F_net vanishes and the feed-forward carries it.
  EXPECT_NEAR(d.net_force, 0.0, 1e-12);
  EXPECT_NEAR(d.velocity.x, 0.05, 1e-12);
  EXPECT_NEAR(d.place.x, 1.0, 1e-12);
  EXPECT_FALSE(d.place_still);  // its parent moves
  EXPECT_EQ(d.arrival, Arrival::None);
  // Off its place by half a metre: pulled back towards it, and lagging towards the goal (+x) when behind.
  const Desire behind = follower.step(none, {0.5, 1.0}, 100, 10.0, parent, p);
  EXPECT_GT(behind.net_force, 0.1);
  EXPECT_GT(behind.lag, 0.0);
  // A parent that crawls: its place counts as standing still.
  parent.last_velocity = {0.001, 0.0};
  EXPECT_TRUE(follower.step(none, {1.0, 1.0}, 100, 10.0, parent, p).place_still);
}

TEST(PointSum, MeanOfThePointsAdded) {
  PointSum s;
  s.add({1.0, 2.0});
  s.add({3.0, -2.0});
  EXPECT_EQ(s.count, 2);
  EXPECT_NEAR(s.mean().x, 2.0, 1e-12);
  EXPECT_NEAR(s.mean().y, 0.0, 1e-12);
}

TEST(ProgressWindow, PinnedOnlyWhenItMovedLittleOfTheWayItAskedFor) {
  ProgressWindow w;
  w.restart({0, 0}, 0);
  // Asked 0.1 m/s for a window and stood: pinned at the window's end, not before.
  for (Tick t = 1; t < ProgressWindow::kPinnedTicks; ++t) EXPECT_FALSE(w.update({0, 0}, 0.1, t, 10.0));
  EXPECT_TRUE(w.update({0, 0}, 0.1, ProgressWindow::kPinnedTicks, 10.0));
  // Moved half of what it asked for: not pinned.
  w.restart({0, 0}, 0);
  bool pinned = false;
  for (Tick t = 1; t <= ProgressWindow::kPinnedTicks; ++t)
    pinned = w.update({0.005 * static_cast<double>(t), 0}, 0.1, t, 10.0);
  EXPECT_FALSE(pinned);
  // Asked for almost nothing (its leader waits): never pinned, however still it stands.
  w.restart({0, 0}, 0);
  for (Tick t = 1; t <= ProgressWindow::kPinnedTicks; ++t) pinned = w.update({0, 0}, 0.02, t, 10.0);
  EXPECT_FALSE(pinned);
}

TEST(LargeObstacleLatch, APostSeenRightAfterAWallIsTheWall) {
  LargeObstacleLatch latch;
  ObstacleSense s;
  s.size = ObstacleSize::Large;
  latch.apply(s, 100);
  s.size = ObstacleSize::Small;
  latch.apply(s, 120);
  EXPECT_EQ(s.size, ObstacleSize::Large);  // within the latch: still the wall, and the latch runs on
  s.size = ObstacleSize::Small;
  latch.apply(s, 149);
  EXPECT_EQ(s.size, ObstacleSize::Large);
  s.size = ObstacleSize::Small;
  latch.apply(s, 149 + LargeObstacleLatch::kLargeLatchTicks);
  EXPECT_EQ(s.size, ObstacleSize::Small);
}

TEST(ApproachStage, TakesOverNearAStillPlaceOrForACutOffRobotOutsideItsSearch) {
  EXPECT_TRUE(approach_takes_over(true, true, false, false));
  EXPECT_FALSE(approach_takes_over(false, true, false, false));  // a place that moves: formation forces
  EXPECT_FALSE(approach_takes_over(true, false, false, false));  // far from a follower's still place
  EXPECT_TRUE(approach_takes_over(true, false, true, false));    // cut off: its own way
  EXPECT_FALSE(approach_takes_over(true, false, true, true));    // unless going round for that place
}

TEST(ApproachStage, OnlyEchoesNearerThanThePlaceAreGoneRound) {
  const auto e = echoes_before_place({{1.0, 0.0}, {3.0, 0.0}, {0.0, -0.5}}, {0, 0}, 2.0);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_NEAR(e[0].range, 1.0 + kRobotRadius, 1e-12);
  EXPECT_NEAR(e[0].azimuth, 0.0, 1e-12);
  EXPECT_TRUE(e[0].echo);
  EXPECT_NEAR(e[1].azimuth, -std::numbers::pi / 2, 1e-12);
}

TEST(BoundaryEpisode, PinnedAgainNoNearerItKeepsItsWayRoundNearerItChoosesAfresh) {
  const BoundaryFollowParams bf{0.47, 0.1, 1.0, 20, 1200};
  std::vector<std::string> events;
  BoundaryEpisode e;
  e.reset();
  // An obstacle straight ahead (+x), the desired motion leaning up: clockwise (-1).
  EpisodeInputs in{{0, 0}, {0.1, 0.05}, {5, 0}, true, {}, 10};
  e.start(in, {0.5, 0}, 1, bf, events);
  ASSERT_TRUE(e.active());
  EXPECT_EQ(e.side(), -1);
  EXPECT_EQ(events.back(), "boundary_follow_start -1");
  EchoMemory trace;
  in.tick = 11;
  ASSERT_TRUE(e.follow(in, Vec2{0.5, 0}, trace, 0.1, bf, events).has_value());  // the way round is remembered
  e.end();
  // Pinned again no nearer its place, the desired motion now leaning down: still clockwise.
  in.desired = {0.1, -0.05};
  in.position = {0.2, 0.0};
  in.tick = 200;
  e.start(in, {0.7, 0}, 1, bf, events);
  EXPECT_EQ(e.side(), -1);
  in.tick = 201;
  ASSERT_TRUE(e.follow(in, Vec2{0.7, 0}, trace, 0.1, bf, events).has_value());
  e.end();
  // Pinned again a metre nearer: the way round is chosen afresh (counter-clockwise for this pull).
  in.position = {1.2, 0.0};
  in.tick = 400;
  e.start(in, {1.7, 0}, 1, bf, events);
  EXPECT_EQ(e.side(), 1);
}

TEST(BoundaryEpisode, AroundAStillPlaceItLeavesOnlyNearerItThanWhereItBegan) {
  const BoundaryFollowParams bf{0.47, 0.1, 1.0, 20, 1200};
  std::vector<std::string> events;
  EchoMemory trace;
  BoundaryEpisode e;
  e.reset();
  EpisodeInputs in{{0, 0}, {0.1, 0.0}, {5, 0}, true, {}, 0};
  e.start(in, {0.5, 0}, 1, bf, events);
  // Later, the pull leads away from the echo, but the robot is no nearer its still place: it goes on round.
  in.tick = 50;
  in.desired = {-0.1, 0.0};
  EXPECT_TRUE(e.follow(in, Vec2{0.5, 0}, trace, 0.1, bf, events).has_value());
  EXPECT_TRUE(e.active());
  // The same, the place having moved with the shape: the way is clear, it leaves.
  in.place = {5, 3};
  in.place_still = false;
  EXPECT_FALSE(e.follow(in, Vec2{0.5, 0}, trace, 0.1, bf, events).has_value());
  EXPECT_FALSE(e.active());
  EXPECT_EQ(events.back(), "boundary_follow_end");
}

// One echo straight ahead of a robot at the origin heading +x.
EchoMemory wall_ahead(double reading, Tick tick) {
  EchoMemory m;
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  r[2] = reading;
  m.add(r, SensorMask{}, Pose2D{0, 0, 0}, tick, 0.6);
  return m;
}

TEST(ObstacleResponse, HeadOnItSlidesTowardsItsParentsSide) {
  const NeighbourTable none;
  ResponseInputs in;
  in.desired = {0.1, 0.0};
  in.m = 0.1;
  in.has_parent = true;
  in.tick = 5;
  for (const double side : {1.0, -1.0}) {
    SlideState state;
    EchoMemory echoes = wall_ahead(0.3, 5);
    in.to_parent = {-0.5, side};
    const Vec2 v = respond_to_obstacles(state, echoes, none, in);
    EXPECT_LT(v.x, 0.1);          // eq. (6) pushes back,
    EXPECT_GT(v.y * side, 0.04);  // and the slide goes the parent's way
    EXPECT_EQ(state.side, side > 0 ? 1 : -1);
  }
}

TEST(ObstacleResponse, TheSideIsKeptWhileTheObstacleIsRememberedAndForgottenAfter) {
  const NeighbourTable none;
  ResponseInputs in;
  in.desired = {0.1, 0.0};
  in.m = 0.1;
  in.has_parent = true;
  in.to_parent = {-0.5, 1.0};
  in.tick = 5;
  SlideState state;
  EchoMemory echoes = wall_ahead(0.3, 5);
  respond_to_obstacles(state, echoes, none, in);
  ASSERT_EQ(state.side, 1);
  in.to_parent = {-0.5, -1.0};  // the parent now on the other side: the side holds while the obstacle is near
  in.tick = 6;
  EXPECT_GT(respond_to_obstacles(state, echoes, none, in).y, 0.0);
  // Nothing remembered any more, for longer than the memory: the side is forgotten, the motion unchanged.
  in.tick = 5 + 2 * kEchoMemoryTicks + 2;
  const Vec2 clear = respond_to_obstacles(state, echoes, none, in);
  EXPECT_EQ(state.side, 0);
  EXPECT_EQ(clear.x, 0.1);
  EXPECT_EQ(clear.y, 0.0);
}

TEST(ObstacleResponse, BetweenTwoObstaclesWithTheWayClearItDoesNotSlide) {
  const NeighbourTable none;
  ResponseInputs in;
  in.desired = {0.1, 0.0};
  in.m = 0.1;
  in.has_parent = true;
  in.to_parent = {-0.5, 1.0};
  in.tick = 5;
  SlideState state;
  EchoMemory echoes;
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  r[1] = 0.35;  // -45 degrees
  r[3] = 0.35;  // +45 degrees: a gap between two posts, nothing straight ahead
  echoes.add(r, SensorMask{}, Pose2D{0, 0, 0}, 5, 0.6);
  const Vec2 v = respond_to_obstacles(state, echoes, none, in);
  EXPECT_NEAR(v.y, 0.0, 1e-9);  // no sideways slide: eq. (6) alone against the full pull
  EXPECT_EQ(state.side, 0);
}

RobotMessage moving_message(RobotId id) {
  RobotMessage m;
  m.sender = id;
  m.state = RobotState::Motion;
  return m;
}

TEST(ObstacleView, ANeighbourNotHeardThisTickStillMasksWhereItShouldStand) {
  NeighbourTable table(20);
  Perception p;
  p.tick = 10;
  p.messages.push_back({3, 1.0, 0.0, encode_message(moving_message(3))});
  p.messages.push_back({5, 1.5, 1.0, encode_message(moving_message(5))});
  table.update(p, 0);
  const std::map<RobotId, Vec2> last_position{{3, {1.0, 0.0}}, {5, vpolar(1.5, 1.0)}};
  const std::map<RobotId, Vec2> last_velocity{{3, {0.1, 0.0}}, {5, {0.0, 0.0}}};
  // Heard now: as read, exact.
  auto now = neighbours_to_mask(table, {0, 0, 0}, 10.0, 0.1, last_position, last_velocity);
  ASSERT_EQ(now.size(), 2u);
  EXPECT_EQ(now[0].range, 1.0);
  EXPECT_EQ(now[0].uncertainty, 0.0);
  // Three ticks later, neither heard (their copies lost): where they should stand, 3 ticks' worth uncertain.
  Perception silent;
  silent.tick = 13;
  table.update(silent, 0);
  const auto later = neighbours_to_mask(table, {0, 0, 0}, 10.0, 0.1, last_position, last_velocity);
  ASSERT_EQ(later.size(), 2u);
  EXPECT_NEAR(later[0].range, 1.03, 1e-12);  // moved on at its broadcast velocity
  EXPECT_NEAR(later[0].bearing, 0.0, 1e-12);
  EXPECT_NEAR(later[0].uncertainty, 0.03, 1e-12);
  EXPECT_NEAR(later[1].range, 1.5, 1e-12);
  EXPECT_NEAR(later[1].bearing, 1.0, 1e-12);
  // The robot itself turned by 0.5 rad meanwhile: the bearing is taken in its frame now.
  const auto turned = neighbours_to_mask(table, {0, 0, 0.5}, 10.0, 0.1, last_position, last_velocity);
  EXPECT_NEAR(turned[1].bearing, 0.5, 1e-12);
  // Its echo straight ahead is masked on that tick, as when it was heard.
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  r[2] = 1.03 - 2 * kRobotRadius;
  EXPECT_TRUE(mask_neighbour_directions(r, later, 0.35, 0.1)[2]);
}

TEST(ObstacleView, AnUncertainNeighbourMasksAWiderCone) {
  UltrasonicArray r;
  r.fill(kUltrasonicMaxRange);
  r[2] = 0.85;
  // Just outside the mask angle plus its half-size, as heard...
  const double off = 0.35 + std::atan2(kRobotRadius, 1.0) + 0.02;
  EXPECT_FALSE(mask_neighbour_directions(r, {{1.0, off, 0.0}}, 0.35, 0.1)[2]);
  // ...inside once its place is 3 cm uncertain.
  EXPECT_TRUE(mask_neighbour_directions(r, {{1.0, off, 0.03}}, 0.35, 0.1)[2]);
}

TEST(PlaceWatch, ThePlaceIsTheMeanOfTheRecentReadingsOfTheParentMinusTheReference) {
  PlaceWatch w;
  EXPECT_FALSE(w.place({1, 0}, 1).has_value());
  w.add(10, {5.0, 0.1}, 20);
  w.add(11, {5.0, -0.1}, 20);
  EXPECT_FALSE(w.place({1, 0}, 3).has_value());  // too few readings yet
  const auto place = w.place({1, 0}, 2);
  ASSERT_TRUE(place.has_value());
  EXPECT_NEAR(place->x, 4.0, 1e-12);
  EXPECT_NEAR(place->y, 0.0, 1e-12);
  // The parent pushed 0.5 m: once the window has passed, only where it stands now counts.
  for (Tick t = 12; t < 40; ++t) w.add(t, {5.5, 0.0}, 20);
  EXPECT_NEAR(w.place({1, 0}, 10)->x, 4.5, 1e-12);
  w.reset();
  EXPECT_FALSE(w.place({1, 0}, 1).has_value());
}

}  // namespace
}  // namespace swarmform::controller::motion
