// Realtime deaths that come together are one event of the host (world_server/mass_loss.hpp).
#include "world_server/mass_loss.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace {

using swarmform::server::MassLoss;

constexpr std::int64_t kMs = 1000000;

TEST(MassLoss, DeathsWithinOneLeaseAreOneGroupNamingEveryRobotAndTheProcessesStillThere) {
  MassLoss m;
  EXPECT_FALSE(m.died(4, 700, 10'000 * kMs, true));
  EXPECT_FALSE(m.died(1, 700, 10'030 * kMs, true));
  EXPECT_FALSE(m.died(7, 701, 10'120 * kMs, false));
  EXPECT_FALSE(m.close(10'900 * kMs)) << "within the window and a suspect's grace: more may come";
  const auto g = m.close(10'000 * kMs + MassLoss::kWindow + MassLoss::kLate + 1);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->tick, 700u);
  EXPECT_EQ(g->robots, (std::vector<swarmform::RobotId>{4, 1, 7}));
  EXPECT_EQ(g->processes_present, 2u);
  EXPECT_EQ(g->last - g->first, 120 * kMs);
  EXPECT_EQ(m.groups().size(), 1u);
  EXPECT_FALSE(m.close(20'000 * kMs)) << "a closed group is reported once";
}

TEST(MassLoss, OneDeathAloneOrDeathsFurtherApartThanALeaseAreNotAMassLoss) {
  MassLoss m;
  EXPECT_FALSE(m.died(2, 100, 1'000 * kMs, true));
  EXPECT_FALSE(m.died(3, 110, 1'000 * kMs + MassLoss::kWindow + 1, true))
      << "the first closed alone: no group";
  EXPECT_FALSE(m.close(5'000 * kMs));
  EXPECT_TRUE(m.groups().empty());
}

TEST(MassLoss, ADeathAfterTheWindowClosesTheGroupBeforeItAndStartsTheNext) {
  MassLoss m;
  m.died(0, 50, 0, true);
  m.died(1, 50, 10 * kMs, true);
  const auto first = m.died(2, 90, 900 * kMs, false);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->robots.size(), 2u);
  m.died(3, 90, 950 * kMs, false);
  const auto second = m.close(std::numeric_limits<dds_time_t>::max());  // the run's end
  ASSERT_TRUE(second);
  EXPECT_EQ(second->robots, (std::vector<swarmform::RobotId>{2, 3}));
  EXPECT_EQ(second->processes_present, 0u);
  EXPECT_EQ(m.groups().size(), 2u);
}

// Under load the world stalls, and a loss noticed right after its stall is only suspected and recorded dead a
// grace later, with the time it was noticed (stall_guard.hpp): it joins the group of the losses recorded at
// once, even though it is recorded after them, and before the group's first. Before, recording times were
// used: the agents of one SIGSTOP straddling a stall of the world's were split into a group and a lone death.
TEST(MassLoss, ALossRecordedAGraceLateJoinsTheGroupOfItsTime) {
  MassLoss m;
  EXPECT_FALSE(m.died(3, 40, 5'100 * kMs, true));
  EXPECT_FALSE(m.died(5, 40, 5'150 * kMs, true));
  EXPECT_FALSE(m.close(5'100 * kMs + MassLoss::kWindow + 1)) << "a suspect may still be recorded";
  EXPECT_FALSE(m.died(6, 46, 5'000 * kMs, true)) << "recorded late, noticed first";
  const auto g = m.close(5'000 * kMs + MassLoss::kWindow + MassLoss::kLate + 1);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->robots, (std::vector<swarmform::RobotId>{3, 5, 6}));
  EXPECT_EQ(g->first, 5'000 * kMs);
  EXPECT_EQ(g->last - g->first, 150 * kMs);
  EXPECT_EQ(g->tick, 40u);
}

}  // namespace
