// InputGuard (docs/faults.md): budgets per writer, reports throttled to one a second per writer and kind,
// and what it holds for writers bounded. ReceiveBudget: the budget on the receive thread, before decoding.
#include <gtest/gtest.h>

#include <vector>

#include "common/dds/receive_budget.hpp"
#include "world_server/input_guard.hpp"

namespace {

using swarmform::server::Abuse;
using swarmform::server::GuardLimits;
using swarmform::server::InputGuard;

constexpr std::int64_t kS = InputGuard::kSecond;
constexpr std::int64_t kT0 = 1000 * kS;

TEST(InputGuard, EachWriterHasItsOwnCommandBudgetAWindow) {
  InputGuard g(GuardLimits{3, 2});
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(g.admit_command(7, 10, kT0));
  EXPECT_FALSE(g.admit_command(7, 10, kT0));  // the flooder is over its budget for tick 10...
  EXPECT_TRUE(g.admit_command(8, 10, kT0));   // ...which costs the owner (another writer) nothing
  EXPECT_TRUE(g.admit_command(7, 11, kT0));   // a new window, a new budget
  EXPECT_TRUE(g.admit_claim(7, kT0));
  EXPECT_TRUE(g.admit_claim(7, kT0 + 1));
  EXPECT_FALSE(g.admit_claim(7, kT0 + 2));
  EXPECT_TRUE(g.admit_claim(7, kT0 + kS));
}

TEST(InputGuard, ReportsAreLoggedOnceASecondWithTheirCount) {
  InputGuard g(GuardLimits{});
  EXPECT_EQ(g.report(5, Abuse::SpoofedCommand, kT0), 1u);  // the first is logged at once
  for (int i = 1; i < 1000; ++i) EXPECT_FALSE(g.report(5, Abuse::SpoofedCommand, kT0 + i * 1000));
  EXPECT_EQ(g.report(5, Abuse::RefusedClaim, kT0 + 5), 1u);        // another kind has its own throttle
  EXPECT_EQ(g.report(6, Abuse::SpoofedCommand, kT0 + 6), 1u);      // and another writer
  EXPECT_EQ(g.report(5, Abuse::SpoofedCommand, kT0 + kS), 1000u);  // the 999 unlogged plus this one
  EXPECT_EQ(g.total(Abuse::SpoofedCommand), 1002u);                // writer 5: 1001, writer 6: 1
  EXPECT_EQ(g.total(Abuse::RefusedClaim), 1u);
  // Sub-kinds (a command's verdicts) each get their first report logged.
  EXPECT_EQ(g.report(5, Abuse::BadCommand, kT0, 2), 1u);
  EXPECT_EQ(g.report(5, Abuse::BadCommand, kT0, 3), 1u);
  EXPECT_FALSE(g.report(5, Abuse::BadCommand, kT0 + 1, 2));
  EXPECT_EQ(g.total(Abuse::BadCommand), 3u);
}

TEST(InputGuard, WritersNotSeenForAWhileAreForgotten) {
  InputGuard g(GuardLimits{});
  for (std::uint64_t w = 1; w <= 1000; ++w) g.admit_claim(w, kT0);
  EXPECT_EQ(g.writers_tracked(), 1000u);
  g.forget(1);
  EXPECT_EQ(g.writers_tracked(), 999u);
  g.admit_claim(5000, kT0 + InputGuard::kForgetAfter + 2 * kS);
  EXPECT_EQ(g.writers_tracked(), 1u);
}

}  // namespace

namespace {

using swarmform::dds::ReceiveBudget;

TEST(InputGuard, TheReceiveBudgetNeverDropsWhatTheGuardAdmits) {
  // Whatever a window holds for the guard (commands and claims, both budgets spent) plus the liveliness
  // assertions of an idle agent fits in the receive thread's budget, in both modes.
  for (const GuardLimits l : {GuardLimits{}, swarmform::server::realtime_limits(10.0),
                              swarmform::server::realtime_limits(1000.0)}) {
    EXPECT_GE(swarmform::server::receive_budget(l),
              l.commands_per_window + l.claims_per_second + swarmform::server::kAliveSamplesPerSecond);
  }
}

TEST(InputGuard, TheReceiveBudgetIsEachWritersOwnAndRenewedEachSecondAndWindow) {
  ReceiveBudget b(/*per_window=*/3, /*accept_ids=*/10);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(b.admit(7, 100, kT0));
  EXPECT_FALSE(b.admit(7, 100, kT0));  // the flooder is over its budget...
  EXPECT_FALSE(b.admit(7, 101, kT0));
  EXPECT_TRUE(b.admit(8, 100, kT0));       // ...which costs another writer nothing
  EXPECT_TRUE(b.admit(7, 100, kT0 + kS));  // a new second
  EXPECT_TRUE(b.admit(7, 100, kT0 + kS));
  EXPECT_TRUE(b.admit(7, 100, kT0 + kS));
  EXPECT_FALSE(b.admit(7, 100, kT0 + kS));
  b.set_window(1);  // lockstep: a new tick
  EXPECT_TRUE(b.admit(7, 100, kT0 + kS));
  EXPECT_EQ(b.over_budget(), 3u);
  std::vector<ReceiveBudget::Drops> drops;
  b.take_drops(drops);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_EQ(drops[0].writer, 7u);
  EXPECT_EQ(drops[0].count, 3u);
  drops.clear();
  b.take_drops(drops);
  EXPECT_TRUE(drops.empty());  // reported once
}

TEST(InputGuard, AWriterThatSentAnIdOutsideTheRunKeepsOnlyInstancesKnownInside) {
  ReceiveBudget b(/*per_window=*/0, /*accept_ids=*/4);
  EXPECT_TRUE(b.taken(5, 100, 2));  // instance 100 is id 2's
  EXPECT_TRUE(b.admit(7, 555, kT0));
  EXPECT_FALSE(b.taken(7, 555, 1000));  // writer 7 sent an id outside the run: dropped, and banned
  EXPECT_FALSE(b.admit(7, 556, kT0));   // its made-up instances never reach the reader again
  EXPECT_FALSE(b.admit(7, 557, kT0));
  EXPECT_TRUE(b.admit(7, 100, kT0));  // an id inside the run still does (the world judges it)
  EXPECT_TRUE(b.admit(8, 556, kT0));  // another writer is not banned
  EXPECT_EQ(b.out_of_range(), 3u);
  ReceiveBudget open(/*per_window=*/0, /*accept_ids=*/0);  // no id check asked
  EXPECT_TRUE(open.taken(7, 555, 1000));
  EXPECT_TRUE(open.admit(7, 556, kT0));
}

TEST(InputGuard, TheReceiveBudgetForgetsWritersNotSeenForAWhile) {
  ReceiveBudget b(/*per_window=*/1, /*accept_ids=*/4);
  for (std::uint64_t w = 1; w <= 100; ++w) EXPECT_TRUE(b.admit(w, 1, kT0));
  EXPECT_EQ(b.writers_tracked(), 100u);
  EXPECT_TRUE(b.admit(1000, 1, kT0 + ReceiveBudget::kForgetAfter + 2 * kS));
  EXPECT_EQ(b.writers_tracked(), 1u);
}

}  // namespace
