// The medium: who hears whom (range, occlusion, loss, dead robots, not the sender) and what they perceive
// (range and bearing in the receiver's frame, with noise).
#include "world_server/world/medium.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_scenarios.hpp"

namespace swarmform::world {
namespace {

using testing::box;

struct Swarm {
  std::vector<Pose2D> poses;
  std::vector<char> alive;
  std::vector<Outbox> out;
  std::vector<Perception> perceptions;
  SpatialGrid grid;

  explicit Swarm(std::vector<Pose2D> p) : poses(std::move(p)) {
    alive.assign(poses.size(), 1);
    out.resize(poses.size());
    perceptions.resize(poses.size());
    grid.build(poses, 1.0);
  }
  void say(std::size_t i, std::vector<std::uint8_t> data) {
    out[i].has_message = true;
    out[i].data = std::move(data);
  }
};

TEST(Medium, DeliversWithinRangeAndNotBeyond) {
  Swarm s(
      {Pose2D{0, 0, 0}, Pose2D{2.9, 0, 0}, Pose2D{0, -2.99, 0}, Pose2D{3.01, 0, 0}, Pose2D{-2.2, 2.2, 0}});
  s.say(0, {42});
  Medium m(MediumParams{}, {}, 1);  // 3 m range
  m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
  EXPECT_TRUE(s.perceptions[0].messages.empty());  // never to the sender itself
  ASSERT_EQ(s.perceptions[1].messages.size(), 1u);
  EXPECT_EQ(s.perceptions[1].messages[0].sender, 0u);
  EXPECT_EQ(s.perceptions[1].messages[0].data, std::vector<std::uint8_t>{42});
  EXPECT_NEAR(s.perceptions[1].messages[0].range, 2.9, 1e-12);
  EXPECT_EQ(s.perceptions[2].messages.size(), 1u);
  EXPECT_TRUE(s.perceptions[3].messages.empty());  // 3.01 m
  EXPECT_TRUE(s.perceptions[4].messages.empty());  // 3.11 m
}

TEST(Medium, BearingInAllFourQuadrantsOfARotatedReceiver) {
  const double heading = 0.9;  // the receiver is turned; bearings are in its frame
  for (double rel_deg : {30.0, 120.0, -150.0, -60.0, 0.0, 180.0}) {
    const double rel = rel_deg * std::numbers::pi / 180.0;
    const double a = heading + rel;
    Swarm s({Pose2D{1.0, 1.0, heading}, Pose2D{1.0 + 1.5 * std::cos(a), 1.0 + 1.5 * std::sin(a), -2.0}});
    s.say(1, {1});
    Medium m(MediumParams{}, {}, 1);
    m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
    ASSERT_EQ(s.perceptions[0].messages.size(), 1u);
    const double b = s.perceptions[0].messages[0].bearing;
    EXPECT_NEAR(wrap_angle(b - rel), 0.0, 1e-9) << rel_deg;
    EXPECT_GT(b, -std::numbers::pi);
    EXPECT_LE(b, std::numbers::pi);
    EXPECT_NEAR(s.perceptions[0].messages[0].range, 1.5, 1e-9);
  }
  // Quadrant signs spelled out: a sender ahead-left has a bearing in (0, pi/2); behind-right in (-pi, -pi/2).
  const RangeBearing ahead_left = to_receiver_frame(Pose2D{1, 1, 0}, Pose2D{0, 0, 0});
  EXPECT_NEAR(ahead_left.bearing, std::numbers::pi / 4.0, 1e-12);
  const RangeBearing behind_right = to_receiver_frame(Pose2D{-1, -1, 0}, Pose2D{0, 0, 0});
  EXPECT_NEAR(behind_right.bearing, -3.0 * std::numbers::pi / 4.0, 1e-12);
  const RangeBearing turned = to_receiver_frame(Pose2D{0, 1, 0}, Pose2D{0, 0, std::numbers::pi / 2.0});
  EXPECT_NEAR(turned.bearing, 0.0, 1e-12);  // straight ahead of a receiver facing +y
}

TEST(Medium, DeadRobotsNeitherSendNorHear) {
  Swarm s({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}, Pose2D{2, 0, 0}});
  s.say(0, {1});
  s.say(1, {2});
  s.alive[1] = 0;
  Medium m(MediumParams{}, {}, 1);
  m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
  EXPECT_TRUE(s.perceptions[1].messages.empty());
  ASSERT_EQ(s.perceptions[2].messages.size(), 1u);
  EXPECT_EQ(s.perceptions[2].messages[0].sender, 0u);
}

TEST(Medium, OcclusionBlocksWhenOnAndNotWhenOff) {
  const std::vector<Obstacle> wall{box(1.0, 0.0, 0.2, 1.0)};
  for (bool occlusion : {true, false}) {
    Swarm s({Pose2D{0, 0, 0}, Pose2D{2, 0, 0}, Pose2D{0, 2, 0}});
    s.say(0, {7});
    MediumParams p;
    p.occlusion = occlusion;
    Medium m(p, wall, 1);
    m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
    EXPECT_EQ(s.perceptions[1].messages.size(), occlusion ? 0u : 1u) << "behind the wall";
    EXPECT_EQ(s.perceptions[2].messages.size(), 1u) << "clear line of sight";
  }
}

TEST(Medium, LossRateWithinTolerance) {
  std::vector<Pose2D> poses{Pose2D{0, 0, 0}};
  for (int i = 0; i < 100; ++i) poses.push_back(Pose2D{0.2 * (i % 10) - 1.0, 0.2 * (i / 10) - 1.0, 0});
  Swarm s(poses);
  s.say(0, {1});
  MediumParams p;
  p.packet_loss = 0.3;
  Medium m(p, {}, 5);
  int delivered = 0, copies = 0;
  for (int round = 0; round < 100; ++round) {
    m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
    for (std::size_t r = 1; r < s.perceptions.size(); ++r)
      delivered += static_cast<int>(s.perceptions[r].messages.size());
    copies += 100;
  }
  const double loss = 1.0 - static_cast<double>(delivered) / copies;
  EXPECT_NEAR(loss, 0.3, 0.03);
}

TEST(Medium, NoiseHasTheRightStandardDeviation) {
  Swarm s({Pose2D{0, 0, 0.4}, Pose2D{1.5, 0.5, 0}});
  s.say(1, {1});
  MediumParams p;
  p.range_noise_sd = 0.1;
  p.bearing_noise_sd = 0.05;
  Medium m(p, {}, 9);
  const RangeBearing truth = to_receiver_frame(s.poses[1], s.poses[0]);
  double sr = 0, sr2 = 0, sb = 0, sb2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
    const double er = s.perceptions[0].messages.at(0).range - truth.range;
    const double eb = wrap_angle(s.perceptions[0].messages.at(0).bearing - truth.bearing);
    sr += er;
    sr2 += er * er;
    sb += eb;
    sb2 += eb * eb;
  }
  EXPECT_NEAR(sr / n, 0.0, 0.003);
  EXPECT_NEAR(std::sqrt(sr2 / n - (sr / n) * (sr / n)), 0.1, 0.01);
  EXPECT_NEAR(sb / n, 0.0, 0.002);
  EXPECT_NEAR(std::sqrt(sb2 / n - (sb / n) * (sb / n)), 0.05, 0.005);
}

