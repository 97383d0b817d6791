// Bursty loss (world_server/world/burst_loss.hpp): over many draws a link loses the fraction `rate` of its
// copies in runs of `mean_burst` ticks on average; a link silent for k ticks follows the chain's k-step law;
// a link's draws depend on nothing but the seed, the tick and the link. And the medium's independent loss
// still draws exactly as before (the seeded stream, receivers by id), so old scenarios replay unchanged.
#include "world_server/world/burst_loss.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "world_server/world/medium.hpp"
#include "world_server/world/rng.hpp"

namespace swarmform::world {
namespace {

struct Measured {
  double rate = 0.0;        // lost / draws
  double mean_burst = 0.0;  // mean length of the runs of lost ticks
  long draws = 0;
  long bursts = 0;
};

// `links` directed links drawn every `every` ticks for `ticks` ticks (bursts counted in draws).
Measured measure(double rate, double mean_burst, int links, Tick ticks, Tick every, std::uint64_t seed) {
  BurstLoss loss(rate, mean_burst, seed);
  Measured m;
  long lost = 0, run_ticks = 0;
  for (int l = 0; l < links; ++l) {
    const auto sender = static_cast<RobotId>(l);
    const auto receiver = static_cast<RobotId>(l + 1);
    bool in_burst = false;
    for (Tick t = 1; t <= ticks; t += every) {
      const bool x = loss.lost(t, sender, receiver);
      ++m.draws;
      if (x) {
        ++lost;
        ++run_ticks;
        if (!in_burst) ++m.bursts;
      }
      in_burst = x;
    }
  }
  m.rate = static_cast<double>(lost) / static_cast<double>(m.draws);
  m.mean_burst = static_cast<double>(run_ticks) / static_cast<double>(m.bursts);
  return m;
}

// 400 links x 2,500 ticks = 10^6 draws per case. The standard error of the rate is ~0.002 (losses within a
// link are correlated: ~sqrt(pi (1 - pi) (1 + l) / (1 - l) / draws)), that of the mean burst ~0.5 % (about
// 10^6 pi / B bursts, each geometric): the tolerances are 5 standard errors or more.
TEST(BurstLoss, MeasuredRateAndMeanBurstMatchTheParameters) {
  struct Case {
    double rate, mean_burst;
  };
  for (const Case c : {Case{0.2, 5.0}, Case{0.1, 10.0}, Case{0.3, 3.0}, Case{0.5, 2.5}}) {
    const Measured m = measure(c.rate, c.mean_burst, 400, 2500, 1, 7);
    std::cout << "rate " << c.rate << " mean_burst " << c.mean_burst << ": measured rate " << m.rate
              << ", mean burst " << m.mean_burst << " over " << m.bursts << " bursts\n";
    EXPECT_NEAR(m.rate, c.rate, 0.01) << "rate " << c.rate << " mean_burst " << c.mean_burst;
    EXPECT_NEAR(m.mean_burst, c.mean_burst, 0.04 * c.mean_burst)
        << "rate " << c.rate << " mean_burst " << c.mean_burst << " over " << m.bursts << " bursts";
  }
}

// At mean_burst = 1 / (1 - rate) the chain forgets its state every tick: a loss is as likely after a loss as
// after a delivery (independent loss, in law). At 5 ticks a loss follows a loss with probability 1 - 1/5.
TEST(BurstLoss, ALossFollowsALossWithTheChainsProbability) {
  auto after_loss = [](double rate, double mean_burst) {
    BurstLoss loss(rate, mean_burst, 3);
    long lost_lost = 0, lost_prev = 0;
    for (RobotId l = 0; l < 200; ++l) {
      bool prev = false;
      for (Tick t = 1; t <= 2000; ++t) {
        const bool x = loss.lost(t, l, 1000 + l);
        if (prev) {
          ++lost_prev;
          lost_lost += x ? 1 : 0;
        }
        prev = x;
      }
    }
    return static_cast<double>(lost_lost) / static_cast<double>(lost_prev);
  };
  EXPECT_NEAR(after_loss(0.2, BurstLoss::min_mean_burst(0.2)), 0.2, 0.01);
  EXPECT_NEAR(after_loss(0.2, 5.0), 0.8, 0.01);
}

// A link drawn only every third tick (the sender spoke, or was in range, one tick in three) still has the
// long-run rate, and a loss follows a loss three ticks earlier with the chain's 3-step probability
// pi + (1 - pi) l^3, l = 1 - 1 / (B (1 - pi)): the state kept running while nobody looked.
TEST(BurstLoss, ALinkNotDrawnForSomeTicksFollowsTheChainsLawOverTheGap) {
  const double rate = 0.2, burst = 5.0;
  const Measured m = measure(rate, burst, 400, 7500, 3, 11);
  EXPECT_NEAR(m.rate, rate, 0.01);
  const double l = 1.0 - 1.0 / (burst * (1.0 - rate));
  const double stay = rate + (1.0 - rate) * std::pow(l, 3);  // 0.5375: P(lost at t+3 | lost at t)
  // Measured in draws, a run's length is geometric with mean 1 / (1 - stay).
  EXPECT_NEAR(m.mean_burst, 1.0 / (1.0 - stay), 0.05 / (1.0 - stay));
  EXPECT_LT(m.mean_burst, burst / 2.0);  // had the state frozen between draws, the runs would be B draws long
}

// One link's draws are the same whatever other links are drawn and in whatever order; another seed changes
// them.
TEST(BurstLoss, ALinksLossesDependOnlyOnTheSeedTheTickAndTheLink) {
  BurstLoss alone(0.3, 4.0, 21);
  BurstLoss crowded(0.3, 4.0, 21);
  BurstLoss other_seed(0.3, 4.0, 22);
  int differs = 0;
  for (Tick t = 1; t <= 3000; ++t) {
    // The crowd: other links first on odd ticks, last on even ones; the link of interest (5 -> 9) among them.
    const bool odd = t % 2 == 1;
    if (odd) {
      for (RobotId s = 0; s < 20; ++s) {
        if (s != 5 && s != 9) crowded.lost(t, s, 9);
      }
    }
    const bool x = crowded.lost(t, 5, 9);
    if (!odd) {
      for (RobotId r = 20; r > 0; --r) crowded.lost(t, 9, r);
    }
    EXPECT_EQ(alone.lost(t, 5, 9), x) << "tick " << t;
    differs += other_seed.lost(t, 5, 9) != x ? 1 : 0;
  }
  EXPECT_GT(differs, 300);
}

// Two robots in range, each speaking every tick, through the medium: the losses of each direction come in
// runs of the mean burst, and the two directions fade independently.
TEST(BurstLoss, TheMediumLosesInBurstsPerDirectedLink) {
  std::vector<Pose2D> poses{Pose2D{0, 0, 0}, Pose2D{1, 0, 0}};
  std::vector<char> alive(2, 1);
  std::vector<Outbox> out(2);
  for (Outbox& o : out) {
    o.has_message = true;
    o.data = {1};
  }
  std::vector<Perception> perceptions(2);
  SpatialGrid grid;
  grid.build(poses, 1.0);
  MediumParams p;
  p.packet_loss = 0.2;
  p.loss_mean_burst = 5.0;
  Medium m(p, {}, 5);
  long lost[2] = {0, 0}, bursts[2] = {0, 0}, both = 0;
  bool prev[2] = {false, false};
  const long ticks = 100000;
  for (long t = 0; t < ticks; ++t) {
    m.deliver(poses, alive, out, grid, perceptions);
    for (int r = 0; r < 2; ++r) {
      const bool x = perceptions[r].messages.empty();
      lost[r] += x ? 1 : 0;
      bursts[r] += x && !prev[r] ? 1 : 0;
      prev[r] = x;
    }
    both += prev[0] && prev[1] ? 1 : 0;
  }
  for (int r = 0; r < 2; ++r) {
    EXPECT_NEAR(static_cast<double>(lost[r]) / ticks, 0.2, 0.015) << "receiver " << r;
    EXPECT_NEAR(static_cast<double>(lost[r]) / static_cast<double>(bursts[r]), 5.0, 0.35) << "receiver " << r;
  }
  EXPECT_NEAR(static_cast<double>(both) / ticks, 0.04, 0.01);  // 0.2 x 0.2: independent directions
}

// packet_loss alone keeps today's model draw for draw: one Bernoulli per copy from the medium's seeded
// stream, receivers by id, senders in the grid's order.
TEST(BurstLoss, IndependentLossStillDrawsFromTheMediumsStream) {
  std::vector<Pose2D> poses{Pose2D{0, 0, 0}, Pose2D{1, 0, 0}, Pose2D{0, 1, 0}};
  std::vector<char> alive(3, 1);
  std::vector<Outbox> out(3);
  for (Outbox& o : out) {
    o.has_message = true;
    o.data = {1};
  }
  std::vector<Perception> perceptions(3);
  SpatialGrid grid;
  grid.build(poses, 1.0);
  MediumParams p;
  p.packet_loss = 0.4;
  Medium m(p, {}, 17);
  Rng reference(17, kSaltMedium);
  for (int t = 0; t < 500; ++t) {
    m.deliver(poses, alive, out, grid, perceptions);
    // The grid's order of the other robots, from a lossless medium (same positions).
    std::vector<Perception> clean(3);
    Medium(MediumParams{}, {}, 1).deliver(poses, alive, out, grid, clean);
    for (std::size_t r = 0; r < 3; ++r) {
      std::vector<RobotId> expected;
      for (const RabReading& c : clean[r].messages) {
        if (!reference.bernoulli(0.4)) expected.push_back(c.sender);
      }
      std::vector<RobotId> got;
      for (const RabReading& g : perceptions[r].messages) got.push_back(g.sender);
      ASSERT_EQ(got, expected) << "tick " << t << " receiver " << r;
    }
  }
}

}  // namespace
}  // namespace swarmform::world