TEST(Medium, RobotsFarApartStillFoundByTheCoarsenedGrid) {
  // Two clusters 5 km apart: the grid coarsens rather than allocating millions of cells, and stays exact.
  Swarm s({Pose2D{0, 0, 0}, Pose2D{1, 0, 0}, Pose2D{5000, 0, 0}, Pose2D{5002, 1, 0}, Pose2D{5004, 2, 0}});
  for (std::size_t i = 0; i < 5; ++i) s.say(i, {1});
  Medium m(MediumParams{}, {}, 1);
  m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
  EXPECT_EQ(s.perceptions[0].messages.size(), 1u);
  EXPECT_EQ(s.perceptions[2].messages.size(), 1u);
  EXPECT_EQ(s.perceptions[3].messages.size(), 2u);
  EXPECT_EQ(s.perceptions[4].messages.size(), 1u);
}

TEST(Medium, LargeSwarmMatchesBruteForce) {
  // The grid finds exactly the robots a brute-force range test finds.
  std::vector<Pose2D> poses;
  Rng rng(3, 99);
  for (int i = 0; i < 400; ++i)
    poses.push_back(Pose2D{rng.uniform(-15, 15), rng.uniform(-15, 15), rng.uniform(-3, 3)});
  Swarm s(poses);
  for (std::size_t i = 0; i < poses.size(); ++i) s.say(i, {static_cast<std::uint8_t>(i % 256)});
  Medium m(MediumParams{}, {}, 1);
  m.deliver(s.poses, s.alive, s.out, s.grid, s.perceptions);
  for (std::size_t r = 0; r < poses.size(); ++r) {
    std::size_t expected = 0;
    for (std::size_t q = 0; q < poses.size(); ++q) {
      if (q != r && std::hypot(poses[q].x - poses[r].x, poses[q].y - poses[r].y) <= 3.0) ++expected;
    }
    EXPECT_EQ(s.perceptions[r].messages.size(), expected) << r;
  }
}

}  // namespace
}  // namespace swarmform::world
